// Leaf-to-leaf visibility for Quake levels: the BSP reader and writer against an engine's reading
// of the format (tests/support/EngineBspReader.h, written separately from the spec), the portals
// rebuilt from the tree, and the rows of the portal flow against the witness search, on voxel
// levels whose right answer is known and on an original Quake level.

#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <sstream>

#include "EngineBspReader.h"
#include "VoxelBsp.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "visibility/bsp/BspPortals.h"
#include "visibility/bsp/LeafWitness.h"
#include "visibility/bsp/PortalVis.h"
#include "visibility/bsp/QuakeBsp.h"

using namespace sightline;
using namespace sightline::bsp;
using test::BspVersion;
using test::makeVoxelLevel;
using test::VoxelLevel;

namespace {

constexpr BspVersion kVersions[] = {BspVersion::Bsp29, BspVersion::Bsp2};

void carve(VoxelLevel& level, int x0, int x1, int y0, int y1, int z0, int z1, int contents = test::kContentsEmpty)
{
    for (int z = z0; z <= z1; ++z)
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x)
                level.at(x, y, z) = contents;
}

struct Baked {
    test::VoxelBsp voxels;
    QuakeBsp level;
    std::vector<LeafPortal> tree, open;
    pvs::VisibilityRows rows;
};

Baked bake(const VoxelLevel& voxels, BspVersion version, bool clearLiquids = true)
{
    Baked b;
    b.voxels = test::voxelBsp(voxels, version);
    b.level = readQuakeBsp(b.voxels.bytes, "voxel level");
    b.tree = treePortals(b.level);
    b.open = openPortals(b.level, clearLiquids);
    b.rows = portalVis(b.level, b.open, {.threads = 2});
    return b;
}

int leafOf(const Baked& b, const VoxelLevel& v, int x, int y, int z) { return b.voxels.leafOfVoxel[v.index(x, y, z)]; }

/// Every non-solid leaf whose voxels all lie in the box.
std::set<int> leavesIn(const Baked& b, const VoxelLevel& v, int x0, int x1, int y0, int y1, int z0, int z1)
{
    std::set<int> inside, outside;
    for (int z = 0; z < v.nz; ++z)
        for (int y = 0; y < v.ny; ++y)
            for (int x = 0; x < v.nx; ++x) {
                const int leaf = leafOf(b, v, x, y, z);
                if (leaf == 0)
                    continue;
                const bool in = x >= x0 && x <= x1 && y >= y0 && y <= y1 && z >= z0 && z <= z1;
                (in ? inside : outside).insert(leaf);
            }
    std::set<int> only;
    for (int leaf : inside)
        if (!outside.count(leaf))
            only.insert(leaf);
    return only;
}

bool sees(const pvs::VisibilityRows& rows, int a, int b) { return rows.visible(std::size_t(a) - 1, std::size_t(b) - 1); }

/// The witness search finds nothing the rows cull (the rows' safety, searched hard).
void expectNoWitnessedCull(const Baked& b, bool clearLiquids = true)
{
    const WitnessCount culled = searchWitnesses(b.level, b.tree, b.rows, true,
                                                {.segmentsPerPair = 256, .clearLiquids = clearLiquids, .threads = 2});
    EXPECT_EQ(culled.witnessed, 0u) << "first witnessed cull: leaves " << (culled.examples.empty() ? 0 : culled.examples[0].first)
                                    << " and " << (culled.examples.empty() ? 0 : culled.examples[0].second);
}

} // namespace

TEST(QuakeVis, ReadsTheTreeAnEngineReads)
{
    VoxelLevel v = makeVoxelLevel(8, 6, 5);
    carve(v, 1, 3, 1, 4, 1, 3);
    carve(v, 4, 4, 2, 2, 1, 2);
    carve(v, 5, 6, 1, 4, 1, 3);
    carve(v, 5, 6, 1, 4, 1, 1, test::kContentsWater);
    for (BspVersion version : kVersions) {
        const test::VoxelBsp built = test::voxelBsp(v, version);
        const QuakeBsp level = readQuakeBsp(built.bytes, "voxel level");
        const test::EngineBsp engine = test::readEngineBsp(built.bytes);
        EXPECT_EQ(level.format, version == BspVersion::Bsp29 ? BspFormat::Bsp29 : BspFormat::Bsp2);
        EXPECT_EQ(level.visleafs, built.visleafs);
        ASSERT_EQ(level.leaves.size(), engine.leafContents.size());
        for (std::size_t l = 0; l < level.leaves.size(); ++l)
            EXPECT_EQ(level.leaves[l].contents, engine.leafContents[l]);
        for (int z = 0; z < v.nz; ++z)
            for (int y = 0; y < v.ny; ++y)
                for (int x = 0; x < v.nx; ++x) {
                    const glm::dvec3 centre = (glm::dvec3(x, y, z) + 0.5) * v.size;
                    EXPECT_EQ(leafAt(level, centre), built.leafOfVoxel[v.index(x, y, z)]);
                }
        // No visibility lump: every leaf sees every leaf, as engines read it.
        EXPECT_FALSE(level.hasVisibility());
        EXPECT_EQ(levelVisibility(level, "voxel level").visibleCount(), std::size_t(level.visleafs) * std::size_t(level.visleafs));
    }
}

TEST(QuakeVis, AWrittenLumpIsWhatAnEngineReadsAndNothingElseChanges)
{
    VoxelLevel v = makeVoxelLevel(9, 7, 5);
    carve(v, 1, 3, 1, 5, 1, 3);
    carve(v, 4, 4, 3, 3, 1, 2);
    carve(v, 5, 7, 1, 5, 1, 3);
    for (BspVersion version : kVersions) {
        Baked b = bake(v, version);
        const std::string written = withVisibility(b.level, b.rows);
        const test::EngineBsp engine = test::readEngineBsp(written);
        ASSERT_EQ(engine.visleafs, b.level.visleafs);
        for (int leaf = 1; leaf <= engine.visleafs; ++leaf) {
            const std::vector<bool> pvs = test::engineLeafPvs(engine, leaf);
            for (int other = 1; other <= engine.visleafs; ++other)
                ASSERT_EQ(pvs[std::size_t(other) - 1], sees(b.rows, leaf, other)) << leaf << " -> " << other;
        }
        // Every lump but the visibility and the leaves' visofs is the original's, byte for byte.
        const test::EngineBsp original = test::readEngineBsp(b.voxels.bytes);
        for (int k = 0; k < kLumpCount; ++k) {
            if (k != kVisibilityLump && k != kLeafLump) {
                EXPECT_EQ(engine.lumpBytes(k), original.lumpBytes(k)) << "lump " << k;
            }
        }
        EXPECT_EQ(engine.leafContents, original.leafContents);
        // Read back by Sightline too: the same rows.
        const QuakeBsp again = readQuakeBsp(written, "written level");
        EXPECT_EQ(levelVisibility(again, "written level"), b.rows);
    }
}

TEST(QuakeVis, IdenticalRowsAreStoredOnce)
{
    pvs::VisibilityRows rows(3, 3);
    for (std::size_t a = 0; a < 3; ++a)
        for (std::size_t b = 0; b < 3; ++b)
            rows.set(a, b, true);
    const VisibilityLump lump = encodeVisibilityLump(rows);
    EXPECT_EQ(lump.rowOffsets, (std::vector<std::int32_t>{0, 0, 0}));
    EXPECT_EQ(lump.bytes, std::string("\x07", 1));
}

TEST(QuakeVis, AConvexRoomSeesItselfWholeAndASealedRoomNothingElse)
{
    VoxelLevel v = makeVoxelLevel(10, 6, 5);
    carve(v, 1, 4, 1, 4, 1, 3);   // room A
    carve(v, 6, 8, 1, 4, 1, 3);   // room B, sealed from A by the wall at x = 5
    for (BspVersion version : kVersions) {
        Baked b = bake(v, version);
        const std::set<int> a = leavesIn(b, v, 1, 4, 1, 4, 1, 3), c = leavesIn(b, v, 6, 8, 1, 4, 1, 3);
        ASSERT_GE(a.size(), 1u);
        ASSERT_GE(c.size(), 1u);
        for (int x : a)
            for (int y : a)
                EXPECT_TRUE(sees(b.rows, x, y)) << "a convex room's leaves see each other";
        for (int x : a)
            for (int y : c) {
                EXPECT_FALSE(sees(b.rows, x, y)) << "sealed rooms";
                EXPECT_FALSE(sees(b.rows, y, x)) << "sealed rooms";
            }
        EXPECT_EQ(b.rows.visibleCount(), a.size() * a.size() + c.size() * c.size());
    }
}

TEST(QuakeVis, BlockersFuseAcrossTwoOffsetTunnels)
{
    // Room A, a tunnel at y = 1, a middle room, a tunnel at y = 6, room C. Either tunnel alone
    // lets lines through; no line passes both (each allows slopes up to 1/2, joining them takes 4/3).
    VoxelLevel v = makeVoxelLevel(16, 9, 4);
    carve(v, 1, 3, 1, 7, 1, 2);     // A
    carve(v, 4, 5, 1, 1, 1, 1);     // tunnel 1
    carve(v, 6, 8, 1, 7, 1, 2);     // middle
    carve(v, 9, 10, 7, 7, 1, 1);    // tunnel 2
    carve(v, 11, 14, 1, 7, 1, 2);   // C
    for (BspVersion version : kVersions) {
        Baked b = bake(v, version);
        const std::set<int> a = leavesIn(b, v, 1, 3, 1, 7, 1, 2), middle = leavesIn(b, v, 6, 8, 1, 7, 1, 2),
                            c = leavesIn(b, v, 11, 14, 1, 7, 1, 2);
        ASSERT_FALSE(a.empty());
        ASSERT_FALSE(c.empty());
        for (int x : a)
            for (int y : c)
                EXPECT_FALSE(sees(b.rows, x, y) || sees(b.rows, y, x)) << "A and C through both tunnels";
        bool aSeesMiddle = false, cSeesMiddle = false;
        for (int m : middle) {
            for (int x : a)
                aSeesMiddle |= sees(b.rows, x, m);
            for (int y : c)
                cSeesMiddle |= sees(b.rows, y, m);
        }
        EXPECT_TRUE(aSeesMiddle);
        EXPECT_TRUE(cSeesMiddle);
        expectNoWitnessedCull(b);
    }
}

TEST(QuakeVis, LiquidsAreClearOrOpaqueAsAsked)
{
    VoxelLevel v = makeVoxelLevel(7, 6, 6);
    carve(v, 1, 5, 1, 4, 1, 4);
    carve(v, 1, 5, 1, 4, 1, 2, test::kContentsWater);   // a pool under the air
    for (BspVersion version : kVersions) {
        for (bool clear : {true, false}) {
            Baked b = bake(v, version, clear);
            const int air = leafOf(b, v, 3, 2, 4), water = leafOf(b, v, 3, 2, 1);
            EXPECT_EQ(sees(b.rows, air, water), clear);
            EXPECT_EQ(sees(b.rows, water, air), clear);
            expectNoWitnessedCull(b, clear);
        }
    }
}

TEST(QuakeVis, PortalsCloseEveryLeafAndPrt1FacesItsFirstLeaf)
{
    VoxelLevel v = makeVoxelLevel(9, 7, 5);
    carve(v, 1, 3, 1, 5, 1, 3);
    carve(v, 4, 4, 3, 3, 1, 2);
    carve(v, 5, 7, 1, 5, 1, 3);
    Baked b = bake(v, BspVersion::Bsp29);
    // Every empty voxel face shared with another leaf's voxel lies on an open portal: count the
    // leaf pairs that touch through a voxel face and compare with the portals' pairs.
    std::set<std::pair<int, int>> touching, portalPairs;
    for (int z = 0; z < v.nz; ++z)
        for (int y = 0; y < v.ny; ++y)
            for (int x = 0; x + 1 < v.nx; ++x)
                for (int axis = 0; axis < 3; ++axis) {
                    const int nx = x + (axis == 0), ny = y + (axis == 1), nz = z + (axis == 2);
                    if (ny >= v.ny || nz >= v.nz)
                        continue;
                    const int l0 = leafOf(b, v, x, y, z), l1 = leafOf(b, v, nx, ny, nz);
                    if (l0 && l1 && l0 != l1)
                        touching.insert({std::min(l0, l1), std::max(l0, l1)});
                }
    for (const LeafPortal& p : b.open)
        portalPairs.insert({std::min(p.leaves[0], p.leaves[1]), std::max(p.leaves[0], p.leaves[1])});
    EXPECT_EQ(portalPairs, touching);

    // PRT1: vis takes (p0 - p1) x (p2 - p1) as the plane and expects the first leaf in front.
    const std::string text = prt1(b.level, b.open);
    std::istringstream in(text);
    std::string magic;
    int leaves = 0, count = 0;
    in >> magic >> leaves >> count;
    EXPECT_EQ(magic, "PRT1");
    EXPECT_EQ(leaves, b.level.visleafs);
    ASSERT_EQ(count, int(b.open.size()));
    for (int k = 0; k < count; ++k) {
        int points = 0, first = 0, second = 0;
        in >> points >> first >> second;
        std::vector<glm::dvec3> w(static_cast<std::size_t>(points));
        for (glm::dvec3& p : w) {
            char open = 0, close = 0;
            in >> open >> p.x >> p.y >> p.z >> close;
        }
        const glm::dvec3 n = glm::cross(w[0] - w[1], w[2] - w[1]);
        glm::dvec3 centre(0.0);
        for (const glm::dvec3& p : w)
            centre += p / double(points);
        // A point a little in front of the winding lies in the first leaf.
        EXPECT_EQ(leafAt(b.level, centre + glm::normalize(n) * 1.0), first + 1) << "portal " << k;
        EXPECT_EQ(leafAt(b.level, centre - glm::normalize(n) * 1.0), second + 1) << "portal " << k;
    }
}

TEST(QuakeVis, AnOriginalQuakeLevelKeepsEveryWitnessedPairAndMatchesItsOwnVis)
{
    const QuakeBsp level = readQuakeBsp(readInputFile(SIGHTLINE_TEST_DATA "/levels/quake-dm4.bsp", "dm4"), "dm4");
    ASSERT_EQ(level.format, BspFormat::Bsp29);
    const std::vector<LeafPortal> tree = treePortals(level), open = openPortals(level, true);
    PortalVisStats stats;
    const pvs::VisibilityRows rows = portalVis(level, open, {.threads = 2}, &stats);
    EXPECT_EQ(stats.portalsOverBudget, 0u);
    const WitnessCount culled = searchWitnesses(level, tree, rows, true, {.segmentsPerPair = 64, .threads = 2});
    EXPECT_GT(culled.pairs, 50000u);
    EXPECT_EQ(culled.witnessed, 0u);
    // The level's own vis (id's tools) keeps nearly the same leaves: within 1% in all, and every
    // pair it keeps that these rows cull has no witness (checked above).
    const pvs::VisibilityRows own = levelVisibility(level, "dm4");
    EXPECT_NEAR(double(rows.visibleCount()) / double(own.visibleCount()), 1.0, 0.01);
    // Engines read the rewritten file as written.
    const test::EngineBsp engine = test::readEngineBsp(withVisibility(level, rows));
    for (int leaf = 1; leaf <= engine.visleafs; leaf += 37) {
        const std::vector<bool> pvs = test::engineLeafPvs(engine, leaf);
        for (int other = 1; other <= engine.visleafs; ++other)
            ASSERT_EQ(pvs[std::size_t(other) - 1], sees(rows, leaf, other));
    }
}

TEST(QuakeVis, BadFilesGetOneLineErrors)
{
    VoxelLevel v = makeVoxelLevel(6, 5, 5);
    carve(v, 1, 4, 1, 3, 1, 3);
    const std::string good = test::voxelBsp(v).bytes;
    auto refuses = [](std::string bytes, const std::string& words) {
        try {
            readQuakeBsp(std::move(bytes), "x.bsp");
            ADD_FAILURE() << "accepted; expected: " << words;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        }
    };
    auto put32 = [](std::string s, std::size_t at, std::int32_t value) {
        std::memcpy(s.data() + at, &value, 4);
        return s;
    };
    refuses(good.substr(0, 30), "truncated");
    refuses(put32(good, 0, 0x50534249), "Quake 2");
    refuses(put32(good, 0, 0x42535032), "2PSB");
    refuses(put32(good, 4 + 8 * kNodeLump, 1 << 30), "outside the file");
    const test::EngineBsp engine = test::readEngineBsp(good);
    const std::size_t nodes = std::size_t(engine.lumps[kNodeLump].first);
    refuses(put32(good, nodes, 1 << 20), "plane");
    // A child that points back at the root: a cycle a walk would follow forever.
    std::string cycle = good;
    const std::int16_t root = 0;
    std::memcpy(cycle.data() + nodes + 4, &root, 2);
    refuses(cycle, "reached twice");
    const std::size_t leaves = std::size_t(engine.lumps[kLeafLump].first);
    refuses(put32(good, leaves + 28 + 4, 1 << 20), "visofs");
    const std::size_t planes = std::size_t(engine.lumps[kPlaneLump].first);
    refuses(put32(good, planes, 0x7fc00000), "not finite");

    const QuakeBsp level = readQuakeBsp(good, "x.bsp");
    EXPECT_THROW(withVisibility(level, pvs::VisibilityRows(1, 1)), Error);
}

TEST(QuakeVis, HalfLifesVersion30IsReadWithQuakesLayoutAndKeptOnWrite)
{
    VoxelLevel v = makeVoxelLevel(9, 7, 5);
    carve(v, 1, 3, 1, 5, 1, 3);
    carve(v, 4, 4, 3, 3, 1, 2);
    carve(v, 5, 7, 1, 5, 1, 3);
    const Baked quake = bake(v, BspVersion::Bsp29);
    std::string bytes = quake.voxels.bytes;
    const std::int32_t thirty = 30;
    std::memcpy(bytes.data(), &thirty, 4);
    const QuakeBsp halfLife = readQuakeBsp(bytes, "hl.bsp");
    EXPECT_EQ(halfLife.format, BspFormat::HalfLife30);
    const pvs::VisibilityRows rows = portalVis(halfLife, openPortals(halfLife, true), {.threads = 2});
    EXPECT_EQ(rows, quake.rows);
    const std::string written = withVisibility(halfLife, rows);
    EXPECT_EQ(written.substr(0, 4), bytes.substr(0, 4));
    EXPECT_EQ(levelVisibility(readQuakeBsp(written, "hl.bsp"), "hl.bsp"), rows);
}
