// The open space's proof (pvs/OpenSpace.h): sealed rooms, lines through two doorways, and dense
// first-hit rays that must never see what it hides.

#include <cmath>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include "TestScenes.h"
#include "visibility/pvs/FirstHitCaster.h"
#include "visibility/pvs/OpenSpace.h"
#include "visibility/pvs/PvsBake.h"
#include "visibility/pvs/PvsObjects.h"
#include "visibility/pvs/PvsReference.h"
#include "visibility/pvs/ShaftProof.h"
#include "visibility/pvs/ShaftSearch.h"

namespace sightline::pvs {
namespace {

using test::addBox;
const auto box = test::boxBounds;

/// A shell of 0.2 m slabs around [lo, hi]: floor, ceiling and the walls along x (the walls
/// across x come from addWall).
void addShell(Scene& s, const std::string& name, glm::vec3 lo, glm::vec3 hi)
{
    const float t = 0.2f;
    addBox(s, name + "_floor", {lo.x - t, lo.y - t, lo.z - t}, {hi.x + t, lo.y, hi.z + t});
    addBox(s, name + "_ceiling", {lo.x - t, hi.y, lo.z - t}, {hi.x + t, hi.y + t, hi.z + t});
    addBox(s, name + "_south", {lo.x - t, lo.y, lo.z - t}, {hi.x + t, hi.y, lo.z});
    addBox(s, name + "_north", {lo.x - t, lo.y, hi.z}, {hi.x + t, hi.y, hi.z + t});
}

/// A wall across x at [x, x + 0.2] from z0 to z1, 3 m high, with a doorway (1 m wide, 2 m high)
/// at z in [door, door + 1] (none when door < z0).
void addWall(Scene& s, const std::string& name, float x, float z0, float z1, float door)
{
    if (door < z0) {
        addBox(s, name, {x, 0.0f, z0}, {x + 0.2f, 3.0f, z1});
        return;
    }
    addBox(s, name + "_a", {x, 0.0f, z0}, {x + 0.2f, 3.0f, door});
    addBox(s, name + "_b", {x, 0.0f, door + 1.0f}, {x + 0.2f, 3.0f, z1});
    addBox(s, name + "_top", {x, 2.0f, door}, {x + 0.2f, 3.0f, door + 1.0f});
}

struct Built {
    Scene scene;
    std::vector<PvsObject> objects;
    std::unique_ptr<ShaftProver> prover;
    std::unique_ptr<OpenSpace> space;
};

Built build(Scene scene, const std::vector<Bounds>& sources)
{
    Built b;
    b.scene = std::move(scene);
    b.objects = sceneObjects(b.scene, false);
    b.prover = std::make_unique<ShaftProver>(b.scene);
    const WorldTriangles world = worldTriangles(b.scene);
    std::vector<std::vector<glm::vec3>> soups(b.objects.size());
    for (std::size_t t = 0; t < world.size(); ++t)
        soups[world.instanceOf[t]].insert(soups[world.instanceOf[t]].end(), &world.vertices[3 * t], &world.vertices[3 * t] + 3);
    b.space = std::make_unique<OpenSpace>(*b.prover, b.scene.bounds(), soups, sources, OpenSpaceLimits{.threads = 2});
    return b;
}

bool hidden(const std::vector<std::uint8_t>& bits, std::size_t o) { return (bits[o / 8] >> (o % 8)) & 1u; }

std::size_t named(const std::vector<PvsObject>& objects, const std::string& name)
{
    for (std::size_t o = 0; o < objects.size(); ++o)
        if (objects[o].name == name)
            return o;
    ADD_FAILURE() << "no object " << name;
    return 0;
}

/// A hall (x in [0, 6]) and a closet (x in [6.2, 8]) behind a wall with a doorway at z in
/// [door, door + 1] (none when door < 0); a crate in each.
Scene hallAndCloset(float door)
{
    Scene s;
    addShell(s, "shell", {0.0f, 0.0f, 0.0f}, {8.0f, 3.0f, 4.0f});
    addWall(s, "west", -0.2f, 0.0f, 4.0f, -1.0f);
    addWall(s, "mid", 6.0f, 0.0f, 4.0f, door);
    addWall(s, "east", 8.0f, 0.0f, 4.0f, -1.0f);
    addBox(s, "crate_hall", {2.0f, 0.0f, 1.0f}, {2.8f, 0.8f, 1.8f});
    addBox(s, "crate_closet", {7.0f, 0.0f, 1.5f}, {7.5f, 0.5f, 2.0f});
    return s;
}

TEST(OpenSpace, ASealedRoomIsHiddenFromEverythingOutsideIt)
{
    const Bounds hall = box({0.5f, 0.5f, 0.5f}, {1.0f, 1.5f, 1.0f});
    const Bounds closet = box({6.5f, 1.0f, 2.5f}, {7.0f, 1.5f, 3.0f});
    const Built b = build(hallAndCloset(-1.0f), {hall, closet});
    const auto fromHall = b.space->hiddenFrom(hall);
    const auto fromCloset = b.space->hiddenFrom(closet);
    EXPECT_TRUE(hidden(fromHall, named(b.objects, "crate_closet")));
    EXPECT_FALSE(hidden(fromHall, named(b.objects, "crate_hall")));
    EXPECT_FALSE(hidden(fromHall, named(b.objects, "mid")));     // its hall side
    EXPECT_TRUE(hidden(fromHall, named(b.objects, "east")));     // the closet's far wall
    EXPECT_TRUE(hidden(fromCloset, named(b.objects, "crate_hall")));
    EXPECT_TRUE(hidden(fromCloset, named(b.objects, "west")));
    EXPECT_FALSE(hidden(fromCloset, named(b.objects, "crate_closet")));
    EXPECT_GE(b.space->stats().parts, 2u);
    // A door in the middle wall joins them: nothing is hidden for being sealed off any more.
    const Built o = build(hallAndCloset(1.5f), {hall});
    EXPECT_FALSE(hidden(o.space->hiddenFrom(hall), named(o.objects, "crate_closet")));
}

TEST(OpenSpace, ARoomNoLineThroughTheDoorwaysReachesIsHidden)
{
    // Four rooms in a row (x in [0, 4], [4.2, 8.2], [8.4, 12.4], [12.6, 16.6]) behind doorways at z
    // in [0.2, 1.2], then [2, 3], then [0.2, 1.2] again. A line from the cell (z in [0.2, 0.6])
    // through the first two climbs in z (at most 0.36 per metre), so it cannot come down to the
    // third: room D is hidden, though each wall alone lets the cell's lines through its doorway.
    // Room C's far corner (z in [3.5, 3.9] at x >= 11.6) is on lines through the first two and is
    // seen. (The proof answers per box of open space: room C's near corner, which those lines miss
    // too, shares its box with the far one.)
    Scene s;
    addShell(s, "shell", {0.0f, 0.0f, 0.0f}, {16.6f, 3.0f, 4.0f});
    addWall(s, "west", -0.2f, 0.0f, 4.0f, -1.0f);
    addWall(s, "wall1", 4.0f, 0.0f, 4.0f, 0.2f);
    addWall(s, "wall2", 8.2f, 0.0f, 4.0f, 2.0f);
    addWall(s, "wall3", 12.4f, 0.0f, 4.0f, 0.2f);
    addWall(s, "east", 16.6f, 0.0f, 4.0f, -1.0f);
    addBox(s, "crate_c_far", {11.6f, 0.0f, 3.5f}, {12.2f, 0.6f, 3.9f});
    addBox(s, "crate_d", {14.0f, 0.0f, 1.5f}, {14.6f, 0.6f, 2.1f});
    const Bounds cell = box({1.0f, 0.5f, 0.2f}, {1.4f, 1.5f, 0.6f});
    const Built b = build(std::move(s), {cell});
    const auto fromCell = b.space->hiddenFrom(cell);
    EXPECT_TRUE(b.space->stats().portalVis);
    EXPECT_EQ(b.space->stats().parts, 1u);   // joined: the flood alone would hide nothing
    EXPECT_TRUE(hidden(fromCell, named(b.objects, "crate_d")));
    EXPECT_TRUE(hidden(fromCell, named(b.objects, "east")));
    EXPECT_FALSE(hidden(fromCell, named(b.objects, "crate_c_far")));
    EXPECT_FALSE(hidden(fromCell, named(b.objects, "wall2_a")));
    EXPECT_FALSE(hidden(fromCell, named(b.objects, "wall3_b")));
}

/// Rooms in a row along x with doorways and slits of 1.6-3 cm in their walls (slabs on exact
/// binary coordinates that touch or leave a gap), crates on the floors, cells in each room: where
/// a leak the proof missed would show.
Scene rooms(std::uint64_t seed, std::vector<Bounds>& cells, glm::vec3 offset = glm::vec3(0.0f))
{
    std::uint64_t state = seed;
    auto unit = [&] {
        state = mixSeed(state, 91);
        return float(state >> 40) * (1.0f / 16777216.0f);
    };
    auto grid = [](float v) { return std::round(v * 64.0f) / 64.0f; };
    Scene s;
    const int count = 4;
    const float length = 4.0f;
    addShell(s, "shell", {0.0f, 0.0f, 0.0f}, {count * (length + 0.25f), 3.0f, 4.0f});
    addWall(s, "west", -0.2f, 0.0f, 4.0f, -1.0f);
    for (int r = 0; r < count; ++r) {
        const float x0 = float(r) * (length + 0.25f), x1 = x0 + length;
        // The wall at the room's east end: slabs across z, touching or apart by a slit or a door.
        float z = 0.0f;
        int k = 0;
        while (z < 4.0f) {
            const float end = std::min(4.0f, grid(z + 0.4f + 1.5f * unit()));
            addBox(s, "wall" + std::to_string(r) + "_" + std::to_string(k++), {x1, 0.0f, z}, {x1 + 0.25f, 3.0f, end});
            const float pick = unit();
            z = end + (r == count - 1 || pick < 0.5f ? 0.0f : pick < 0.8f ? (1.0f + std::floor(2.0f * unit())) / 64.0f : 0.75f);
        }
        for (int c = 0; c < 3; ++c) {
            const glm::vec3 at(grid(x0 + 0.2f + (length - 1.0f) * unit()), 0.0f, grid(0.2f + 3.0f * unit()));
            addBox(s, "crate" + std::to_string(r) + "_" + std::to_string(c), at, at + glm::vec3(0.5f, grid(0.2f + unit()), 0.5f));
        }
        const glm::vec3 at(x0 + 0.3f + 2.5f * unit(), 0.3f, 0.3f + 2.8f * unit());
        cells.push_back(box(offset + at, offset + at + glm::vec3(0.6f, 1.2f, 0.6f)));
    }
    for (Instance& instance : s.instances)
        instance.transform = glm::translate(glm::mat4(1.0f), offset) * instance.transform;
    return s;
}

TEST(OpenSpace, NothingItHidesIsSeenByDenseRays)
{
    // Seed 5 kilometres from the origin (slabs on 1/64 m stay exact floats there).
    std::size_t cellPairsApart = 0;
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        std::vector<Bounds> cells;
        Scene scene = rooms(seed, cells, seed == 5 ? glm::vec3(12000.0f, 0.0f, -8000.0f) : glm::vec3(0.0f));
        const Built b = build(scene, cells);
        PvsData data;
        data.sceneSha256 = "0be5";
        data.cells = cells;
        data.objects = b.objects;
        data.rows = VisibilityRows(cells.size(), b.objects.size());
        std::size_t culled = 0;
        for (std::size_t c = 0; c < cells.size(); ++c) {
            const auto bits = b.space->hiddenFrom(cells[c]);
            for (std::size_t o = 0; o < b.objects.size(); ++o) {
                data.rows.set(c, o, !hidden(bits, o));
                culled += hidden(bits, o);
            }
        }
        ReferenceSettings reference;
        reference.cellPoints = 216;
        reference.objectPoints = 256;
        reference.views = 0;
        const AccuracyReport report = measureAccuracy(b.scene, data, reference);
        EXPECT_GT(culled, 0u) << "seed " << seed;
        EXPECT_GT(report.referenceVisible, 0u);
        EXPECT_EQ(report.missed, 0u) << "seed " << seed;
        EXPECT_EQ(report.edgeMissed, 0u) << "seed " << seed;
        // Cell to cell: no segment between two cells it calls apart is free.
        const FirstHitCaster caster(b.scene);
        for (std::size_t c = 0; c < cells.size(); ++c) {
            const std::vector<char> reach = b.space->reachableFrom(cells[c]);
            ASSERT_FALSE(reach.empty());
            for (std::size_t d = 0; d < cells.size(); ++d) {
                if (!b.space->hides(reach, cells[d]))
                    continue;
                ++cellPairsApart;
                const auto from = boxPoints(cells[c], 64, 2 * c + 1), to = boxPoints(cells[d], 64, 2 * d);
                for (const glm::vec3& p : from)
                    for (const glm::vec3& q : to)
                        ASSERT_GE(caster.cast(p, q - p, 1.0f).instance, 0) << "seed " << seed << " cells " << c << " " << d;
            }
        }
    }
    EXPECT_GT(cellPairsApart, 0u);
}

TEST(OpenSpace, TheBakeCullsWhatItProvesInBothModes)
{
    const Scene s = hallAndCloset(-1.0f);
    const std::vector<Bounds> cells = {box({0.5f, 0.5f, 0.5f}, {1.0f, 1.5f, 1.0f})};
    const auto objects = sceneObjects(s, false);
    for (bool safe : {true, false}) {
        PvsSettings settings;
        settings.safe = safe;
        PvsStats stats;
        const VisibilityRows rows = PvsBaker(s, cells, objects, "c105", settings).bake({}, {}, &stats);
        EXPECT_FALSE(rows.visible(0, named(objects, "crate_closet"))) << "safe " << safe;
        EXPECT_FALSE(rows.visible(0, named(objects, "east"))) << "safe " << safe;
        EXPECT_TRUE(rows.visible(0, named(objects, "mid"))) << "safe " << safe;
        EXPECT_GE(stats.spaceHidden, 2u) << "safe " << safe;
    }
    // Cell to cell, a cell in the closet: apart.
    const std::vector<Bounds> twoCells = {cells[0], box({6.5f, 1.0f, 2.5f}, {7.0f, 1.5f, 3.0f})};
    for (bool safe : {true, false}) {
        PvsSettings settings;
        settings.safe = safe;
        PvsStats stats;
        const VisibilityRows rows = PvsBaker(s, twoCells, objects, "c105", settings).bakeCellRows({}, {}, &stats);
        EXPECT_FALSE(rows.visible(0, 1)) << "safe " << safe;
        EXPECT_FALSE(rows.visible(1, 0)) << "safe " << safe;
        EXPECT_TRUE(rows.visible(1, 1));
        EXPECT_EQ(stats.spaceHidden, 2u) << "safe " << safe;
    }
}

TEST(OpenSpace, TriangleBoxOverlapIsClosedAndSeparatesByEveryAxis)
{
    const OpenSpace::Box unit{glm::dvec3(0.0), glm::dvec3(1.0)};
    // Touching a face, an edge, a corner: met (closed).
    EXPECT_TRUE(triangleMeetsBox({1.0, 0.2, 0.2}, {2.0, 0.2, 0.2}, {1.0, 0.8, 0.8}, unit, 0.0));
    EXPECT_TRUE(triangleMeetsBox({1.0, 1.0, 0.5}, {2.0, 1.0, 0.5}, {2.0, 2.0, 0.5}, unit, 0.0));
    EXPECT_TRUE(triangleMeetsBox({1.0, 1.0, 1.0}, {2.0, 1.0, 1.0}, {1.0, 2.0, 1.0}, unit, 0.0));
    // Apart along a box axis, along the triangle's normal, along an edge cross product.
    EXPECT_FALSE(triangleMeetsBox({1.1, 0.0, 0.0}, {2.0, 0.0, 0.0}, {1.1, 1.0, 1.0}, unit, 0.0));
    EXPECT_FALSE(triangleMeetsBox({1.6, 0.0, 0.0}, {0.0, 1.6, 0.0}, {0.0, 0.0, 3.2}, {glm::dvec3(0.0), glm::dvec3(0.5)}, 0.0));
    EXPECT_FALSE(triangleMeetsBox({1.5, -0.5, 0.5}, {-0.5, 1.5, 0.5}, {1.5, -0.5, 0.6}, {glm::dvec3(0.0), glm::dvec3(0.4)}, 0.0));
    // The margin grows the box.
    EXPECT_TRUE(triangleMeetsBox({1.1, 0.0, 0.0}, {2.0, 0.0, 0.0}, {1.1, 1.0, 1.0}, unit, 0.2));
}

} // namespace
} // namespace sightline::pvs
