#include "lighting/ao/AoTexels.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>

#include <glm/geometric.hpp>

#include "NearestOnTriangle.h"
#include "ShelfAtlas.h"
#include "base/Error.h"

namespace sightline {

namespace {


} // namespace

glm::vec2 AoTexelLayout::uv(const AoOccluders& occluders, std::uint32_t t, int c) const
{
    const AoTexelTile& tile = tiles[t];
    const glm::dvec3 p = glm::dvec3(occluders.vertices[occluders.indices[3 * std::size_t(t) + std::size_t(c)]]);
    const glm::dvec3 r = p - glm::dvec3(tile.origin);
    const double s = glm::dot(r, glm::dvec3(tile.axisU)) * density, q = glm::dot(r, glm::dvec3(tile.axisV)) * density;
    return {float((tile.x + s) / width), float((tile.y + q) / height)};
}

void checkTexelDensity(double density)
{
    if (density > 0.0 && density <= kMaxTexelDensity)   // false for NaN
        return;
    char text[64];
    std::snprintf(text, sizeof text, "--texel %g: ", density);
    throw Error(text + std::string("the light-map density must be a number of texels per metre in (0, ") +
                std::to_string(int(kMaxTexelDensity)) + "]");
}

AoTexelLayout aoTexelPoints(const AoOccluders& occluders, double density, AoPoints& points, std::uint64_t maxPixels)
{
    checkTexelDensity(density);
    AoTexelLayout layout;
    layout.density = density;
    const std::size_t nt = occluders.triangleCount();
    layout.tiles.resize(nt);
    std::vector<glm::dvec2> extents(nt, glm::dvec2(0.0));   // (0, 0): degenerate, no texels
    for (std::uint32_t t = 0; t < nt; ++t) {
        AoTexelTile& tile = layout.tiles[t];
        tile.triangle = t;
        const glm::dvec3 a(occluders.vertices[occluders.indices[3 * t]]), b(occluders.vertices[occluders.indices[3 * t + 1]]),
            c(occluders.vertices[occluders.indices[3 * t + 2]]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        const double length = glm::length(b - a), area2 = glm::length(n);
        if (!(length > 0.0) || !(area2 > 1e-12 * length * length))
            continue;   // degenerate: no texels
        const glm::dvec3 u = (b - a) / length, v = glm::cross(n / area2, u);
        const double cu = glm::dot(c - a, u), cv = glm::dot(c - a, v);
        const double u0 = std::min(0.0, cu), u1 = std::max(length, cu);
        tile.origin = glm::vec3(a + u0 * u);
        tile.axisU = glm::vec3(u);
        tile.axisV = glm::vec3(v);
        extents[t] = {u1 - u0, cv};
    }
    // Sized and packed in double before anything is allocated: a tile past the limit wraps no int.
    const auto sizeAt = [&](std::size_t t, double at) {
        return extents[t].x > 0.0 ? std::pair{std::max(1.0, std::ceil(extents[t].x * at)), std::max(1.0, std::ceil(extents[t].y * at))}
                                  : std::pair{0.0, 0.0};
    };
    std::vector<atlas::ShelfRect> rects(nt);
    const auto packAt = [&](double at) {
        std::vector<std::pair<double, double>> sizes(nt);
        for (std::size_t t = 0; t < nt; ++t)
            sizes[t] = sizeAt(t, at);
        return atlas::packWithin(rects, sizes, maxPixels);
    };
    const auto packed = packAt(density);
    if (!packed)
        atlas::refuseDensity(density, maxPixels, [&](double at) { return packAt(at).has_value(); });
    for (std::size_t t = 0; t < nt; ++t) {
        AoTexelTile& tile = layout.tiles[t];
        tile.width = rects[t].width, tile.height = rects[t].height, tile.x = rects[t].x, tile.y = rects[t].y;
    }
    std::tie(layout.width, layout.height) = *packed;
    for (AoTexelTile& tile : layout.tiles) {
        tile.firstPoint = points.size();
        if (tile.width == 0)
            continue;
        const std::uint32_t t = tile.triangle;
        const glm::dvec3 a(occluders.vertices[occluders.indices[3 * t]]), b(occluders.vertices[occluders.indices[3 * t + 1]]),
            c(occluders.vertices[occluders.indices[3 * t + 2]]);
        const glm::vec3 normal = glm::vec3(glm::normalize(glm::cross(b - a, c - a)));
        for (int q = 0; q < tile.height; ++q)
            for (int s = 0; s < tile.width; ++s) {
                const glm::dvec3 centre = glm::dvec3(tile.origin) + ((s + 0.5) / density) * glm::dvec3(tile.axisU) +
                                          ((q + 0.5) / density) * glm::dvec3(tile.axisV);
                points.positions.push_back(glm::vec3(nearestOnTriangle(centre, a, b, c)));
                points.normals.push_back(normal);
                points.status.push_back(AoPointStatus::Ok);
            }
    }
    return layout;
}

} // namespace sightline
