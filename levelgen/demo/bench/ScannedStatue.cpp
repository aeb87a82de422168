#include "demo/bench/ScannedStatue.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>

namespace sightline::demo::bench {
namespace {

struct Bump {
    vec3 direction;
    float threshold;   // cosine of its angular radius
    float height;
};

float radiusFactor(const std::vector<Bump>& bumps, vec3 d)
{
    float r = 1.0f;
    for (const Bump& b : bumps) {
        const float t = (glm::dot(d, b.direction) - b.threshold) / (1.0f - b.threshold);
        if (t > 0.0f) {
            const float s = std::min(t, 1.0f);
            r += b.height * s * s * (3.0f - 2.0f * s);
        }
    }
    return std::max(r, 0.4f);
}

} // namespace

Mesh scannedStatue(const std::string& name, const StatueShape& shape, Rng& rng)
{
    std::vector<Bump> bumps;
    for (int k = 0; k < shape.bumps; ++k)
        bumps.push_back({rng.direction(), rng.range(0.55f, 0.9f), shape.amplitude * rng.range(-0.6f, 1.0f)});
    for (int k = 0; k < 4 * shape.bumps; ++k)   // scan noise: narrow, shallow
        bumps.push_back({rng.direction(), rng.range(0.97f, 0.995f), rng.range(-0.03f, 0.04f)});

    const int n = shape.resolution;
    // Equal-angle grid: the cube coordinate of line i is tan of its angle, ends and middle exact
    // so that faces meet on bit-identical edges.
    std::vector<float> g(std::size_t(n) + 1);
    for (int i = 0; i <= n; ++i) {
        const glm::dvec2 cs = cosSin((double(i) / n - 0.5) * 0.25);
        g[std::size_t(i)] = i == 0 ? -1.0f : i == n ? 1.0f : 2 * i == n ? 0.0f : float(cs.y / cs.x);
    }
    Mesh mesh;
    mesh.name = name;
    mesh.watertight = !shape.cutBelow;
    const std::size_t side = std::size_t(n) + 1;
    std::vector<std::int32_t> index(side * side * side, -1);
    auto vertex = [&](std::array<int, 3> c) {
        std::int32_t& id = index[(std::size_t(c[0]) * side + std::size_t(c[1])) * side + std::size_t(c[2])];
        if (id < 0) {
            const vec3 d = glm::normalize(vec3(g[std::size_t(c[0])], g[std::size_t(c[1])], g[std::size_t(c[2])]));
            id = std::int32_t(mesh.positions.size());
            mesh.positions.push_back(shape.radii * d * radiusFactor(bumps, d));
        }
        return std::uint32_t(id);
    };
    for (int axis = 0; axis < 3; ++axis) {
        const int b = (axis + 1) % 3, c = (axis + 2) % 3;
        for (int sign : {-1, 1})
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    auto at = [&](int di, int dj) {
                        std::array<int, 3> p{};
                        p[std::size_t(axis)] = sign > 0 ? n : 0;
                        p[std::size_t(b)] = i + di;
                        p[std::size_t(c)] = j + dj;
                        return vertex(p);
                    };
                    // Counter-clockwise seen from outside: (b, c) is right-handed about +axis.
                    std::array<std::uint32_t, 4> q{at(0, 0), at(1, 0), at(1, 1), at(0, 1)};
                    if (sign < 0)
                        std::swap(q[1], q[3]);
                    for (const auto& t : {std::array{q[0], q[1], q[2]}, std::array{q[0], q[2], q[3]}}) {
                        if (shape.cutBelow && mesh.positions[t[0]].y < *shape.cutBelow &&
                            mesh.positions[t[1]].y < *shape.cutBelow && mesh.positions[t[2]].y < *shape.cutBelow)
                            continue;
                        mesh.indices.insert(mesh.indices.end(), t.begin(), t.end());
                    }
                }
    }
    mesh.normals.assign(mesh.positions.size(), vec3(0.0f));
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const vec3 &p = mesh.positions[mesh.indices[t]], &q = mesh.positions[mesh.indices[t + 1]],
                   &r = mesh.positions[mesh.indices[t + 2]];
        const vec3 n3 = glm::cross(q - p, r - p);
        for (std::size_t k = 0; k < 3; ++k)
            mesh.normals[mesh.indices[t + k]] += n3;
    }
    for (vec3& nrm : mesh.normals)
        nrm = glm::dot(nrm, nrm) > 0.0f ? glm::normalize(nrm) : vec3(0, 1, 0);
    return mesh;
}

} // namespace sightline::demo::bench
