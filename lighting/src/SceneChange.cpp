#include "lighting/SceneChange.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <iterator>
#include <map>

namespace sightline {

namespace {

/// A triangle's vertices bit for bit, then the instance that holds it (not compared).
using TriangleKey = std::array<std::uint32_t, 10>;
using PointKey = std::array<std::uint64_t, 6>;

bool lessGeometry(const TriangleKey& a, const TriangleKey& b)
{
    return std::lexicographical_compare(a.begin(), a.begin() + 9, b.begin(), b.begin() + 9);
}

std::vector<TriangleKey> sortedTriangles(const WorldTriangles& triangles)
{
    std::vector<TriangleKey> keys(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (int k = 0; k < 9; ++k)
            keys[t][std::size_t(k)] = std::bit_cast<std::uint32_t>(triangles.vertices[3 * t + std::size_t(k / 3)][k % 3]);
    for (std::size_t t = 0; t < triangles.size(); ++t)
        keys[t][9] = triangles.instanceOf[t];
    std::sort(keys.begin(), keys.end(), lessGeometry);
    return keys;
}

/// One box per instance of the triangles' keys, in the instances' order.
void addBoxes(std::vector<Bounds>& out, const std::vector<TriangleKey>& keys)
{
    std::map<std::uint32_t, Bounds> byInstance;
    for (const TriangleKey& key : keys)
        for (int v = 0; v < 3; ++v)
            byInstance[key[9]].extend(glm::vec3(std::bit_cast<float>(key[std::size_t(3 * v)]),
                                                std::bit_cast<float>(key[std::size_t(3 * v + 1)]),
                                                std::bit_cast<float>(key[std::size_t(3 * v + 2)])));
    for (const auto& [instance, box] : byInstance)
        out.push_back(box);
}

PointKey keyOf(const ShadingPoint& p)
{
    return {std::bit_cast<std::uint64_t>(p.position.x), std::bit_cast<std::uint64_t>(p.position.y),
            std::bit_cast<std::uint64_t>(p.position.z), std::bit_cast<std::uint64_t>(p.normal.x),
            std::bit_cast<std::uint64_t>(p.normal.y),   std::bit_cast<std::uint64_t>(p.normal.z)};
}

} // namespace

std::vector<Bounds> changedRegions(const WorldTriangles& before, const WorldTriangles& after)
{
    const std::vector<TriangleKey> a = sortedTriangles(before), b = sortedTriangles(after);
    std::vector<TriangleKey> gone, added;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(gone), lessGeometry);
    std::set_difference(b.begin(), b.end(), a.begin(), a.end(), std::back_inserter(added), lessGeometry);
    std::vector<Bounds> regions;
    addBoxes(regions, gone);
    addBoxes(regions, added);
    return regions;
}

std::vector<std::size_t> matchPoints(std::span<const ShadingPoint> before, std::span<const ShadingPoint> after)
{
    std::vector<std::pair<PointKey, std::size_t>> old(before.size());
    for (std::size_t i = 0; i < before.size(); ++i)
        old[i] = {keyOf(before[i]), i};
    std::sort(old.begin(), old.end());
    std::vector<bool> taken(before.size(), false);
    std::vector<std::size_t> previous(after.size(), SIZE_MAX);
    for (std::size_t j = 0; j < after.size(); ++j) {
        const PointKey key = keyOf(after[j]);
        auto it = std::lower_bound(old.begin(), old.end(), std::pair<PointKey, std::size_t>{key, 0});
        for (; it != old.end() && it->first == key; ++it)
            if (!taken[it->second]) {
                taken[it->second] = true;
                previous[j] = it->second;
                break;
            }
    }
    return previous;
}

} // namespace sightline
