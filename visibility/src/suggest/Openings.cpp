#include "visibility/suggest/Openings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "base/Error.h"
#include "visibility/suggest/DistanceGrid.h"

namespace sightline::suggest {

namespace {

/// Union-find over the occupied cells.
struct Groups {
    std::vector<std::uint32_t> parent;
    std::uint32_t find(std::uint32_t a)
    {
        while (parent[a] != a)
            a = parent[a] = parent[parent[a]];
        return a;
    }
    void join(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

/// A bin of tightest points.
struct Cell {
    glm::ivec3 at;
    glm::dvec3 sum{0.0};
    std::uint64_t rays = 0;
    double clearance = 0.0;
    std::vector<std::uint64_t> raySample;
};

/// The point of `ray` with the least clearance, away from its ends by a few voxels (or a tenth
/// of it), and that clearance.
std::pair<glm::dvec3, double> tightestPoint(const DistanceGrid& grid, const OpeningRay& ray, int steps)
{
    const double length = glm::length(ray.to - ray.from);
    const double margin = std::min(0.1, 3.0 * grid.voxel() / std::max(length, 1e-12));
    double best = std::numeric_limits<double>::infinity();
    glm::dvec3 at = 0.5 * (ray.from + ray.to);
    for (int k = 0; k <= steps; ++k) {
        const double t = margin + (1.0 - 2.0 * margin) * double(k) / steps;
        const glm::dvec3 p = ray.from + t * (ray.to - ray.from);
        const double d = grid.distance(p);
        if (d < best) {
            best = d;
            at = p;
        }
    }
    return {at, std::isfinite(best) ? best : 0.0};
}

/// Neighbouring cells (26-connected) joined into groups, one Opening per group.
std::vector<Opening> joinCells(const std::vector<Cell>& cells, const std::unordered_map<std::uint64_t, std::uint32_t>& cellAt,
                               glm::ivec3 n, auto key)
{
    Groups groups{std::vector<std::uint32_t>(cells.size())};
    std::iota(groups.parent.begin(), groups.parent.end(), 0u);
    for (std::uint32_t a = 0; a < cells.size(); ++a)
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const glm::ivec3 c = cells[a].at + glm::ivec3(dx, dy, dz);
                    if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, n)))
                        continue;
                    if (const auto it = cellAt.find(key(c)); it != cellAt.end())
                        groups.join(a, it->second);
                }
    std::unordered_map<std::uint32_t, std::size_t> openingOf;
    std::vector<Opening> openings;
    for (std::uint32_t a = 0; a < cells.size(); ++a) {
        const Cell& cell = cells[a];
        auto [it, fresh] = openingOf.try_emplace(groups.find(a), openings.size());
        if (fresh) {
            Opening opening;
            opening.min = glm::dvec3(std::numeric_limits<double>::infinity());
            opening.max = -opening.min;
            openings.push_back(opening);
        }
        Opening& opening = openings[it->second];
        const glm::dvec3 mean = cell.sum / double(cell.rays);
        opening.centre += cell.sum;
        opening.rays += cell.rays;
        opening.min = glm::min(opening.min, mean);
        opening.max = glm::max(opening.max, mean);
        opening.clearance = std::max(opening.clearance, cell.clearance);
        for (std::uint64_t ray : cell.raySample)
            if (opening.raySample.size() < kOpeningRaySample)
                opening.raySample.push_back(ray);
    }
    for (Opening& opening : openings)
        opening.centre /= double(opening.rays);
    std::stable_sort(openings.begin(), openings.end(), [](const Opening& a, const Opening& b) { return a.rays > b.rays; });
    return openings;
}

} // namespace

std::vector<Opening> groupOpenings(const WorldTriangles& triangles, std::span<const OpeningRay> rays, double spacing,
                                   const OpeningSettings& settings)
{
    if (rays.empty())
        return {};
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const OpeningRay& ray : rays) {
        if (!finite(ray.from) || !finite(ray.to))
            throw Error("openings: a ray with a non-finite end");
        lo = glm::min(lo, glm::min(ray.from, ray.to));
        hi = glm::max(hi, glm::max(ray.from, ray.to));
    }
    const double longest = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-6});
    const double voxel = longest / double(std::max(settings.cells, 8));
    const glm::dvec3 pad(2.0 * voxel);
    const DistanceGrid grid(triangles, lo - pad, hi + pad, voxel, settings.cells + 8);

    // Cells wide enough that the tightest points of neighbouring rays through one opening (as far
    // apart as the rays' ends) fall into touching cells.
    const double width = std::max(2.0 * grid.voxel(), std::isfinite(spacing) ? spacing : 0.0);
    const glm::dvec3 origin = lo - pad;
    const glm::ivec3 n = glm::ivec3(glm::ceil((hi + pad - origin) / width)) + 1;
    const auto key = [n](glm::ivec3 c) {
        return (std::uint64_t(c.z) * std::uint64_t(n.y) + std::uint64_t(c.y)) * std::uint64_t(n.x) + std::uint64_t(c.x);
    };
    std::unordered_map<std::uint64_t, std::uint32_t> cellAt;   // cell key -> index into `cells`
    std::vector<Cell> cells;
    const int steps = std::max(settings.steps, 8);
    for (const OpeningRay& ray : rays) {
        const auto [at, clearance] = tightestPoint(grid, ray, steps);
        const glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor((at - origin) / width)), glm::ivec3(0), n - 1);
        auto [it, fresh] = cellAt.try_emplace(key(c), std::uint32_t(cells.size()));
        if (fresh)
            cells.push_back(Cell{c, glm::dvec3(0.0), 0, 0.0, {}});
        Cell& cell = cells[it->second];
        cell.sum += at;
        ++cell.rays;
        cell.clearance = std::max(cell.clearance, clearance);
        if (cell.raySample.size() < kOpeningRaySample)
            cell.raySample.push_back(ray.id);
    }
    return joinCells(cells, cellAt, n, key);
}

} // namespace sightline::suggest
