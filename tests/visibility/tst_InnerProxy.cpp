// The inner proxies of meshes (bitmask/InnerProxy.h), closed or capped over their holes: their
// faces lie inside the volume and clear of the surface, and the sampler's answers with them are
// the exact answers, at production sample counts, near the origin and 10 and 100 km from it.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

#include "AdversarialScenes.h"
#include "ExactJudge.h"
#include "TestScenes.h"
#include "bitmask/InnerProxy.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/ExactSegment.h"
#include "visibility/RayCastSampler.h"

using namespace sightline;
using namespace sightline::test;
using namespace sightline::bitmask;
using sightline::judge_detail::pointTriangleDistance2;

namespace {

/// Two tori through each other as one mesh: closed (every edge shared twice), crossing itself;
/// the space inside both has even parity and must stay out of the proxy.
Mesh linkedTori(const glm::dvec3& centre)
{
    Mesh m = closedTorus(centre, 1.0, 0.45, 64, 32, 0.1);
    const Mesh other = closedTorus(centre + glm::dvec3(0.5, 0.0, 0.0), 1.0, 0.45, 64, 32, 0.1);
    const auto offset = std::uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), other.positions.begin(), other.positions.end());
    for (std::uint32_t i : other.indices)
        m.indices.push_back(i + offset);
    return m;
}

/// An open tube along z, or x (no ends): `rings` x `sides` quads of lumpy radius around the axis
/// through `centre`, from length / 2 before it to length / 2 after. Rays along the axis pass
/// through it without meeting it.
Mesh openTube(const glm::dvec3& centre, double radius, double length, int rings, int sides, bool alongX = false)
{
    Mesh m;
    m.name = "tube";
    constexpr double kTwoPi = 6.283185307179586;
    for (int i = 0; i <= rings; ++i)
        for (int k = 0; k < sides; ++k) {
            const double a = kTwoPi * k / sides, z = length * (double(i) / rings - 0.5);
            const double r = radius * (1.0 + 0.05 * std::sin(3.0 * a + 5.0 * z) * (i > 0 && i < rings));
            m.positions.emplace_back(centre + (alongX ? glm::dvec3(z, r * std::sin(a), r * std::cos(a))
                                                      : glm::dvec3(r * std::cos(a), r * std::sin(a), z)));
        }
    const auto at = [&](int i, int k) { return std::uint32_t(i * sides + (k % sides)); };
    for (int i = 0; i < rings; ++i)
        for (int k = 0; k < sides; ++k)
            m.indices.insert(m.indices.end(), {at(i, k), at(i, k + 1), at(i + 1, k + 1), at(i, k), at(i + 1, k + 1), at(i + 1, k)});
    return m;
}

/// A closed torus with the quads of a few of its rings removed: `holes` (up to 8) holes in the
/// top of its tube, one boundary loop each.
Mesh holedTorus(const glm::dvec3& centre, int holes)
{
    Mesh m = closedTorus(centre, 1.0, 0.5, 64, 32, 0.15);
    m.watertight = false;
    std::vector<std::uint32_t> kept;
    for (std::size_t q = 0; q < m.indices.size() / 6; ++q) {
        const int ring = int(q) / 32, side = int(q) % 32;
        const bool hole = side >= 4 && side < 10 && ring % 8 < 2 && ring / 8 < holes;
        if (!hole)
            kept.insert(kept.end(), m.indices.begin() + std::ptrdiff_t(6 * q), m.indices.begin() + std::ptrdiff_t(6 * q + 6));
    }
    m.indices = std::move(kept);
    return m;
}

/// An n x n grid of quads over [0, 1]², flat (z = 0), open along its outline.
Mesh flatSheet(int n)
{
    Mesh m;
    m.name = "sheet";
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            m.positions.emplace_back(float(x) / float(n), float(y) / float(n), 0.0f);
    const auto at = [&](int x, int y) { return std::uint32_t(y * (n + 1) + x); };
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            m.indices.insert(m.indices.end(), {at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y), at(x + 1, y + 1), at(x, y + 1)});
    return m;
}

/// Every undirected edge of the triangles (three vertices each, equal positions welded) is
/// shared by an even number of them.
bool closedModTwo(const std::vector<glm::vec3>& v)
{
    std::vector<std::pair<std::array<float, 3>, std::array<float, 3>>> edges;
    for (std::size_t t = 0; t + 2 < v.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            std::array<float, 3> a{v[t + k].x, v[t + k].y, v[t + k].z};
            std::array<float, 3> b{v[t + (k + 1) % 3].x, v[t + (k + 1) % 3].y, v[t + (k + 1) % 3].z};
            if (a != b)
                edges.emplace_back(std::min(a, b), std::max(a, b));
        }
    std::sort(edges.begin(), edges.end());
    for (std::size_t k = 0; k < edges.size();) {
        std::size_t end = k;
        while (end < edges.size() && edges[end] == edges[k])
            ++end;
        if ((end - k) % 2 == 1)
            return false;
        k = end;
    }
    return true;
}

/// The distance from p to the nearest of the triangles.
double nearestDistance(const WorldTriangles& t, const glm::dvec3& p)
{
    double nearest = 1e300;
    for (std::size_t k = 0; k < t.size(); ++k)
        nearest = std::min(nearest, pointTriangleDistance2(p, glm::dvec3(t.vertices[3 * k]), glm::dvec3(t.vertices[3 * k + 1]),
                                                           glm::dvec3(t.vertices[3 * k + 2])));
    return std::sqrt(nearest);
}

/// Crossings of the segment from p to a far point, in world triangles of one mesh.
int crossings(const WorldTriangles& t, const glm::dvec3& p, const glm::dvec3& far)
{
    int count = 0;
    for (std::size_t k = 0; k < t.size(); ++k)
        count += segmentCrossesTriangle(p, far, glm::dvec3(t.vertices[3 * k]), glm::dvec3(t.vertices[3 * k + 1]),
                                        glm::dvec3(t.vertices[3 * k + 2]));
    return count;
}

/// A patch facing +z at height z over [x0, x0 + size] x [y0, y0 + size].
Patch patchAt(const glm::dvec3& corner, double size, int n)
{
    Patch p;
    p.corner = corner;
    p.u = {size, 0.0, 0.0};
    p.v = {0.0, size, 0.0};
    p.na = p.nb = n;
    return p;
}

} // namespace

TEST(InnerProxy, FacesLieInsideTheVolumeClearOfTheSurface)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (const double offset : {0.0, 1e4, 1e5})
        for (const bool linked : {false, true}) {
            const glm::dvec3 centre(offset, -0.5 * offset, 0.25 * offset);
            Mesh mesh = linked ? linkedTori(centre) : closedTorus(centre, 1.0, 0.5, 64, 32, 0.15);
            ASSERT_TRUE(closedAndOutward(mesh));
            const WorldTriangles triangles = worldTriangles(sceneOf({std::move(mesh)}));
            const std::vector<glm::vec3> faces = innerProxyTriangles(triangles.vertices.data(), triangles.size(), 16);
            ASSERT_GT(faces.size(), 0u) << offset;
            ASSERT_EQ(faces.size() % 3, 0u);
            EXPECT_LE(faces.size() / 3, triangles.size() / 4);   // coarse: a quarter of the mesh at most
            // Points on every face (corners, centroid and random points) have parity 1 and keep
            // the margin from every triangle.
            for (std::size_t f = 0; f < faces.size(); f += 3) {
                const glm::dvec3 a(faces[f]), b(faces[f + 1]), c(faces[f + 2]);
                EXPECT_GT(glm::length(glm::cross(b - a, c - a)), 0.0);
                std::vector<glm::dvec3> points{a, b, c, (a + b + c) / 3.0};
                for (int k = 0; k < 2; ++k) {
                    double s = 0.5 * (unit(rng) + 1.0), t = 0.5 * (unit(rng) + 1.0);
                    if (s + t > 1.0)
                        s = 1.0 - s, t = 1.0 - t;
                    points.push_back(a + s * (b - a) + t * (c - a));
                }
                for (const glm::dvec3& p : points) {
                    ASSERT_GE(nearestDistance(triangles, p), kInnerMarginMetres) << offset << " face " << f / 3;
                    const glm::dvec3 far = p + 100.0 * glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)));
                    ASSERT_EQ(crossings(triangles, p, far) % 2, 1) << offset << " face " << f / 3;
                }
            }
        }
}

TEST(InnerProxy, ThinOrSmallMeshesGetNone)
{
    // A closed box 0.1 mm thick: no voxel clears the margin on both sides.
    Mesh slab = closedBox();
    for (glm::vec3& p : slab.positions)
        p.z *= 1e-4f;
    const WorldTriangles t = worldTriangles(sceneOf({slab}));
    EXPECT_TRUE(innerProxyTriangles(t.vertices.data(), t.size(), 16).empty());
    // The unit box has a proxy of its own, but the sampler leaves meshes under
    // kProxyMinTriangles whole.
    const WorldTriangles box = worldTriangles(sceneOf({closedBox()}));
    EXPECT_FALSE(innerProxyTriangles(box.vertices.data(), box.size(), 16).empty());
    EXPECT_TRUE(buildInnerProxy(box.vertices.data(), box.size(), 16).faces.empty());
}

TEST(InnerProxy, KeepsTheSamplersExactAtProductionSizes)
{
    // Lumpy statues standing in the shaft between a 32x32 source and a 64x64 receiver (4M rays
    // a call): every strategy, with proxies, against the reference; the rays the two disagree on
    // judged by the exact brute force. The proxies must have answered most blocked rays.
    for (const double offset : {0.0, 1e4, 1e5}) {
        const glm::dvec3 o(offset, 0.5 * offset, -0.25 * offset);
        Mesh a = closedTorus(o + glm::dvec3(0.2, 0.3, 2.0), 0.9, 0.45, 96, 48, 0.15);
        Mesh b = linkedTori(o + glm::dvec3(2.2, 1.6, 3.5));
        b.watertight = closedAndOutward(b);
        ASSERT_TRUE(a.watertight && b.watertight);
        const Scene scene = sceneOf({std::move(a), std::move(b)});
        const Patch source = patchAt(o + glm::dvec3(-0.5, -0.5, 0.0), 3.0, 32);
        const Patch receiver = patchAt(o + glm::dvec3(-1.5, -1.5, 5.5), 5.0, 64);
        const HiddenSampleMap expected = RayCastScene(scene).sample(source, receiver);
        const ExactJudge judge(worldTriangles(scene), source, receiver);
        CpuBitmaskSampler sampler(scene);
        std::size_t everyFace = 0;
        for (const CpuStrategy strategy : {CpuStrategy::Auto, CpuStrategy::RayCast, CpuStrategy::Bitmask}) {
            BitmaskStats stats;
            const HiddenSampleMap map = sampler.sample(source, receiver, {.strategy = strategy}, &stats);
            EXPECT_GT(stats.debug.proxyFaces, 0u) << offset;
            everyFace = stats.debug.proxyFaces;
            EXPECT_GT(stats.proxyBlocked, expected.blockedCount() / 2) << offset;
            const Verdict v = judge.judge(map, raysToJudge({&map, &expected}, 4096, 3u));
            EXPECT_EQ(v.nonTie(), 0u) << offset << " " << stats.strategy;
        }
        // 8x4 source samples: more pairs per ray, so only the faces across the shaft's axis.
        {
            Patch few = source;
            few.na = 8, few.nb = 4;
            BitmaskStats stats;
            const HiddenSampleMap map = sampler.sample(few, receiver, {.strategy = CpuStrategy::RayCast}, &stats);
            const HiddenSampleMap fewExpected = RayCastScene(scene).sample(few, receiver);
            EXPECT_GT(stats.debug.proxyFaces, 0u) << offset;
            EXPECT_LT(stats.debug.proxyFaces, everyFace) << offset;
            EXPECT_GT(stats.proxyBlocked, fewExpected.blockedCount() / 4) << offset;
            const ExactJudge fewJudge(worldTriangles(scene), few, receiver);
            EXPECT_EQ(fewJudge.judge(map, raysToJudge({&map, &fewExpected}, 4096, 3u)).nonTie(), 0u) << offset;
        }
        // Decorrelated source samples (§6.2) and a bumpy receiver (§8, bumps up to 0.4 m).
        const ReceiverHeights heights = randomHeights(receiver, 11u, 0.4);
        const std::vector<glm::dvec3> displaced = displacedSamples(source, receiver, heights);
        const SourceJitter jitter{.seed = 5};
        const HiddenSampleMap bumpyExpected =
            RayCastScene(scene).sample(source, receiver, {.jitter = jitter, .heights = &heights});
        const ExactJudge bumpyJudge(worldTriangles(scene), source, receiver, jitter, &displaced);
        BitmaskStats stats;
        const HiddenSampleMap map = sampler.sample(
            source, receiver, {.strategy = CpuStrategy::RayCast, .jitter = jitter, .heights = &heights}, &stats);
        EXPECT_GT(stats.proxyBlocked, bumpyExpected.blockedCount() / 2) << offset;
        EXPECT_EQ(bumpyJudge.judge(map, raysToJudge({&map, &bumpyExpected}, 4096, 3u)).nonTie(), 0u) << offset;
    }
}

TEST(InnerProxy, StepsAsideWhenAPatchIsInsideAMeshsBounds)
{
    // The source inside a closed statue's bounds (here in the torus's hole, outside the volume,
    // and then inside the tube itself, where every ray is blocked): the statue gets no proxy,
    // other statues keep theirs, and the answer stays the reference's.
    Mesh torus = closedTorus({0.0, 0.0, 0.0}, 1.5, 0.5, 96, 48, 0.1);
    Mesh statue = closedTorus({0.5, 0.5, 3.0}, 0.6, 0.3, 96, 48, 0.1);
    const Scene scene = sceneOf({std::move(torus), std::move(statue)});
    const RayCastScene reference(scene);
    const CpuBitmaskSampler sampler(scene);
    for (const glm::dvec3 corner : {glm::dvec3(-0.3, -0.3, 0.0), glm::dvec3(1.3, -0.2, -0.1)}) {
        const Patch source = patchAt(corner, 0.4, 32);
        const Patch receiver = patchAt({-1.0, -1.0, 5.0}, 3.0, 64);
        BitmaskStats stats;
        const HiddenSampleMap map = sampler.sample(source, receiver, {.strategy = CpuStrategy::RayCast}, &stats);
        const HiddenSampleMap expected = reference.sample(source, receiver);
        const ExactJudge judge(worldTriangles(scene), source, receiver);
        EXPECT_EQ(judge.judge(map, raysToJudge({&map, &expected}, 4096, 5u)).nonTie(), 0u);
        // Only the statue's proxy: its faces alone.
        EXPECT_GT(stats.debug.proxyFaces, 0u);
        BitmaskStats without;
        sampler.sample(source, receiver, {.strategy = CpuStrategy::RayCast, .innerProxy = false}, &without);
        EXPECT_EQ(without.debug.proxyFaces, 0u);
        EXPECT_EQ(without.proxyBlocked, 0u);
    }
    // Both patches inside every statue's bounds: no proxy at all.
    const Patch source = patchAt({-0.3, -0.3, 0.0}, 0.4, 32), receiver = patchAt({-0.2, -0.2, 0.2}, 0.3, 32);
    BitmaskStats stats;
    const HiddenSampleMap map = sampler.sample(source, receiver, {.strategy = CpuStrategy::RayCast}, &stats);
    EXPECT_EQ(stats.debug.proxyFaces, 0u);
    const HiddenSampleMap expected = reference.sample(source, receiver);
    const ExactJudge judge(worldTriangles(scene), source, receiver);
    EXPECT_EQ(judge.judge(map, raysToJudge({&map, &expected}, 4096, 5u)).nonTie(), 0u);
}

TEST(InnerProxy, IsBuiltWhereItPaysAndKeptForUnchangedMeshes)
{
    // Two statues of 4,608 triangles: a one-source call (1,024 rays) builds none, a 1024-source
    // call builds both; after the scene is replaced with a wall moved, they are reused, and
    // after one statue moves, only that one is built again. Every answer is the reference's.
    const auto sceneWith = [](double wallX, double statueX) {
        Mesh wall = quad({float(wallX), -1.0f, 2.5f}, {0.3f, 0.0f, 0.0f}, {0.0f, 0.3f, 0.0f}, "wall");
        return sceneOf({closedTorus({0.2, 0.3, 2.0}, 0.9, 0.45, 64, 36, 0.15),
                        closedTorus({statueX, 1.6, 3.5}, 0.9, 0.45, 64, 36, 0.15), std::move(wall)});
    };
    Scene scene = sceneWith(0.0, 2.2);
    CpuBitmaskSampler sampler(scene);
    const Patch small = patchAt({-0.5, -0.5, 0.0}, 3.0, 32), large = small;
    Patch few = small;
    few.na = few.nb = 1;
    const Patch receiver = patchAt({-1.5, -1.5, 5.5}, 5.0, 32);
    const auto check = [&](const Patch& source, std::size_t built, const char* what) {
        BitmaskStats stats;
        const HiddenSampleMap map = sampler.sample(source, receiver, {.strategy = CpuStrategy::RayCast}, &stats);
        EXPECT_EQ(stats.debug.proxiesBuilt, built) << what;
        const HiddenSampleMap expected = RayCastScene(scene).sample(source, receiver);
        const ExactJudge judge(worldTriangles(scene), source, receiver);
        EXPECT_EQ(judge.judge(map, raysToJudge({&map, &expected}, 2048, 9u)).nonTie(), 0u) << what;
        return stats;
    };
    EXPECT_EQ(check(few, 0, "few rays").debug.proxyFaces, 0u);
    EXPECT_GT(check(large, 2, "first").debug.proxyFaces, 0u);
    EXPECT_GT(check(large, 0, "again").proxyBlocked, 0u);
    scene = sceneWith(0.5, 2.2);
    sampler.setScene(scene);
    EXPECT_GT(check(large, 0, "wall moved").proxyBlocked, 0u);
    scene = sceneWith(0.5, 2.3);
    sampler.setScene(scene);
    EXPECT_GT(check(large, 1, "statue moved").proxyBlocked, 0u);
}

TEST(InnerProxy, CapsCloseOpenMeshes)
{
    // No caps for a closed mesh; an open one with its caps is closed (mod 2), one cap per hole,
    // and its proxy's faces have parity 1 for the capped surface, clear of it by the margin.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const WorldTriangles closed = worldTriangles(sceneOf({closedTorus({0.0, 0.0, 0.0}, 1.0, 0.5, 64, 32, 0.15)}));
    EXPECT_TRUE(boundaryCaps(closed.vertices.data(), closed.size()).empty());
    for (const double offset : {0.0, 1e4, 1e5})
        for (const int holes : {1, 3}) {
            const glm::dvec3 centre(offset, 0.5 * offset, -0.25 * offset);
            const WorldTriangles open = worldTriangles(sceneOf({holedTorus(centre, holes)}));
            EXPECT_FALSE(closedModTwo(open.vertices));
            const std::vector<std::vector<glm::vec3>> caps = boundaryCaps(open.vertices.data(), open.size());
            ASSERT_EQ(caps.size(), std::size_t(holes));
            std::vector<glm::vec3> surface = open.vertices;
            for (const std::vector<glm::vec3>& cap : caps)
                surface.insert(surface.end(), cap.begin(), cap.end());
            EXPECT_TRUE(closedModTwo(surface)) << offset;
            const InnerProxy proxy = buildInnerProxy(open.vertices.data(), open.size(), 16);
            ASSERT_FALSE(proxy.faces.empty()) << offset;
            EXPECT_EQ(proxy.capBoxes.size(), std::size_t(holes));
            WorldTriangles capped;
            capped.vertices = surface;
            capped.instanceOf.assign(surface.size() / 3, 0);
            for (std::size_t f = 0; f < proxy.faces.size(); f += 3) {
                const glm::dvec3 p = (glm::dvec3(proxy.faces[f]) + glm::dvec3(proxy.faces[f + 1]) + glm::dvec3(proxy.faces[f + 2])) / 3.0;
                ASSERT_GE(nearestDistance(capped, p), kInnerMarginMetres) << offset << " face " << f / 3;
                const glm::dvec3 far = p + 100.0 * glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)));
                ASSERT_EQ(crossings(capped, p, far) % 2, 1) << offset << " face " << f / 3;
            }
        }
    // A flat open sheet caps to itself: nothing inside, no proxy.
    const WorldTriangles sheet = worldTriangles(sceneOf({flatSheet(32)}));
    EXPECT_TRUE(buildInnerProxy(sheet.vertices.data(), sheet.size(), 16).faces.empty());
}

TEST(InnerProxy, OpenMeshesKeepTheSamplersExact)
{
    // An open tube along the shaft (rays down its bore meet nothing: its proxy's rays through
    // the caps must be given back) and a torus with holes facing the patches, 32x32 source
    // samples and a 64x64 receiver, at 0, 10 and 100 km: every strategy against the reference,
    // disagreements judged. The proxies answer part of the blocked rays.
    for (const double offset : {0.0, 1e4, 1e5}) {
        const glm::dvec3 o(offset, -0.5 * offset, 0.25 * offset);
        const Scene scene = sceneOf({openTube(o + glm::dvec3(1.0, 1.0, 2.75), 0.7, 2.5, 16, 48), holedTorus(o + glm::dvec3(3.2, 2.6, 3.0), 3)});
        const Patch source = patchAt(o + glm::dvec3(-0.5, -0.5, 0.0), 3.0, 32);
        const Patch receiver = patchAt(o + glm::dvec3(-1.5, -1.5, 5.5), 6.0, 64);
        const HiddenSampleMap expected = RayCastScene(scene).sample(source, receiver);
        ASSERT_GT(expected.blockedCount(), expected.rayCount() / 10);
        ASSERT_LT(expected.blockedCount(), expected.rayCount() * 9 / 10);
        const ExactJudge judge(worldTriangles(scene), source, receiver);
        CpuBitmaskSampler sampler(scene);
        for (const CpuStrategy strategy : {CpuStrategy::Auto, CpuStrategy::RayCast, CpuStrategy::Bitmask}) {
            BitmaskStats stats;
            const HiddenSampleMap map = sampler.sample(source, receiver, {.strategy = strategy}, &stats);
            EXPECT_GT(stats.debug.proxyFaces, 0u) << offset;
            EXPECT_GT(stats.proxyBlocked, expected.blockedCount() / 10) << offset;
            const Verdict v = judge.judge(map, raysToJudge({&map, &expected}, 4096, 3u));
            EXPECT_EQ(v.nonTie(), 0u) << offset << " " << stats.strategy;
        }
        // Decorrelated source samples (§6.2) and a bumpy receiver (§8, bumps up to 0.4 m).
        const ReceiverHeights heights = randomHeights(receiver, 13u, 0.4);
        const std::vector<glm::dvec3> displaced = displacedSamples(source, receiver, heights);
        const SourceJitter jitter{.seed = 7};
        const HiddenSampleMap bumpyExpected = RayCastScene(scene).sample(source, receiver, {.jitter = jitter, .heights = &heights});
        const ExactJudge bumpyJudge(worldTriangles(scene), source, receiver, jitter, &displaced);
        BitmaskStats stats;
        const HiddenSampleMap map = sampler.sample(
            source, receiver, {.strategy = CpuStrategy::RayCast, .jitter = jitter, .heights = &heights}, &stats);
        EXPECT_GT(stats.proxyBlocked, 0u) << offset;
        EXPECT_EQ(bumpyJudge.judge(map, raysToJudge({&map, &bumpyExpected}, 4096, 3u)).nonTie(), 0u) << offset;
    }
    // A tube lying across the source's plane beside it, along x: its ends' caps reach behind
    // the plane (no shadow on it bounds their rays), and rays from the source run down its bore
    // to a low receiver.
    for (const double offset : {0.0, 1e4}) {
        const glm::dvec3 o(-0.25 * offset, offset, 0.5 * offset);
        const Scene scene = sceneOf({openTube(o + glm::dvec3(4.0, 1.0, 0.0), 0.7, 2.6, 16, 48, true)});
        const Patch source = patchAt(o + glm::dvec3(-0.5, -0.5, 0.0), 3.0, 32);
        const Patch receiver = patchAt(o + glm::dvec3(5.5, -1.0, 0.9), 4.0, 64);
        const HiddenSampleMap expected = RayCastScene(scene).sample(source, receiver);
        ASSERT_GT(expected.blockedCount(), expected.rayCount() / 20);
        const ExactJudge judge(worldTriangles(scene), source, receiver);
        CpuBitmaskSampler sampler(scene);
        for (const CpuStrategy strategy : {CpuStrategy::RayCast, CpuStrategy::Bitmask}) {
            BitmaskStats stats;
            const HiddenSampleMap map = sampler.sample(source, receiver, {.strategy = strategy}, &stats);
            EXPECT_GT(stats.proxyBlocked, 0u) << offset;
            EXPECT_EQ(judge.judge(map, raysToJudge({&map, &expected}, 4096, 3u)).nonTie(), 0u) << offset << " " << stats.strategy;
        }
    }
}

TEST(InnerProxy, MeshesWithManyHolesSitOutSmallCalls)
{
    // Eight holes, so eight cap boxes in the shaft: more than an eighth of 32 source samples
    // (kProxyCapBoxesPerSource), so an 8x4 call goes without the proxy, a 32x32 call with it;
    // both answers exact.
    const Scene scene = sceneOf({holedTorus({1.0, 1.0, 2.75}, 8)});
    const Patch source = patchAt({-0.5, -0.5, 0.0}, 3.0, 32), receiver = patchAt({-1.5, -1.5, 5.5}, 6.0, 32);
    Patch few = source;
    few.na = 8, few.nb = 4;
    CpuBitmaskSampler sampler(scene);
    for (const Patch* s : {&source, static_cast<const Patch*>(&few)}) {
        BitmaskStats stats;
        const HiddenSampleMap map = sampler.sample(*s, receiver, {.strategy = CpuStrategy::RayCast}, &stats);
        if (s == &few)
            EXPECT_EQ(stats.debug.proxyFaces, 0u);
        else
            EXPECT_GT(stats.proxyBlocked, 0u);
        const HiddenSampleMap expected = RayCastScene(scene).sample(*s, receiver);
        const ExactJudge judge(worldTriangles(scene), *s, receiver);
        EXPECT_EQ(judge.judge(map, raysToJudge({&map, &expected}, 4096, 3u)).nonTie(), 0u);
    }
}
