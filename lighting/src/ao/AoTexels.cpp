#include "lighting/ao/AoTexels.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

#include <glm/geometric.hpp>

#include "NearestOnTriangle.h"
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
    std::uint64_t texels = 0;
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
        // Sized in double first: a tile past the limit must not reach an int.
        const double width = std::max(1.0, std::ceil((u1 - u0) * density)), height = std::max(1.0, std::ceil(cv * density));
        if (!(width * height <= double(maxPixels))) {
            texels = maxPixels + 1;
            break;
        }
        tile.width = int(width);
        tile.height = int(height);
        texels += std::uint64_t(tile.width) * std::uint64_t(tile.height);
        if (texels > maxPixels)
            break;
    }
    // Shelf packing, tallest first, one-texel gutter.
    std::vector<std::uint32_t> order(nt);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t l, std::uint32_t r) {
        return layout.tiles[l].height != layout.tiles[r].height ? layout.tiles[l].height > layout.tiles[r].height : l < r;
    });
    int widest = 1;
    for (const AoTexelTile& tile : layout.tiles)
        widest = std::max(widest, tile.width + 1);
    const int atlasWidth = std::max(widest, int(std::ceil(std::sqrt(double(texels) * 1.3))) + 1);
    int x = 0, y = 0, shelf = 0;
    for (std::uint32_t t : order) {
        AoTexelTile& tile = layout.tiles[t];
        if (tile.width == 0)
            continue;
        if (x + tile.width + 1 > atlasWidth) {
            x = 0;
            y += shelf + 1;
            shelf = 0;
        }
        tile.x = x;
        tile.y = y;
        x += tile.width + 1;
        shelf = std::max(shelf, tile.height);
    }
    layout.width = atlasWidth;
    layout.height = std::max(1, y + shelf);
    const std::uint64_t pixels = std::uint64_t(layout.width) * std::uint64_t(layout.height);
    if (texels > maxPixels || pixels > maxPixels) {
        const double fit = density * std::sqrt(double(maxPixels) / double(std::max(texels, pixels)) * 0.7);
        throw Error("--texel " + std::to_string(density) + ": the light map would need more than " +
                    std::to_string(maxPixels >> 20) + " Mpixels; try --texel " + std::to_string(fit) + " or less");
    }
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
