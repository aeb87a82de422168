#include "lights/EdgeNeighbours.h"

#include <algorithm>
#include <cstring>
#include <unordered_map>

namespace sightline::lights {

namespace {

struct EdgeKey {
    std::array<float, 6> ends;   ///< the lower vertex first (lexicographically), so both windings meet

    bool operator==(const EdgeKey& other) const { return std::memcmp(ends.data(), other.ends.data(), sizeof(ends)) == 0; }
};

struct EdgeKeyHash {
    std::size_t operator()(const EdgeKey& key) const
    {
        std::uint32_t words[6];
        std::memcpy(words, key.ends.data(), sizeof(words));
        std::uint64_t h = 0x9E3779B97F4A7C15ull;
        for (const std::uint32_t w : words)
            h = (h ^ w) * 0x100000001B3ull;
        return std::size_t(h ^ (h >> 29));
    }
};

EdgeKey keyOf(const glm::vec3& p, const glm::vec3& q)
{
    const auto less = [](const glm::vec3& x, const glm::vec3& y) {
        return x.x != y.x ? x.x < y.x : x.y != y.y ? x.y < y.y : x.z < y.z;
    };
    const glm::vec3& lo = less(p, q) ? p : q;
    const glm::vec3& hi = less(p, q) ? q : p;
    return {{lo.x, lo.y, lo.z, hi.x, hi.y, hi.z}};
}

} // namespace

std::vector<std::array<std::int64_t, 3>> edgeNeighbours(const WorldTriangles& triangles)
{
    const std::size_t count = triangles.size();
    // Each edge's first two triangles and how many share it.
    struct Sharing {
        std::int64_t first = -1, second = -1;
        int count = 0;
    };
    std::unordered_map<EdgeKey, Sharing, EdgeKeyHash> edges;
    edges.reserve(3 * count);
    for (std::size_t t = 0; t < count; ++t)
        for (int e = 0; e < 3; ++e) {
            Sharing& s = edges[keyOf(triangles.vertices[3 * t + std::size_t(e)], triangles.vertices[3 * t + std::size_t((e + 1) % 3)])];
            (s.count == 0 ? s.first : s.second) = std::int64_t(t);
            ++s.count;
        }
    std::vector<std::array<std::int64_t, 3>> neighbours(count, {-1, -1, -1});
    for (std::size_t t = 0; t < count; ++t)
        for (int e = 0; e < 3; ++e) {
            const Sharing& s = edges.at(keyOf(triangles.vertices[3 * t + std::size_t(e)], triangles.vertices[3 * t + std::size_t((e + 1) % 3)]));
            if (s.count == 2)
                neighbours[t][std::size_t(e)] = s.first == std::int64_t(t) ? s.second : s.first;
        }
    return neighbours;
}

} // namespace sightline::lights
