#include "lighting/TexelCharts.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>

#include <glm/geometric.hpp>

#include "lighting/ao/AoTexels.h"
#include "lights/EdgeNeighbours.h"
#include "NearestOnTriangle.h"
#include "ShelfAtlas.h"
#include "base/Error.h"
#include "base/UnionFind.h"

namespace sightline {

namespace {

glm::dvec3 corner(const AoOccluders& occluders, std::size_t t, int c)
{
    return glm::dvec3(occluders.vertices[occluders.indices[3 * t + std::size_t(c)]]);
}



/// Triangles grouped into charts (by their smallest triangle index, in order); -1 for degenerate.
std::vector<std::int32_t> groupCharts(const AoOccluders& occluders, std::vector<glm::dvec3>& normals, std::int32_t& count)
{
    const std::size_t nt = occluders.triangleCount();
    WorldTriangles flat;
    flat.vertices.reserve(3 * nt);
    for (std::size_t t = 0; t < nt; ++t)
        for (int c = 0; c < 3; ++c)
            flat.vertices.push_back(occluders.vertices[occluders.indices[3 * t + std::size_t(c)]]);
    flat.instanceOf.assign(nt, 0);
    const auto neighbours = lights::edgeNeighbours(flat);
    normals.assign(nt, glm::dvec3(0.0));
    std::vector<char> valid(nt, 0);
    for (std::size_t t = 0; t < nt; ++t) {
        const glm::dvec3 a = corner(occluders, t, 0), n = glm::cross(corner(occluders, t, 1) - a, corner(occluders, t, 2) - a);
        const double length = glm::length(n), edge = glm::length(corner(occluders, t, 1) - a);
        if (length > 1e-12 * edge * edge && std::isfinite(length)) {
            normals[t] = n / length;
            valid[t] = 1;
        }
    }
    UnionFind sets(nt);
    for (std::size_t t = 0; t < nt; ++t) {
        if (!valid[t])
            continue;
        for (int e = 0; e < 3; ++e) {
            const std::int64_t u = neighbours[t][std::size_t(e)];
            if (u < 0 || !valid[std::size_t(u)] || glm::dot(normals[t], normals[std::size_t(u)]) < kChartCosine)
                continue;
            double off = 0.0;
            for (int c = 0; c < 3; ++c)
                off = std::max(off, std::abs(glm::dot(normals[t], corner(occluders, std::size_t(u), c) - corner(occluders, t, 0))));
            if (off <= kChartPlaneMetres)
                sets.join(std::uint32_t(t), std::uint32_t(u));
        }
    }
    std::vector<std::int32_t> chartOf(nt, -1), chartOfRoot(nt, -1);
    count = 0;
    for (std::size_t t = 0; t < nt; ++t) {
        if (!valid[t])
            continue;
        const std::uint32_t root = sets.find(std::uint32_t(t));
        if (chartOfRoot[root] < 0)
            chartOfRoot[root] = count++;
        chartOf[t] = chartOfRoot[root];
    }
    return chartOf;
}

/// The chart's rectangle at `density` (texels, with a one-texel border), in double.
std::pair<double, double> chartSize(const glm::dvec2& extent, double density)
{
    return {std::ceil(extent.x * density) + 2.0, std::ceil(extent.y * density) + 2.0};
}

/// The chart's plane frame and its rectangle (texels, with a one-texel border); returns the
/// extent it covers in its frame (metres), whatever the density.
glm::dvec2 frameChart(const AoOccluders& occluders, const std::vector<glm::dvec3>& normals, double density, TexelChart& chart)
{
    std::uint32_t largest = chart.triangles.front();
    double largestArea = -1.0;
    for (const std::uint32_t t : chart.triangles) {
        const double area = glm::length(glm::cross(corner(occluders, t, 1) - corner(occluders, t, 0), corner(occluders, t, 2) - corner(occluders, t, 0)));
        if (area > largestArea)
            largestArea = area, largest = t;
    }
    chart.normal = normals[largest];
    const glm::dvec3 base = corner(occluders, largest, 0);
    // u along whichever edge of the largest triangle gives the chart the smallest rectangle (a
    // floor's grid follows its quads, not their diagonals).
    double lo[2] = {0.0, 0.0}, hi[2] = {0.0, 0.0}, bestArea = INFINITY;
    for (int e = 0; e < 3; ++e) {
        const glm::dvec3 edge = corner(occluders, largest, (e + 1) % 3) - corner(occluders, largest, e);
        const glm::dvec3 u = glm::normalize(edge - chart.normal * glm::dot(chart.normal, edge)), v = glm::cross(chart.normal, u);
        double l[2] = {INFINITY, INFINITY}, h[2] = {-INFINITY, -INFINITY};
        for (const std::uint32_t t : chart.triangles)
            for (int c = 0; c < 3; ++c) {
                const glm::dvec3 d = corner(occluders, t, c) - base;
                const double s = glm::dot(d, u), q = glm::dot(d, v);
                l[0] = std::min(l[0], s), h[0] = std::max(h[0], s), l[1] = std::min(l[1], q), h[1] = std::max(h[1], q);
            }
        const double area = (h[0] - l[0]) * (h[1] - l[1]);
        if (area < bestArea) {
            bestArea = area;
            chart.axisU = u, chart.axisV = v;
            lo[0] = l[0], lo[1] = l[1], hi[0] = h[0], hi[1] = h[1];
        }
    }
    chart.origin = base + (lo[0] - 1.0 / density) * chart.axisU + (lo[1] - 1.0 / density) * chart.axisV;
    // In double first: a kilometre chart at a high density must be refused, not wrap an int.
    const glm::dvec2 extent(hi[0] - lo[0], hi[1] - lo[1]);
    const auto [width, height] = chartSize(extent, density);
    const bool fits = width <= double(1 << 30) && height <= double(1 << 30) && width * height <= double(std::uint64_t(1) << 40);
    chart.width = fits ? int(width) : -1;
    chart.height = fits ? int(height) : -1;
    return extent;
}

/// The chart's texel points: on a triangle where the centre falls in one, the nearest point of a
/// neighbouring texel's triangle next to one, NoFace elsewhere.
void chartPoints(const AoOccluders& occluders, double density, const TexelChart& chart, const std::vector<glm::dvec3>& normals,
                 AoPoints& points)
{
    const int w = chart.width, h = chart.height;
    std::vector<std::int64_t> owner(std::size_t(w) * std::size_t(h), -1);
    std::vector<glm::dvec3> position(owner.size());
    const auto centre = [&](int s, int q) {
        return chart.origin + ((s + 0.5) / density) * chart.axisU + ((q + 0.5) / density) * chart.axisV;
    };
    for (const std::uint32_t t : chart.triangles) {
        glm::dvec2 p[3];
        for (int c = 0; c < 3; ++c) {
            const glm::dvec3 d = corner(occluders, t, c) - chart.origin;
            p[c] = {glm::dot(d, chart.axisU) * density, glm::dot(d, chart.axisV) * density};
        }
        const double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
        if (area == 0.0)
            continue;
        const int s0 = std::max(0, int(std::floor(std::min({p[0].x, p[1].x, p[2].x}) - 0.5)));
        const int s1 = std::min(w - 1, int(std::ceil(std::max({p[0].x, p[1].x, p[2].x}) - 0.5)));
        const int q0 = std::max(0, int(std::floor(std::min({p[0].y, p[1].y, p[2].y}) - 0.5)));
        const int q1 = std::min(h - 1, int(std::ceil(std::max({p[0].y, p[1].y, p[2].y}) - 0.5)));
        bool claimed = false;
        for (int q = q0; q <= q1; ++q)
            for (int s = s0; s <= s1; ++s) {
                const glm::dvec2 c(s + 0.5, q + 0.5);
                const double l1 = ((p[2].x - c.x) * (p[0].y - c.y) - (p[0].x - c.x) * (p[2].y - c.y)) / area;
                const double l2 = ((p[0].x - c.x) * (p[1].y - c.y) - (p[1].x - c.x) * (p[0].y - c.y)) / area;
                const double l0 = 1.0 - l1 - l2;
                if (l0 < 0.0 || l1 < 0.0 || l2 < 0.0)
                    continue;
                const std::size_t k = std::size_t(q) * std::size_t(w) + std::size_t(s);
                owner[k] = t;
                position[k] = l0 * corner(occluders, t, 0) + l1 * corner(occluders, t, 1) + l2 * corner(occluders, t, 2);
                claimed = true;
            }
        if (!claimed) {
            // Smaller than a texel (a leaf): the texel under its centroid samples it, unless a
            // larger triangle of the chart holds that texel already.
            const glm::dvec2 centroid = (p[0] + p[1] + p[2]) / 3.0;
            const int s = std::clamp(int(std::floor(centroid.x)), 0, w - 1), q = std::clamp(int(std::floor(centroid.y)), 0, h - 1);
            const std::size_t k = std::size_t(q) * std::size_t(w) + std::size_t(s);
            if (owner[k] < 0) {
                owner[k] = t;
                position[k] = nearestOnTriangle(centre(s, q), corner(occluders, t, 0), corner(occluders, t, 1), corner(occluders, t, 2));
            }
        }
    }
    for (int q = 0; q < h; ++q)
        for (int s = 0; s < w; ++s) {
            const std::size_t k = std::size_t(q) * std::size_t(w) + std::size_t(s);
            std::int64_t t = owner[k];
            glm::dvec3 at = position[k];
            if (t < 0) {   // the nearest point of a neighbouring texel's triangle, if any
                double best = INFINITY;
                for (int dq = -1; dq <= 1; ++dq)
                    for (int ds = -1; ds <= 1; ++ds) {
                        const int nq = q + dq, ns = s + ds;
                        if (nq < 0 || ns < 0 || nq >= h || ns >= w)
                            continue;
                        const std::int64_t u = owner[std::size_t(nq) * std::size_t(w) + std::size_t(ns)];
                        if (u < 0)
                            continue;
                        const glm::dvec3 c = centre(s, q);
                        const glm::dvec3 p = nearestOnTriangle(c, corner(occluders, std::size_t(u), 0), corner(occluders, std::size_t(u), 1),
                                                               corner(occluders, std::size_t(u), 2));
                        const double d = glm::length(p - c);
                        if (d < best)
                            best = d, at = p, t = u;
                    }
            }
            if (t >= 0) {
                points.positions.push_back(glm::vec3(at));
                points.normals.push_back(glm::vec3(normals[std::size_t(t)]));
                points.status.push_back(AoPointStatus::Ok);
            } else {
                points.positions.push_back(glm::vec3(centre(s, q)));
                points.normals.push_back(glm::vec3(0.0f));
                points.status.push_back(AoPointStatus::NoFace);
            }
        }
}

} // namespace

glm::vec2 ChartLayout::uv(const AoOccluders& occluders, std::uint32_t t, int c) const
{
    if (chartOf[t] < 0)
        return glm::vec2(0.0f);
    const TexelChart& chart = charts[std::size_t(chartOf[t])];
    const glm::dvec3 d = corner(occluders, t, c) - chart.origin;
    return {float((chart.x + glm::dot(d, chart.axisU) * density) / width), float((chart.y + glm::dot(d, chart.axisV) * density) / height)};
}

ChartLayout chartTexelPoints(const AoOccluders& occluders, double density, AoPoints& points, std::uint64_t maxPixels)
{
    checkTexelDensity(density);
    ChartLayout layout;
    layout.density = density;
    std::vector<glm::dvec3> normals;
    std::int32_t count = 0;
    layout.chartOf = groupCharts(occluders, normals, count);
    layout.charts.resize(std::size_t(count));
    for (std::size_t t = 0; t < layout.chartOf.size(); ++t)
        if (layout.chartOf[t] >= 0)
            layout.charts[std::size_t(layout.chartOf[t])].triangles.push_back(std::uint32_t(t));
    std::vector<glm::dvec2> extents(layout.charts.size());
    for (std::size_t k = 0; k < layout.charts.size(); ++k)
        extents[k] = frameChart(occluders, normals, density, layout.charts[k]);
    // Sized and packed in double before anything is allocated: a huge chart's size wraps nothing.
    std::vector<atlas::ShelfRect> rects(layout.charts.size());
    const auto packAt = [&](double at) {
        std::vector<std::pair<double, double>> sizes(extents.size());
        for (std::size_t k = 0; k < extents.size(); ++k)
            sizes[k] = chartSize(extents[k], at);
        return atlas::packWithin(rects, sizes, maxPixels);
    };
    const auto packed = packAt(density);
    if (!packed)
        atlas::refuseDensity(density, maxPixels, [&](double at) { return packAt(at).has_value(); });
    for (std::size_t k = 0; k < rects.size(); ++k)
        layout.charts[k].x = rects[k].x, layout.charts[k].y = rects[k].y;
    std::tie(layout.width, layout.height) = *packed;
    for (TexelChart& chart : layout.charts) {
        chart.firstPoint = points.size();
        chartPoints(occluders, density, chart, normals, points);
    }
    return layout;
}

void dilateAtlas(int width, int height, std::vector<glm::vec3>& pixels, std::vector<std::uint8_t>& filled, int passes)
{
    const std::size_t count = std::size_t(width) * std::size_t(height);
    if (pixels.size() != count || filled.size() != count)
        throw Error("dilateAtlas: the image and its mask must both hold width x height pixels");
    std::vector<std::size_t> grown;
    std::vector<glm::vec3> value;
    for (int pass = 0; pass < passes; ++pass) {
        grown.clear(), value.clear();
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const std::size_t px = std::size_t(y) * std::size_t(width) + std::size_t(x);
                if (filled[px])
                    continue;
                glm::vec3 sum(0.0f);
                int n = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int nx = x + dx, ny = y + dy;
                        if (nx < 0 || ny < 0 || nx >= width || ny >= height)
                            continue;
                        const std::size_t q = std::size_t(ny) * std::size_t(width) + std::size_t(nx);
                        if (filled[q])
                            sum += pixels[q], ++n;
                    }
                if (n > 0)
                    grown.push_back(px), value.push_back(sum / float(n));
            }
        if (grown.empty())
            return;
        // Written after the pass: a pixel filled in this pass feeds only the next one.
        for (std::size_t k = 0; k < grown.size(); ++k)
            pixels[grown[k]] = value[k], filled[grown[k]] = 1;
    }
}

} // namespace sightline
