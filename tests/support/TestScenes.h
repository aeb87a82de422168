#pragma once
// Small scenes with known answers, built in code.

#include <cmath>
#include <cstdint>
#include <exception>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/vec3.hpp>

#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline::test {

/// A quad (two triangles) with corners c, c+u, c+u+v, c+v.
inline Mesh quad(const glm::vec3& c, const glm::vec3& u, const glm::vec3& v, const std::string& name = "quad")
{
    Mesh m;
    m.name = name;
    m.positions = {c, c + u, c + u + v, c + v};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

/// `count` random triangles: a first vertex uniform in [xyLo, xyHi]^2 x [zLo, zHi], the other two
/// within +-spread of it on each axis.
inline Mesh randomSoup(unsigned seed, std::uint32_t count, float xyLo, float xyHi, float zLo, float zHi, float spread)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> xy(xyLo, xyHi), z(zLo, zHi), d(-spread, spread);
    Mesh soup;
    soup.name = "soup";
    for (std::uint32_t t = 0; t < count; ++t) {
        const glm::vec3 a(xy(rng), xy(rng), z(rng));
        soup.positions.insert(soup.positions.end(), {a, a + glm::vec3(d(rng), d(rng), d(rng)),
                                                     a + glm::vec3(d(rng), d(rng), d(rng))});
        soup.indices.insert(soup.indices.end(), {3 * t, 3 * t + 1, 3 * t + 2});
    }
    return soup;
}

/// A closed, outward-oriented unit cube [-0.5, 0.5]^3 flagged watertight.
inline Mesh closedBox()
{
    Mesh m;
    m.name = "box";
    for (int i = 0; i < 8; ++i)
        m.positions.emplace_back((i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f);
    m.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    m.watertight = true;
    return m;
}

/// A closed box instance named `name` spanning [lo, hi] (closedBox scaled and moved); its index.
inline std::size_t addBox(Scene& scene, const std::string& name, glm::vec3 lo, glm::vec3 hi)
{
    Mesh m = closedBox();
    m.name = name;
    const glm::mat4 xf = glm::scale(glm::translate(glm::mat4(1.0f), 0.5f * (lo + hi)), hi - lo);
    const std::size_t i = scene.addMeshInstance(m, xf);
    scene.instances[i].name = name;
    return i;
}

/// The bounds [lo, hi].
inline Bounds boxBounds(glm::vec3 lo, glm::vec3 hi)
{
    Bounds b;
    b.min = lo;
    b.max = hi;
    return b;
}

/// A closed, outward-oriented torus around the z axis through `centre` (`rings` x `sides` quads,
/// two triangles each), its tube's radius varied by `lumps` (0: smooth) so that no two quads are
/// alike. Flagged watertight.
inline Mesh closedTorus(const glm::dvec3& centre, double major, double minor, int rings, int sides, double lumps = 0.0)
{
    Mesh m;
    m.name = "torus";
    constexpr double kTwoPi = 6.283185307179586;
    for (int i = 0; i < rings; ++i)
        for (int k = 0; k < sides; ++k) {
            const double a = kTwoPi * i / rings, b = kTwoPi * k / sides;
            const double r = minor * (1.0 + lumps * std::sin(3.0 * a + 2.0 * b) * std::cos(5.0 * b - a));
            m.positions.emplace_back(centre + glm::dvec3((major + r * std::cos(b)) * std::cos(a),
                                                         (major + r * std::cos(b)) * std::sin(a), r * std::sin(b)));
        }
    const auto at = [&](int i, int k) { return std::uint32_t((i % rings) * sides + (k % sides)); };
    for (int i = 0; i < rings; ++i)
        for (int k = 0; k < sides; ++k)
            m.indices.insert(m.indices.end(), {at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k), at(i + 1, k + 1), at(i, k + 1)});
    m.watertight = true;
    return m;
}

inline Scene sceneOf(std::vector<Mesh> meshes)
{
    Scene s;
    for (Mesh& m : meshes)
        s.addMeshInstance(std::move(m));
    return s;
}

/// A comb of many small triangles across the shaft of xyPatch pairs at z ~ 1 (1.00 to 1.04): a
/// 3 x 3 m grid of 40 x 40 cells of which every other column is filled, so partly open. Every
/// triangle touches most receiver samples: with few source samples the pairs outnumber the rays.
inline Mesh combWall(int n = 40)
{
    Mesh grid;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            grid.positions.emplace_back(-1.0f + 3.0f * float(x) / n, -1.0f + 3.0f * float(y) / n,
                                        1.0f + 0.01f * float((x * 7 + y * 3) % 5));
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; x += 2) {
            const std::uint32_t i = std::uint32_t(y * (n + 1) + x);
            grid.indices.insert(grid.indices.end(), {i, i + 1, i + n + 2, i, i + n + 2, i + n + 1});
        }
    return grid;
}

/// A sheet of n x n quads over x, z in [-extent, extent] at y = height(x, z), two triangles a
/// quad (a curved surface to coarsen, or to draw in chunks).
template <typename Height>
Mesh heightGrid(const std::string& name, int n, float extent, Height&& height)
{
    Mesh sheet;
    sheet.name = name;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = -extent + 2.0f * extent * float(i) / float(n), z = -extent + 2.0f * extent * float(j) / float(n);
            sheet.positions.emplace_back(x, height(x, z), z);
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n + 1), d = c + 1;
            sheet.indices.insert(sheet.indices.end(), {a, c, b, b, c, d});
        }
    return sheet;
}

/// Two parallel unit patches facing each other along +Z: source at z = 0, receiver at z = depth,
/// both spanning [0, 1]^2 in XY.
inline Patch xyPatch(double z, int na, int nb, double size = 1.0)
{
    Patch p;
    p.corner = {0.0, 0.0, z};
    p.u = {size, 0.0, 0.0};
    p.v = {0.0, size, 0.0};
    p.na = na;
    p.nb = nb;
    return p;
}


/// A random valid non-parallel patch pair and a soup of triangles of mixed sizes in and around
/// the shaft, some crossing the patch planes.
struct RandomCase {
    Scene scene;
    Patch source, receiver;

    /// The generator can make a pair that docs/design.md §2 refuses; such cases are skipped.
    bool valid() const
    {
        try {
            validatePatchPair(source, receiver);
            return true;
        } catch (const std::exception&) {
            return false;
        }
    }
};

inline RandomCase randomCase(unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto range = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
    RandomCase c;
    // Source near the origin facing +Z, tilted; receiver 3-5 m away, tilted the other way.
    c.source.corner = {range(-0.2, 0.2), range(-0.2, 0.2), 0.0};
    c.source.u = {range(0.6, 1.5), 0.0, range(-0.3, 0.3)};
    c.source.v = {range(-0.2, 0.2), range(0.6, 1.5), range(-0.3, 0.3)};
    c.source.na = 1 + int(rng() % 12);
    c.source.nb = 1 + int(rng() % 12);
    const double depth = range(3.0, 5.0);
    c.receiver.corner = {range(-1.0, 1.0), range(-1.0, 1.0), depth};
    c.receiver.u = {range(0.8, 2.5), range(-0.4, 0.4), range(-0.5, 0.5)};
    c.receiver.v = {0.0, range(0.8, 2.5), range(-0.5, 0.5)};
    c.receiver.na = 1 + int(rng() % 10);
    c.receiver.nb = 1 + int(rng() % 10);

    Mesh soup;
    auto addTriangle = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 cc) {
        const auto base = std::uint32_t(soup.positions.size());
        soup.positions.insert(soup.positions.end(), {glm::vec3(a), glm::vec3(b), glm::vec3(cc)});
        soup.indices.insert(soup.indices.end(), {base, base + 1, base + 2});
    };
    auto point = [&](double zLo, double zHi) { return glm::dvec3(range(-1.0, 2.5), range(-1.0, 2.5), range(zLo, zHi)); };
    auto jitter = [&](double size) { return glm::dvec3(range(-size, size), range(-size, size), range(-size, size)); };
    for (int t = 0; t < 60; ++t) {   // tiny
        const glm::dvec3 p = point(0.3, depth - 0.3);
        addTriangle(p, p + jitter(0.05), p + jitter(0.05));
    }
    for (int t = 0; t < 25; ++t) {   // medium
        const glm::dvec3 p = point(0.3, depth - 0.3);
        addTriangle(p, p + jitter(0.6), p + jitter(0.6));
    }
    for (int t = 0; t < 3; ++t) {    // huge, possibly crossing both patch planes
        const glm::dvec3 p = point(-1.0, depth + 1.0);
        addTriangle(p, p + jitter(6.0), p + jitter(6.0));
    }
    // One crossing the source plane, one crossing the receiver plane.
    addTriangle({0.3, 0.3, -0.5}, {0.9, 0.4, 0.7}, {0.5, 1.0, 0.4});
    addTriangle({0.0, 0.5, depth + 0.5}, {1.5, 0.6, depth - 0.8}, {0.6, 1.8, depth - 0.2});
    c.scene.addMeshInstance(std::move(soup));
    return c;
}


} // namespace sightline::test
