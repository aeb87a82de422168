#include "lights/PointTiles.h"

#include <algorithm>

#include <glm/common.hpp>

namespace sightline::lights {

namespace {

/// The 30-bit Morton code of three 10-bit coordinates.
std::uint32_t morton(std::uint32_t x, std::uint32_t y, std::uint32_t z)
{
    const auto spread = [](std::uint32_t v) {
        v = (v | (v << 16)) & 0x030000FFu;
        v = (v | (v << 8)) & 0x0300F00Fu;
        v = (v | (v << 4)) & 0x030C30C3u;
        v = (v | (v << 2)) & 0x09249249u;
        return v;
    };
    return spread(x) | (spread(y) << 1) | (spread(z) << 2);
}

} // namespace

std::vector<PointTile> makePointTiles(std::span<const ShadingPoint> points)
{
    if (points.empty())
        return {};
    glm::dvec3 lo = points[0].position, hi = lo;
    for (const ShadingPoint& p : points)
        lo = glm::min(lo, p.position), hi = glm::max(hi, p.position);
    const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(1e-30));
    std::vector<std::pair<std::uint32_t, std::uint32_t>> order(points.size());
    for (std::size_t j = 0; j < points.size(); ++j) {
        const glm::dvec3 t = (points[j].position - lo) / extent * 1023.0;
        order[j] = {morton(std::uint32_t(t.x), std::uint32_t(t.y), std::uint32_t(t.z)), std::uint32_t(j)};
    }
    std::sort(order.begin(), order.end());
    std::vector<PointTile> tiles;
    tiles.reserve((points.size() + kTilePoints - 1) / kTilePoints);
    for (std::size_t first = 0; first < order.size(); first += kTilePoints) {
        PointTile tile;
        const std::size_t last = std::min(order.size(), first + kTilePoints);
        tile.lo = tile.hi = points[order[first].second].position;
        for (std::size_t k = first; k < last; ++k) {
            const glm::dvec3& p = points[order[k].second].position;
            tile.points.push_back(order[k].second);
            tile.lo = glm::min(tile.lo, p), tile.hi = glm::max(tile.hi, p);
        }
        tiles.push_back(std::move(tile));
    }
    return tiles;
}

} // namespace sightline::lights
