// Proofs of invisibility for the PVS bake (safe mode): the planar-region and
// closed-solid arguments of ShaftProof.h, the adaptive search of ShaftSearch.h, and a property
// test: on random cluttered levels, no pair the safe bake culls is seen by dense rays.

#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "TestScenes.h"
#include "visibility/pvs/FirstHitCaster.h"
#include "visibility/pvs/PvsBake.h"
#include "visibility/pvs/PvsObjects.h"
#include "visibility/pvs/PvsReference.h"
#include "visibility/pvs/ShaftProof.h"
#include "visibility/pvs/ShaftSearch.h"

namespace sightline::pvs {
namespace {

using test::addBox;
const auto box = test::boxBounds;

/// A one-sided rectangle in the plane z = z over [x0, x1] x [y0, y1], facing -z, as its own
/// instance (two triangles).
std::size_t addPanel(Scene& scene, const std::string& name, float x0, float x1, float y0, float y1, float z)
{
    Mesh m;
    m.name = name;
    m.positions = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
    m.indices = {0, 2, 1, 0, 3, 2};
    const std::size_t i = scene.addMeshInstance(m);
    scene.instances[i].name = name;
    return i;
}

Quad quad(glm::dvec3 corner, glm::dvec3 u, glm::dvec3 v) { return Quad{corner, u, v}; }

/// A small source square at z = 0 and a receiver square at z = 2 around (x, y): the shaft's
/// cross-section at z = 1 is a square of side `side` around (x, y).
std::pair<Quad, Quad> shaftAround(double x, double y, double side)
{
    return {quad({x - side / 2, y - side / 2, 0.0}, {side, 0, 0}, {0, side, 0}),
            quad({x - side / 2, y - side / 2, 2.0}, {side, 0, 0}, {0, side, 0})};
}

TEST(ShaftProof, ConvexHullKeepsTheCornersInCounterClockwiseOrder)
{
    const std::vector<glm::dvec2> hull = convexHull({{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0.2, 0.7}, {1, 0}});
    ASSERT_EQ(hull.size(), 4u);
    double area = 0.0;
    for (std::size_t i = 0; i < hull.size(); ++i)
        area += hull[i].x * hull[(i + 1) % 4].y - hull[(i + 1) % 4].x * hull[i].y;
    EXPECT_DOUBLE_EQ(area / 2.0, 1.0);   // positive: counter-clockwise
}

TEST(ShaftProof, APanelBlocksTheShaftsWhoseCrossSectionItCovers)
{
    Scene s;
    addPanel(s, "panel", -1.0f, 1.0f, -1.0f, 1.0f, 1.0f);
    const ShaftProver prover(s);
    const auto inside = shaftAround(0.0, 0.0, 0.5);
    EXPECT_TRUE(prover.planeBlocks(0, inside.first, inside.second, {}));
    // Over the panel's edge: some segments pass beside it.
    const auto across = shaftAround(0.9, 0.0, 0.5);
    EXPECT_FALSE(prover.planeBlocks(0, across.first, across.second, {}));
    // Both ends on one side of the panel's plane: nothing is proven.
    const Quad near = quad({-0.1, -0.1, 0.0}, {0.2, 0, 0}, {0, 0.2, 0});
    const Quad alsoNear = quad({-0.1, -0.1, 0.5}, {0.2, 0, 0}, {0, 0.2, 0});
    EXPECT_FALSE(prover.planeBlocks(0, near, alsoNear, {}));
}

TEST(ShaftProof, CoplanarPanelsOfSeveralInstancesAreFusedAcrossTJunctions)
{
    // Left: two panels stacked (cut at y = 0.2); right: one panel. The seam at x = 0 is a
    // T-junction (the left side has a vertex at (0, 0.2), the right does not).
    Scene s;
    addPanel(s, "left_low", -1.0f, 0.0f, -1.0f, 0.2f, 1.0f);
    addPanel(s, "left_high", -1.0f, 0.0f, 0.2f, 1.0f, 1.0f);
    const std::size_t right = addPanel(s, "right", 0.0f, 1.0f, -1.0f, 1.0f, 1.0f);
    const ShaftProver prover(s);
    EXPECT_EQ(prover.regionCount(), 1u);
    const auto seam = shaftAround(0.0, 0.2, 0.5);   // straddles both seams
    for (std::size_t t = 0; t < prover.triangleCount(); ++t)
        EXPECT_TRUE(prover.planeBlocks(t, seam.first, seam.second, {})) << "triangle " << t;
    // The right panel is the target: its triangles are holes, the shaft passes through them.
    const OwnInstances rightIsOwn = [&](std::uint32_t i) { return i == right; };
    EXPECT_FALSE(prover.planeBlocks(0, seam.first, seam.second, rightIsOwn));
    const auto leftOnly = shaftAround(-0.5, 0.2, 0.5);
    EXPECT_TRUE(prover.planeBlocks(0, leftOnly.first, leftOnly.second, rightIsOwn));

    // Without the right panel the left panels' edge at x = 0 is a boundary.
    Scene half;
    addPanel(half, "left_low", -1.0f, 0.0f, -1.0f, 0.2f, 1.0f);
    addPanel(half, "left_high", -1.0f, 0.0f, 0.2f, 1.0f, 1.0f);
    const ShaftProver halfProver(half);
    EXPECT_FALSE(halfProver.planeBlocks(0, seam.first, seam.second, {}));
}

TEST(ShaftProof, AHoleInARegionIsABoundary)
{
    // A frame around a 0.2 m window at the origin, made of four panels sharing corners.
    Scene s;
    addPanel(s, "bottom", -1.0f, 1.0f, -1.0f, -0.1f, 1.0f);
    addPanel(s, "top", -1.0f, 1.0f, 0.1f, 1.0f, 1.0f);
    addPanel(s, "left", -1.0f, -0.1f, -0.1f, 0.1f, 1.0f);
    addPanel(s, "right", 0.1f, 1.0f, -0.1f, 0.1f, 1.0f);
    const ShaftProver prover(s);
    const auto overHole = shaftAround(0.0, 0.0, 0.5);   // covers the window: rays pass through it
    for (std::size_t t = 0; t < prover.triangleCount(); ++t)
        EXPECT_FALSE(prover.planeBlocks(t, overHole.first, overHole.second, {}));
    const auto beside = shaftAround(0.5, 0.0, 0.3);
    EXPECT_TRUE(prover.planeBlocks(0, beside.first, beside.second, {}));
}

TEST(ShaftProof, ABallIsInsideAClosedBoxOnlyWhenItClearsEveryFace)
{
    Scene s;
    addBox(s, "a", {0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f});
    addBox(s, "b", {3.0f, 0.0f, 0.0f}, {4.0f, 2.0f, 1.0f});
    addPanel(s, "open", 0.0f, 1.0f, 0.0f, 1.0f, 5.0f);
    const ShaftProver prover(s);
    EXPECT_EQ(prover.solidCount(), 2u);
    EXPECT_TRUE(prover.isSolid(0));
    EXPECT_FALSE(prover.isSolid(prover.triangleCount() - 1));   // a lone panel is no solid
    EXPECT_TRUE(prover.ballInsideSolid(0, {0.5, 0.5, 0.5}, 0.4));
    EXPECT_FALSE(prover.ballInsideSolid(0, {0.5, 0.5, 0.5}, 0.5));   // touches the faces
    EXPECT_FALSE(prover.ballInsideSolid(0, {0.5, 0.5, 0.5}, 0.6));
    EXPECT_FALSE(prover.ballInsideSolid(0, {2.0, 0.5, 0.5}, 0.1));   // outside, between the boxes
    EXPECT_TRUE(prover.ballInsideSolid(12, {3.5, 1.0, 0.5}, 0.4));   // the second box's own solid
}

TEST(ShaftProof, TheConnectedPartsOfAClosedMeshAreSolidsOfTheirOwn)
{
    // One mesh of two separate closed boxes (a chair's legs): two solids, each with its own bounds.
    Mesh two = test::closedBox();
    const std::size_t n = two.positions.size();
    for (std::size_t k = 0; k < n; ++k)
        two.positions.push_back(two.positions[k] + glm::vec3(5.0f, 0.0f, 0.0f));
    const std::size_t indices = two.indices.size();
    for (std::size_t k = 0; k < indices; ++k)
        two.indices.push_back(two.indices[k] + std::uint32_t(n));
    Scene s;
    s.addMeshInstance(two);
    const ShaftProver prover(s);
    EXPECT_EQ(prover.solidCount(), 2u);
    EXPECT_FLOAT_EQ(prover.solidBounds(0).max.x, 0.5f);
    EXPECT_FLOAT_EQ(prover.solidBounds(12).min.x, 4.5f);
}

// ---------------------------------------------------------------------------- the search

struct Searcher {
    Scene scene;
    std::vector<PvsObject> objects;
    std::vector<std::int32_t> objectOf;
    std::unique_ptr<FirstHitCaster> caster;
    std::unique_ptr<ShaftProver> prover;
    std::unique_ptr<ShaftSearch> search;

    explicit Searcher(Scene s) : scene(std::move(s))
    {
        objects = sceneObjects(scene, false);
        objectOf.assign(scene.instances.size(), -1);
        for (std::size_t o = 0; o < objects.size(); ++o)
            for (std::uint32_t i : objects[o].instances)
                objectOf[i] = std::int32_t(o);
        caster = std::make_unique<FirstHitCaster>(scene);
        prover = std::make_unique<ShaftProver>(scene);
        search = std::make_unique<ShaftSearch>(*caster, *prover, objectOf);
    }
    Reach reach(const Bounds& cell, std::size_t object, int maxShafts = 4096)
    {
        SearchTarget target;
        target.box = objects[object].bounds;
        target.object = std::int32_t(object);
        target.own = [&, object](std::uint32_t i) { return objectOf[i] == std::int32_t(object); };
        SearchLimits limits;
        limits.maxShafts = maxShafts;
        limits.smallestGap = 0.01;
        return search->search(cell, target, limits, 1, nullptr);
    }
};

TEST(ShaftSearch, AWallOfTouchingSlabsIsProvenToHideWhatIsBehindIt)
{
    // Three slabs side by side (no gap) between the cell and the target: no single slab covers
    // the shaft, the fused front faces do, and every sub-shaft is proven. (Coordinates exact in
    // binary: slabs placed at -0.2 would meet at two different floats, and the crack between
    // them, 1e-8 m wide, is a real opening no proof may close.)
    Scene s;
    addBox(s, "slab_a", {-3.0f, -1.0f, 1.0f}, {-0.25f, 2.0f, 1.25f});
    addBox(s, "slab_b", {-0.25f, -1.0f, 1.0f}, {0.5f, 2.0f, 1.25f});
    addBox(s, "slab_c", {0.5f, -1.0f, 1.0f}, {3.0f, 2.0f, 1.25f});
    addBox(s, "target", {-0.5f, 0.0f, 3.0f}, {0.7f, 1.0f, 3.2f});
    Searcher searcher(std::move(s));
    EXPECT_EQ(searcher.reach(box({-0.5f, 0.0f, -1.0f}, {0.7f, 1.0f, 0.0f}), 3), Reach::Hidden);
}

TEST(ShaftSearch, AGapBetweenSlabsIsFoundAndLeavesNoProof)
{
    Scene s;
    addBox(s, "slab_a", {-3.0f, -1.0f, 1.0f}, {0.1f, 2.0f, 1.2f});
    addBox(s, "slab_c", {0.11f, -1.0f, 1.0f}, {3.0f, 2.0f, 1.2f});   // a 1 cm gap
    addBox(s, "target", {-0.5f, 0.0f, 3.0f}, {0.7f, 1.0f, 3.2f});
    Searcher searcher(std::move(s));
    EXPECT_NE(searcher.reach(box({-0.5f, 0.0f, -1.0f}, {0.7f, 1.0f, 0.0f}), 2), Reach::Hidden);
}

TEST(ShaftSearch, AThickPillarSeenAcrossItsEdgesIsProvenByItsInside)
{
    // A square pillar between cell and target: segments cross its front face or its side faces;
    // no face alone covers the shaft, the solid does (ball argument).
    Scene s;
    addBox(s, "pillar", {-1.0f, -1.0f, 1.0f}, {1.2f, 1.2f, 3.0f});
    addBox(s, "target", {0.0f, 0.0f, 4.0f}, {0.2f, 0.2f, 4.2f});
    Searcher searcher(std::move(s));
    EXPECT_EQ(searcher.reach(box({0.0f, 0.0f, 0.0f}, {0.2f, 0.2f, 0.2f}), 1), Reach::Hidden);
}

/// A closed block [-h, h]^2 x [z0, z1] with a square tunnel [-t, t]^2 through it along z (genus
/// one, outward wound): 32 triangles.
Mesh tunnelBlock(float h, float t, float z0, float z1)
{
    Mesh m;
    m.name = "tunnel";
    auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {   // counter-clockwise seen from outside
        const std::uint32_t base = std::uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {a, b, c, d});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    };
    const float o[2] = {-h, h}, i[2] = {-t, t};
    // Front (z0, facing -z) and back (z1, facing +z) rings: four quads each around the hole.
    for (int side = 0; side < 2; ++side) {
        const float z = side ? z1 : z0;
        auto ring = [&](glm::vec2 a, glm::vec2 b, glm::vec2 c, glm::vec2 d) {
            if (side)
                quad({a, z}, {b, z}, {c, z}, {d, z});
            else
                quad({d, z}, {c, z}, {b, z}, {a, z});
        };
        ring({o[0], o[0]}, {o[1], o[0]}, {i[1], i[0]}, {i[0], i[0]});   // bottom
        ring({o[1], o[0]}, {o[1], o[1]}, {i[1], i[1]}, {i[1], i[0]});   // right
        ring({o[1], o[1]}, {o[0], o[1]}, {i[0], i[1]}, {i[1], i[1]});   // top
        ring({o[0], o[1]}, {o[0], o[0]}, {i[0], i[0]}, {i[0], i[1]});   // left
    }
    // Outer sides (facing out) and the tunnel's walls (facing into the tunnel).
    quad({o[0], o[0], z0}, {o[1], o[0], z0}, {o[1], o[0], z1}, {o[0], o[0], z1});   // -y
    quad({o[1], o[0], z0}, {o[1], o[1], z0}, {o[1], o[1], z1}, {o[1], o[0], z1});   // +x
    quad({o[1], o[1], z0}, {o[0], o[1], z0}, {o[0], o[1], z1}, {o[1], o[1], z1});   // +y
    quad({o[0], o[1], z0}, {o[0], o[0], z0}, {o[0], o[0], z1}, {o[0], o[1], z1});   // -x
    quad({i[0], i[0], z1}, {i[1], i[0], z1}, {i[1], i[0], z0}, {i[0], i[0], z0});   // tunnel floor, +y
    quad({i[1], i[0], z1}, {i[1], i[1], z1}, {i[1], i[1], z0}, {i[1], i[0], z0});   // tunnel right, -x
    quad({i[1], i[1], z1}, {i[0], i[1], z1}, {i[0], i[1], z0}, {i[1], i[1], z0});   // tunnel top, -y
    quad({i[0], i[1], z1}, {i[0], i[0], z1}, {i[0], i[0], z0}, {i[0], i[1], z0});   // tunnel left, +x
    return m;
}

TEST(ShaftSearch, ATunnelThroughASolidIsNeverProvenClosed)
{
    // A 0.5 m thick block with a 2 cm square tunnel: the target behind it is seen only along the
    // tunnel. The block is one closed solid (its own check says so) whose inside surrounds the
    // tunnel: a ball argument with too large a ball would close it.
    Scene s;
    const Mesh block = tunnelBlock(2.0f, 0.01f, 1.0f, 1.5f);
    ASSERT_TRUE(closedAndOutward(block));
    s.addMeshInstance(block);
    addBox(s, "target", {-0.5f, -0.5f, 3.0f}, {0.5f, 0.5f, 3.2f});
    Searcher searcher(std::move(s));
    EXPECT_TRUE(searcher.prover->isSolid(0));
    EXPECT_NE(searcher.reach(box({-0.3f, -0.3f, -0.6f}, {0.3f, 0.3f, 0.0f}), 1, 1 << 14), Reach::Hidden);
    // Sealed (no tunnel: a plain box) it is proven.
    Scene sealed;
    addBox(sealed, "block", {-2.0f, -2.0f, 1.0f}, {2.0f, 2.0f, 1.5f});
    addBox(sealed, "target", {-0.5f, -0.5f, 3.0f}, {0.5f, 0.5f, 3.2f});
    Searcher sealedSearcher(std::move(sealed));
    EXPECT_EQ(sealedSearcher.reach(box({-0.3f, -0.3f, -0.6f}, {0.3f, 0.3f, 0.0f}), 1), Reach::Hidden);
}

/// A random cluttered level: a floor; two walls across it (z = 4 and z = 8) of slabs of random
/// heights that touch (on exactly equal coordinates), leave slits of 1.6-3 cm or doorways; boxes
/// and free panels beyond the first wall; the view cells before it. Most of what lies beyond is
/// seen, if at all, through a slit, a doorway or over a low slab: where a wrong proof would show.
Scene clutter(std::uint64_t seed, std::vector<Bounds>& cells)
{
    std::uint64_t state = seed;
    auto unit = [&] {
        state = mixSeed(state, 77);
        return float(state >> 40) * (1.0f / 16777216.0f);
    };
    auto grid = [](float v) { return std::round(v * 64.0f) / 64.0f; };   // exact binary coordinates
    Scene s;
    addBox(s, "floor", {0.0f, -0.25f, 0.0f}, {12.0f, 0.0f, 12.0f});
    for (int w = 0; w < 2; ++w) {
        const float z = 4.0f * float(w + 1);
        float x = 0.0f;
        int k = 0;
        while (x < 12.0f) {
            const float end = std::min(12.0f, grid(x + 0.5f + 2.5f * unit()));
            const float height = unit() < 0.25f ? 1.25f : 2.5f;
            addBox(s, "wall" + std::to_string(w) + "_" + std::to_string(k++), {x, 0.0f, z}, {end, height, z + 0.25f});
            const float pick = unit();
            x = end + (pick < 0.4f ? 0.0f : pick < 0.8f ? (1.0f + std::floor(2.0f * unit())) / 64.0f : 0.875f);
        }
    }
    for (int b = 0; b < 24; ++b) {
        const glm::vec3 at(grid(11.0f * unit()), 0.0f, grid(4.5f + 7.0f * unit()));
        addBox(s, "box" + std::to_string(b), at, at + glm::vec3(grid(0.2f + 0.6f * unit()), grid(0.2f + 1.5f * unit()), grid(0.2f + 0.6f * unit())));
    }
    for (int p = 0; p < 8; ++p) {
        const float x = 11.0f * unit(), y = 2.0f * unit(), z = 4.5f + 7.0f * unit();
        addPanel(s, "panel" + std::to_string(p), x, x + 0.3f + unit(), y, y + 0.2f + unit(), z);
    }
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 at(0.5f + 10.0f * unit(), 0.1f, 0.3f + 2.5f * unit());
        cells.push_back(box(at, at + glm::vec3(1.0f, 1.6f, 0.6f)));
    }
    return s;
}

TEST(PvsSafe, NothingTheSafeBakeCullsIsSeenByDenseRays)
{
    // The safe mode culls a pair only with a proof; dense first-hit rays from many points of the
    // cell to many points of every object must never see a culled object. A proof that skipped a
    // hole, an edge, the target's own triangles or a solid's outside would show here.
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
        std::vector<Bounds> cells;
        const Scene scene = clutter(seed, cells);
        PvsSettings settings;
        settings.safe = true;
        settings.fineShafts = 256;
        const PvsBaker baker(scene, cells, sceneObjects(scene, false), "5afe", settings);
        PvsStats stats;
        PvsData data;
        data.sceneSha256 = "5afe";
        data.cells = cells;
        data.objects = baker.objects();
        data.rows = baker.bake({}, {}, &stats);
        ReferenceSettings reference;
        reference.cellPoints = 216;
        reference.objectPoints = 256;
        reference.views = 0;
        const AccuracyReport report = measureAccuracy(scene, data, reference);
        EXPECT_GT(stats.provenHidden, 0u) << "seed " << seed;   // it does cull
        EXPECT_EQ(report.missed, 0u) << "seed " << seed;
        EXPECT_GT(report.referenceVisible, 0u);
    }
}

} // namespace
} // namespace sightline::pvs
