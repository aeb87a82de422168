// The PVS core: closed-form levels, determinism, the file formats (with an
// independent Quake row decoder), part merging and bad cells.

#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstring>
#include <mutex>
#include <limits>
#include <random>
#include <set>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include "TestScenes.h"
#include "base/Error.h"
#include "visibility/pvs/FirstHitCaster.h"
#include "visibility/pvs/PvsBake.h"
#include "visibility/pvs/PvsFile.h"
#include "visibility/pvs/PvsObjects.h"
#include "visibility/pvs/PvsReference.h"
#include "visibility/pvs/ViewCells.h"

namespace sightline::pvs {
namespace {

using test::addBox;
const auto box = test::boxBounds;

/// Two 4 x 4 m rooms side by side along x (x in [0, 4] and [4.2, 8.2]), 3 m high under one ceiling, joined
/// (or not) by a 1 m wide, 2 m high doorway at z in [1.5, 2.5] in the shared wall; a crate in
/// the middle of each room.
Scene twoRooms(bool door)
{
    Scene s;
    addBox(s, "floor", {-0.2f, -0.2f, -0.2f}, {8.4f, 0.0f, 4.2f});
    addBox(s, "ceiling", {-0.2f, 3.0f, -0.2f}, {8.4f, 3.2f, 4.2f});
    addBox(s, "wall_south", {-0.2f, 0.0f, -0.2f}, {8.4f, 3.0f, 0.0f});
    addBox(s, "wall_north", {-0.2f, 0.0f, 4.0f}, {8.4f, 3.0f, 4.2f});
    addBox(s, "wall_west", {-0.2f, 0.0f, 0.0f}, {0.0f, 3.0f, 4.0f});
    addBox(s, "wall_east", {8.2f, 0.0f, 0.0f}, {8.4f, 3.0f, 4.0f});
    if (door) {
        addBox(s, "wall_mid_a", {4.0f, 0.0f, 0.0f}, {4.2f, 3.0f, 1.5f});
        addBox(s, "wall_mid_b", {4.0f, 0.0f, 2.5f}, {4.2f, 3.0f, 4.0f});
        addBox(s, "wall_mid_top", {4.0f, 2.0f, 1.5f}, {4.2f, 3.0f, 2.5f});
    } else {
        addBox(s, "wall_mid", {4.0f, 0.0f, 0.0f}, {4.2f, 3.0f, 4.0f});
    }
    addBox(s, "crate_a", {1.6f, 0.0f, 1.6f}, {2.4f, 0.8f, 2.4f});
    addBox(s, "crate_b", {5.8f, 0.0f, 1.6f}, {6.6f, 0.8f, 2.4f});
    return s;
}

std::size_t objectNamed(const std::vector<PvsObject>& objects, const std::string& name)
{
    for (std::size_t o = 0; o < objects.size(); ++o)
        if (objects[o].name == name)
            return o;
    ADD_FAILURE() << "no object " << name;
    return 0;
}

VisibilityRows bakeOf(const Scene& scene, const std::vector<Bounds>& cells, PvsSettings settings = {})
{
    const PvsBaker baker(scene, cells, sceneObjects(scene, false), "00ab", settings);
    return baker.bake();
}

const std::vector<Bounds> kRoomCells = {box({0.5f, 0.1f, 0.5f}, {2.0f, 1.9f, 3.5f}),    // room A, west half
                                        box({6.2f, 0.1f, 0.5f}, {7.7f, 1.9f, 3.5f})};   // room B, east half

TEST(Pvs, TwoRoomsJoinedByADoorSeeEachOther)
{
    const Scene scene = twoRooms(true);
    const auto objects = sceneObjects(scene, false);
    const VisibilityRows rows = bakeOf(scene, kRoomCells);
    EXPECT_TRUE(rows.visible(0, objectNamed(objects, "crate_a")));
    EXPECT_TRUE(rows.visible(0, objectNamed(objects, "crate_b")));   // through the doorway
    EXPECT_TRUE(rows.visible(1, objectNamed(objects, "crate_a")));
    EXPECT_TRUE(rows.visible(1, objectNamed(objects, "crate_b")));
    // Room B's east wall, seen through the door from room A.
    EXPECT_TRUE(rows.visible(0, objectNamed(objects, "wall_east")));
}

TEST(Pvs, ASealedWallHidesEverythingBehindIt)
{
    const Scene scene = twoRooms(false);
    const auto objects = sceneObjects(scene, false);
    PvsSettings settings;
    settings.safe = true;   // even the conservative mode: nothing reaches room B
    const VisibilityRows rows = bakeOf(scene, kRoomCells, settings);
    EXPECT_TRUE(rows.visible(0, objectNamed(objects, "crate_a")));
    EXPECT_FALSE(rows.visible(0, objectNamed(objects, "crate_b")));
    EXPECT_FALSE(rows.visible(0, objectNamed(objects, "wall_east")));
    EXPECT_FALSE(rows.visible(1, objectNamed(objects, "crate_a")));
    EXPECT_FALSE(rows.visible(1, objectNamed(objects, "wall_west")));
    EXPECT_TRUE(rows.visible(1, objectNamed(objects, "crate_b")));
    // Both see the shared wall, the floor and the long walls.
    for (const char* shared : {"wall_mid", "floor", "ceiling", "wall_south", "wall_north"}) {
        EXPECT_TRUE(rows.visible(0, objectNamed(objects, shared))) << shared;
        EXPECT_TRUE(rows.visible(1, objectNamed(objects, shared))) << shared;
    }
}

TEST(Pvs, AnObjectBehindAPillarFromEveryPointOfTheCellIsCulled)
{
    // Cell [0, 0.2]^3; pillar z in [1, 1.2] covering x, y in [-1, 1.2]; target in [0, 0.2]^2 at
    // z in [2, 2.2]. Every segment from the cell to the target keeps x, y in [0, 0.2] (convex),
    // so it crosses the pillar: culled. A second target beside the pillar is seen.
    Scene s;
    addBox(s, "pillar", {-1.0f, -1.0f, 1.0f}, {1.2f, 1.2f, 1.2f});
    addBox(s, "hidden", {0.0f, 0.0f, 2.0f}, {0.2f, 0.2f, 2.2f});
    addBox(s, "beside", {3.0f, 0.0f, 2.0f}, {3.2f, 0.2f, 2.2f});
    PvsSettings settings;
    settings.safe = true;
    const VisibilityRows rows = bakeOf(s, {box({0.0f, 0.0f, 0.0f}, {0.2f, 0.2f, 0.2f})}, settings);
    EXPECT_TRUE(rows.visible(0, 0));
    EXPECT_FALSE(rows.visible(0, 1));
    EXPECT_TRUE(rows.visible(0, 2));
}

TEST(Pvs, AnObjectSeenOnlyThroughANarrowSlotIsFoundByTheShafts)
{
    // A wall with a 5 cm slot; the target behind it is seen only through the slot. The direct
    // rays (few, random) rarely find it; the shaft search must: the sub-shafts through the slot
    // are the ones no wall proves blocked, so they are split and their central segments cast.
    Scene s;
    addBox(s, "wall_left", {-3.0f, -1.0f, 1.0f}, {0.075f, 2.0f, 1.1f});
    addBox(s, "wall_right", {0.125f, -1.0f, 1.0f}, {3.0f, 2.0f, 1.1f});
    addBox(s, "target", {-0.5f, 0.0f, 3.0f}, {0.7f, 1.0f, 3.2f});
    const VisibilityRows rows = bakeOf(s, {box({-0.5f, 0.0f, -1.0f}, {0.7f, 1.0f, 0.0f})});
    EXPECT_TRUE(rows.visible(0, 2));
}

TEST(Pvs, CellRowsSeeThroughTheDoorAndNotThroughTheWall)
{
    // The Quake formats' rows are over clusters: cell to cell. Room A's cell sees room B's through
    // the doorway; with the wall sealed, not even the safe mode keeps them (the wall proves it).
    for (bool door : {true, false}) {
        const Scene scene = twoRooms(door);
        PvsSettings settings;
        settings.safe = !door;
        const PvsBaker baker(scene, kRoomCells, sceneObjects(scene, false), "00ab", settings);
        const VisibilityRows cellRows = baker.bakeCellRows();
        ASSERT_EQ(cellRows.cellCount(), 2u);
        ASSERT_EQ(cellRows.objectCount(), 2u);
        EXPECT_TRUE(cellRows.visible(0, 0));   // every cell sees itself
        EXPECT_TRUE(cellRows.visible(1, 1));
        EXPECT_EQ(cellRows.visible(0, 1), door) << "door " << door;
        EXPECT_EQ(cellRows.visible(1, 0), door) << "door " << door;
    }
}

TEST(Pvs, TheDistanceCutOffCullsWhatIsFartherThanItFromTheCell)
{
    const Scene scene = twoRooms(true);
    const auto objects = sceneObjects(scene, false);
    PvsSettings settings;
    settings.maxDistance = 2.5;   // room A's cell (x <= 2) to room B's crate (x >= 5.8): 3.8 m
    const VisibilityRows rows = bakeOf(scene, kRoomCells, settings);
    EXPECT_TRUE(rows.visible(0, objectNamed(objects, "crate_a")));
    EXPECT_FALSE(rows.visible(0, objectNamed(objects, "crate_b")));
    EXPECT_FALSE(rows.visible(0, objectNamed(objects, "wall_east")));
    EXPECT_TRUE(rows.visible(0, objectNamed(objects, "floor")));   // it runs under the cell
    const VisibilityRows cellRows = PvsBaker(scene, kRoomCells, objects, "00ab", settings).bakeCellRows();
    EXPECT_FALSE(cellRows.visible(0, 1));   // 4.2 m apart
    EXPECT_TRUE(cellRows.visible(0, 0));
}

TEST(Pvs, TheSafeModeCullsOnlyWhatItProves)
{
    // A wall with a 2 cm slit: the crate behind the slit is seen through it; the box behind the
    // wall's right part is hidden by that part from every point of the cell. The safe bake keeps
    // the crate and culls the box, and every pair it culls is one it proved hidden.
    Scene s;
    addBox(s, "wall_left", {-3.0f, -1.0f, 1.0f}, {0.09f, 2.0f, 1.1f});
    addBox(s, "wall_right", {0.11f, -1.0f, 1.0f}, {3.0f, 2.0f, 1.1f});
    addBox(s, "crate", {-0.5f, 0.0f, 3.0f}, {0.7f, 1.0f, 3.2f});
    addBox(s, "hidden", {2.0f, 0.0f, 1.5f}, {2.5f, 0.5f, 2.0f});
    const std::vector<Bounds> cell = {box({-0.5f, 0.0f, -1.0f}, {0.7f, 1.0f, 0.0f})};
    for (bool safe : {true, false}) {
        PvsSettings settings;
        settings.safe = safe;
        PvsStats stats;
        const PvsBaker baker(s, cell, sceneObjects(s, false), "00ab", settings);
        const VisibilityRows rows = baker.bake({}, {}, &stats);
        EXPECT_TRUE(rows.visible(0, 2)) << "safe " << safe;
        EXPECT_FALSE(rows.visible(0, 3)) << "safe " << safe;
        if (safe) {
            EXPECT_EQ(stats.provenHidden + rows.visibleCount(0), 4u);
        }
    }
}

TEST(Pvs, TheRowsDoNotDependOnThreadsOrOnWhichCellsAreBakedTogether)
{
    const Scene scene = twoRooms(true);
    std::vector<Bounds> cells;
    for (int i = 0; i < 6; ++i)
        cells.push_back(box({0.3f + 1.3f * float(i), 0.1f, 0.4f}, {1.2f + 1.3f * float(i), 1.9f, 1.4f}));
    auto objects = sceneObjects(scene, false);
    PvsSettings one, two;
    one.threads = 1;
    two.threads = 2;
    const VisibilityRows a = PvsBaker(scene, cells, objects, "beef", one).bake();
    const VisibilityRows b = PvsBaker(scene, cells, objects, "beef", two).bake();
    EXPECT_EQ(a, b);
    // Baking cells one by one (as shards do) gives the same rows.
    const PvsBaker baker(scene, cells, objects, "beef", one);
    for (std::size_t c = 0; c < cells.size(); ++c) {
        const VisibilityRows single = baker.bake({c});
        EXPECT_TRUE(std::equal(single.row(c), single.row(c) + single.rowBytes(), a.row(c))) << "cell " << c;
    }
}

TEST(Pvs, ProgressReportsEveryCellForTheCoarsePassBeforeAnyRefinement)
{
    const Scene scene = twoRooms(true);
    std::vector<PvsPass> passes;
    std::mutex m;
    PvsProgress progress;
    progress.onCell = [&](PvsPass pass, std::size_t, const std::vector<std::uint8_t>&) {
        const std::lock_guard lock(m);
        passes.push_back(pass);
    };
    const PvsBaker baker(scene, kRoomCells, sceneObjects(scene, false), "00", {});
    baker.bake({}, progress);
    ASSERT_EQ(passes.size(), 4u);
    EXPECT_EQ(passes[0], PvsPass::Coarse);
    EXPECT_EQ(passes[1], PvsPass::Coarse);
    EXPECT_EQ(passes[2], PvsPass::Refine);
    EXPECT_EQ(passes[3], PvsPass::Refine);
    std::atomic<bool> cancel{true};
    progress.cancel = &cancel;
    EXPECT_THROW(baker.bake({}, progress), PvsCancelled);
}

TEST(Pvs, BadCellsAreRefusedInOneLine)
{
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<std::pair<Bounds, std::string>> bad = {
        {box({0, 0, 0}, {1, 0, 1}), "empty box"},
        {box({0, 2, 0}, {1, 1, 1}), "inverted box"},
        {box({0, nan, 0}, {1, 1, 1}), "not finite"},
        {box({0, 0, 0}, {2e6f, 1, 1}), "beyond 1e6"},
    };
    for (const auto& [cell, words] : bad) {
        try {
            validateCells({box({0, 0, 0}, {1, 1, 1}), cell}, "level.json: pvs.cells");
            ADD_FAILURE() << words << " accepted";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(words), std::string::npos) << what;
            EXPECT_NE(what.find("pvs.cells[1]"), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos);
        }
    }
    EXPECT_THROW(validateCells({}, "x"), Error);
}

TEST(Pvs, GridCellsStandOnFloorsWithRoomAboveThem)
{
    // A 4 x 4 m floor at y = 0 and a 2 x 4 m mezzanine at y = 1 over half of it (x in [0, 2]):
    // with 1.5 m cells that need 0.1 + 0.8 m of room, columns under the mezzanine get a cell on
    // the floor (1 m of room) and one on the mezzanine (up to the scene's top at y = 3).
    Scene s;
    addBox(s, "floor", {0.0f, -0.1f, 0.0f}, {4.0f, 0.0f, 4.0f});
    addBox(s, "mezzanine", {0.0f, 0.95f, 0.0f}, {2.0f, 1.0f, 4.0f});
    addBox(s, "mast", {3.9f, 0.0f, 3.9f}, {4.0f, 3.0f, 4.0f});
    const FirstHitCaster caster(s);
    GridCellSettings g;
    g.cellSize = 2.0f;
    g.height = 0.8f;
    g.lift = 0.1f;
    const auto cells = gridCells(s, caster, g);
    // 2 x 2 columns; the two at x < 2 have two floors.
    ASSERT_EQ(cells.size(), 6u);
    int onMezzanine = 0;
    for (const Bounds& c : cells) {
        EXPECT_FLOAT_EQ(c.max.y - c.min.y, 0.8f);
        if (std::abs(c.min.y - 1.1f) < 1e-4f)
            ++onMezzanine;
        else
            EXPECT_NEAR(c.min.y, 0.1f, 1e-4f);
    }
    EXPECT_EQ(onMezzanine, 2);
}

TEST(Pvs, ObjectsGroupedByNameShareOneRow)
{
    Scene s;
    addBox(s, "lamp", {0, 0, 0}, {1, 1, 1});
    addBox(s, "crate", {2, 0, 0}, {3, 1, 1});
    addBox(s, "lamp", {4, 0, 0}, {5, 1, 1});
    const auto grouped = sceneObjects(s, true);
    ASSERT_EQ(grouped.size(), 2u);
    EXPECT_EQ(grouped[0].name, "lamp");
    EXPECT_EQ(grouped[0].instances, (std::vector<std::uint32_t>{0, 2}));
    EXPECT_FLOAT_EQ(grouped[0].bounds.max.x, 5.0f);
    EXPECT_EQ(sceneObjects(s, false).size(), 3u);
}

// ---------------------------------------------------------------- formats

PvsData sampleData()
{
    PvsData d;
    d.sceneSha256 = std::string(64, 'a');
    d.settingsSha256 = std::string(64, 'b');
    for (int c = 0; c < 5; ++c)
        d.cells.push_back(box({float(c), 0, 0}, {float(c + 1), 1, 1}));
    for (int o = 0; o < 700; ++o)
        d.objects.push_back({"obj" + std::to_string(o), std::uint32_t(o), {std::uint32_t(o)}, box({0, 0, 0}, {1, 1, 1})});
    d.objects[3].name = "naïve \"quoted\"";
    d.rows = VisibilityRows(5, 700);
    for (int c = 0; c < 5; ++c)
        for (int o = 0; o < 700; ++o)
            if ((o * 7 + c * 13) % 97 == 0 || (c == 2 && o > 600))
                d.rows.set(std::size_t(c), std::size_t(o), true);
    return d;
}

std::uint32_t le32(const std::string& s, std::size_t at)
{
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k)
        v |= std::uint32_t(std::uint8_t(s[at + std::size_t(k)])) << (8 * k);
    return v;
}

/// Quake's DecompressVis, written again from the engine's description (not the library's code):
/// a non-zero byte is copied; a zero byte is followed by a count of zero bytes.
std::vector<std::uint8_t> quakeDecompress(const std::string& data, std::size_t at, std::size_t rowBytes)
{
    std::vector<std::uint8_t> out;
    while (out.size() < rowBytes) {
        const std::uint8_t b = std::uint8_t(data.at(at++));
        if (b) {
            out.push_back(b);
        } else {
            const int c = std::uint8_t(data.at(at++));
            out.insert(out.end(), std::size_t(c), 0);
        }
    }
    EXPECT_EQ(out.size(), rowBytes);
    return out;
}

TEST(PvsFiles, PvsBinaryRoundTripsRawAndCompressed)
{
    const PvsData d = sampleData();
    for (RowEncoding e : {RowEncoding::Raw, RowEncoding::ZeroRuns}) {
        const std::string bytes = encodePvs(d, e);
        EXPECT_EQ(bytes.substr(0, 5), "SLPVS");
        EXPECT_EQ(le32(bytes, 8), kPvsFileVersion);
        EXPECT_EQ(le32(bytes, 16), 5u);
        EXPECT_EQ(le32(bytes, 20), 700u);
        const PvsData back = decodePvs(bytes, "x.pvs");
        EXPECT_EQ(back.rows, d.rows);
        EXPECT_EQ(back.objects[3].name, d.objects[3].name);
        EXPECT_EQ(back.sceneSha256, d.sceneSha256);
        EXPECT_EQ(encodePvs(back, e), bytes);
    }
    // The compressed rows are smaller here: mostly zeros.
    EXPECT_LT(encodePvs(d, RowEncoding::ZeroRuns).size(), encodePvs(d, RowEncoding::Raw).size());
}

TEST(PvsFiles, CellRowsRoundTripInVersionTwoAndVersionOneFilesStillRead)
{
    PvsData d = sampleData();
    d.cellRows = VisibilityRows(d.cells.size(), d.cells.size());
    for (std::size_t c = 0; c < d.cells.size(); ++c)
        for (std::size_t e = 0; e < d.cells.size(); ++e)
            d.cellRows.set(c, e, (c + e) % 2 == 0);
    for (RowEncoding e : {RowEncoding::Raw, RowEncoding::ZeroRuns}) {
        const std::string bytes = encodePvs(d, e);
        EXPECT_EQ(le32(bytes, 28), 1u);   // flags: cell rows follow
        const PvsData back = decodePvs(bytes, "x.pvs");
        EXPECT_EQ(back.rows, d.rows);
        EXPECT_EQ(back.cellRows, d.cellRows);
        EXPECT_EQ(encodePvs(back, e), bytes);
        EXPECT_NE(pvsJson(back).find("\"visible_cells\": [\n  [0, 2, 4]"), std::string::npos);
    }
    // A version 1 file (no flags, no cell rows) is read as before.
    std::string old = encodePvs(sampleData());
    old[8] = 1;
    const PvsData back = decodePvs(old, "old.pvs");
    EXPECT_EQ(back.rows, sampleData().rows);
    EXPECT_FALSE(back.hasCellRows());
    old[28] = 1;   // version 1 knows no flags
    EXPECT_THROW(decodePvs(old, "old.pvs"), Error);
}

TEST(PvsFiles, DamagedPvsFilesAreRefusedNotRead)
{
    const std::string bytes = encodePvs(sampleData());
    EXPECT_THROW(decodePvs(bytes.substr(0, bytes.size() - 1), "x.pvs"), Error);
    EXPECT_THROW(decodePvs(bytes.substr(0, 40), "x.pvs"), Error);
    std::string other = bytes;
    other[8] = 9;   // version
    try {
        decodePvs(other, "x.pvs");
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("version 9"), std::string::npos);
    }
    EXPECT_THROW(decodePvs("not a pvs file at all", "x.pvs"), Error);
}

/// The message of the Error `f` throws, or a failure when it throws none.
template <class F>
std::string refusal(F&& f)
{
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "accepted";
    return {};
}

void put32At(std::string& s, std::size_t at, std::uint32_t v)
{
    for (int k = 0; k < 4; ++k)
        s[at + std::size_t(k)] = char((v >> (8 * k)) & 0xff);
}

TEST(PvsFiles, DeclaredCountsAreCheckedAgainstTheBytesBeforeAnythingIsAllocated)
{
    // 200,000 cells x 180,000 objects would take 4.5 GB of rows: refused from the header, at once.
    std::string bytes = encodePvs(sampleData());
    put32At(bytes, 16, 200000);
    put32At(bytes, 20, 180000);
    put32At(bytes, 24, 22500);
    EXPECT_NE(refusal([&] { decodePvs(bytes, "x.pvs"); }).find("truncated"), std::string::npos);
    // Row offsets that declare more row data than follows, or rows too short for their size.
    const PvsData d = sampleData();
    std::size_t offsets = 160 + 24 * d.cells.size();   // docs/pvs.md's layout: the row offsets follow the object table
    for (const PvsObject& o : d.objects)
        offsets += 4 + 4 + 4 * o.instances.size() + 24 + 4 + o.name.size();
    for (RowEncoding e : {RowEncoding::Raw, RowEncoding::ZeroRuns}) {
        const std::string good = encodePvs(d, e);
        if (e == RowEncoding::Raw) {
            std::string cut = good;
            cut[offsets + 8] = char(87);   // the second row starts one byte early
            EXPECT_NE(refusal([&] { decodePvs(cut, "x.pvs"); }).find("bytes for a row of 88"), std::string::npos);
        }
        std::string huge = good;
        huge[offsets + 5 * 8 + 7] = char(0x7f);   // the last offset: 2^62 bytes of rows
        EXPECT_NE(refusal([&] { decodePvs(huge, "x.pvs"); }).find("truncated"), std::string::npos);
    }
    // A table past kMaxRowTableBytes is refused by the rows themselves (bake and read alike).
    EXPECT_THROW(VisibilityRows(std::size_t(1) << 20, std::size_t(1) << 14), Error);
}

TEST(PvsFiles, CellsAndObjectBoxesMustBeFiniteOrderedAndNear)
{
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (const Bounds& bad : {box({nan, 0, 0}, {1, 1, 1}), box({0, 0, 0}, {inf, 1, 1}), box({0, 2, 0}, {1, 1, 1}),
                              box({-1e30f, 0, 0}, {1, 1, 1})}) {
        PvsData d = sampleData();
        d.cells[2] = bad;
        EXPECT_NE(refusal([&] { decodePvs(encodePvs(d), "x.pvs"); }).find("x.pvs: cell[2]"), std::string::npos);
        d = sampleData();
        d.objects[4].bounds = bad;
        EXPECT_NE(refusal([&] { decodePvs(encodePvs(d), "x.pvs"); }).find("x.pvs: object 4"), std::string::npos);
    }
    PvsData d = sampleData();
    d.objects[4].bounds = Bounds();   // an object without triangles: its empty box is kept
    EXPECT_EQ(decodePvs(encodePvs(d), "x.pvs").rows, d.rows);
    d.objects[4].instances = {9, 4};
    EXPECT_NE(refusal([&] { decodePvs(encodePvs(d), "x.pvs"); }).find("instance list"), std::string::npos);
}

TEST(PvsFiles, APartCarriesItsOwnHashAndEveryFlippedBitIsRefused)
{
    PvsPart p;
    p.data = sampleData();
    p.shard = 1;
    p.shardCount = 2;
    for (std::size_t c = 1; c < p.data.cells.size(); c += 2)
        p.cellIndices.push_back(std::uint32_t(c));
    const std::string bytes = encodePart(p);
    ASSERT_EQ(encodePvs(decodePart(bytes, "p").data), encodePvs(p.data));
    std::mt19937 random(7);
    for (int k = 0; k < 300; ++k) {
        std::string flipped = bytes;
        const std::size_t at = random() % bytes.size();
        flipped[at] = char(flipped[at] ^ (1 << (random() % 8)));
        EXPECT_THROW(decodePart(flipped, "p"), Error) << "bit flipped at byte " << at;
    }
    // A part from an older build (no hash) is told to bake again.
    std::string old = bytes;
    put32At(old, 8, 2);
    EXPECT_NE(refusal([&] { decodePart(old, "p"); }).find("bake the shard again"), std::string::npos);
}

TEST(PvsFiles, AShardCountFromAFileAllocatesNothing)
{
    PvsPart p;
    p.data = sampleData();
    p.shard = 0;
    p.shardCount = kMaxShards + 1;
    p.cellIndices = {0};
    EXPECT_NE(refusal([&] { decodePart(encodePart(p), "p"); }).find("is not valid"), std::string::npos);
    // The most shards allowed, one part given: the missing shard is named without a table of them.
    p.shardCount = kMaxShards;
    const PvsPart one = decodePart(encodePart(p), "p");
    EXPECT_NE(refusal([&] { mergeParts({one}, {"p"}); }).find("shard 1/1000000 is missing"), std::string::npos);
}

TEST(PvsFiles, QuakeOneRowsDecodeWithAnIndependentDecoder)
{
    const PvsData d = sampleData();
    const std::string q = quake1Vis(d.rows);
    const std::size_t leafs = le32(q, 0);
    ASSERT_EQ(leafs, 5u);
    const std::size_t visdata = 4 + 4 * leafs;
    for (std::size_t c = 0; c < leafs; ++c) {
        const auto row = quakeDecompress(q, visdata + le32(q, 4 + 4 * c), d.rows.rowBytes());
        for (std::size_t o = 0; o < 700; ++o)
            ASSERT_EQ(bool(row[o >> 3] & (1 << (o & 7))), d.rows.visible(c, o)) << c << " " << o;
    }
}

TEST(PvsFiles, QuakeTwoVisLumpDecodesWithAnIndependentDecoder)
{
    const PvsData d = sampleData();
    const std::string q = quake2Vis(d.rows);
    const std::size_t clusters = le32(q, 0);
    ASSERT_EQ(clusters, 5u);
    for (std::size_t c = 0; c < clusters; ++c) {
        const std::size_t pvsOffset = le32(q, 4 + 8 * c), phsOffset = le32(q, 8 + 8 * c);
        EXPECT_GE(pvsOffset, 4 + 8 * clusters);   // offsets count from the lump's start
        EXPECT_EQ(phsOffset, pvsOffset);
        const auto row = quakeDecompress(q, pvsOffset, d.rows.rowBytes());
        for (std::size_t o = 0; o < 700; ++o)
            ASSERT_EQ(bool(row[o >> 3] & (1 << (o & 7))), d.rows.visible(c, o));
    }
}

TEST(PvsFiles, ZeroRunsSplitLongRunsAt255AndRefuseOverflows)
{
    std::vector<std::uint8_t> row(600, 0);
    row[599] = 0x80;
    const auto packed = compressZeroRuns(row.data(), row.size());
    // 599 zeros: runs of 255, 255 and 89, then the byte.
    EXPECT_EQ(packed, (std::vector<std::uint8_t>{0, 255, 0, 255, 0, 89, 0x80}));
    const std::string text(packed.begin(), packed.end());
    EXPECT_EQ(decompressZeroRuns(text, 0, 600), row);
    EXPECT_THROW(decompressZeroRuns(text, 0, 500), Error);          // the run overflows the row
    EXPECT_THROW(decompressZeroRuns(text.substr(0, 3), 0, 600), Error);   // data ends
}

TEST(PvsFiles, JsonFollowsDesignSection4)
{
    PvsData d = sampleData();
    const std::string j = pvsJson(d);
    EXPECT_NE(j.find("\"version\": 1"), std::string::npos);
    EXPECT_NE(j.find("\"scene_sha256\": \"" + std::string(64, 'a') + "\""), std::string::npos);
    EXPECT_NE(j.find("{\"min\": [2, 0, 0], \"max\": [3, 1, 1]}"), std::string::npos);
    EXPECT_NE(j.find("{\"name\": \"obj5\", \"instance\": 5,"), std::string::npos);
    EXPECT_NE(j.find("\"naïve \\\"quoted\\\"\""), std::string::npos);
    // Row 0: o * 7 % 97 == 0 -> 0, 97, 194, ...
    EXPECT_NE(j.find("\"visible\": [\n  [0, 97, 194, 291, 388, 485, 582, 679]"), std::string::npos);
}

TEST(PvsFiles, PrtOneListsOnePortalPerSharedFace)
{
    // Three cells in a row along x, and one above the first: 3 shared faces.
    const std::vector<Bounds> cells = {box({0, 0, 0}, {1, 1, 1}), box({1, 0, 0}, {2, 1, 1}), box({2, 0, 0}, {3, 1, 1}),
                                       box({0, 1, 0}, {1, 2, 1}), box({5, 0, 0}, {6, 1, 1})};
    const std::string prt = prt1(cells);
    EXPECT_EQ(prt.substr(0, prt.find('\n', prt.find('\n', 5) + 1) + 1), "PRT1\n5\n3\n");
    EXPECT_NE(prt.find("4 0 1 (1 -0 0) (1 -0 1) (1 -1 1) (1 -1 0)"), std::string::npos) << prt;   // x = 1, Quake Z up
    EXPECT_NE(prt.find("4 0 3 "), std::string::npos);
    EXPECT_NE(prt.find("4 1 2 "), std::string::npos);
}

TEST(PvsFiles, PartsMergeToTheWholeAndRefuseMismatches)
{
    const PvsData whole = sampleData();
    std::vector<PvsPart> parts;
    std::vector<std::string> names;
    for (std::uint32_t s = 0; s < 3; ++s) {
        PvsPart p;
        p.data = whole;
        p.shard = s;
        p.shardCount = 3;
        for (std::size_t c = 0; c < whole.cells.size(); ++c)
            if (c % 3 == s)
                p.cellIndices.push_back(std::uint32_t(c));
            else
                std::fill(p.data.rows.row(c), p.data.rows.row(c) + p.data.rows.rowBytes(), std::uint8_t(0));
        parts.push_back(decodePart(encodePart(p), "p" + std::to_string(s)));
        names.push_back("p" + std::to_string(s));
    }
    EXPECT_EQ(encodePvs(mergeParts(parts, names)), encodePvs(whole));
    auto expectRefused = [&](std::vector<PvsPart> ps, const std::string& words) {
        try {
            mergeParts(ps, names);
            ADD_FAILURE() << words;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        }
    };
    auto otherScene = parts;
    otherScene[1].data.sceneSha256 = std::string(64, 'c');
    expectRefused(otherScene, "p1 is of another scene");
    auto otherSettings = parts;
    otherSettings[2].data.settingsSha256 = std::string(64, 'd');
    expectRefused(otherSettings, "p2 was baked with other settings");
    expectRefused({parts[0], parts[2]}, "shard 1/3 is missing");
    expectRefused({parts[0], parts[0], parts[1]}, "shard 0 given twice");
    const std::string bytes = encodePart(parts[0]);
    EXPECT_THROW(decodePart(bytes.substr(0, bytes.size() - 3), "p0"), Error);
}

// ---------------------------------------------------------------- accuracy

TEST(PvsAccuracy, TheReferenceFindsWhatAnEmptyPvsMissesAndNothingInAFullOne)
{
    const Scene scene = twoRooms(true);
    PvsData d;
    d.sceneSha256 = "12";
    d.cells = kRoomCells;
    d.objects = sceneObjects(scene, false);
    d.rows = VisibilityRows(d.cells.size(), d.objects.size());
    ReferenceSettings r;
    r.cellPoints = 27;
    r.objectPoints = 27;
    r.views = 2;
    r.width = 32;
    r.height = 16;
    const AccuracyReport empty = measureAccuracy(scene, d, r);
    EXPECT_GT(empty.referenceVisible, 0u);
    EXPECT_EQ(empty.missed, empty.referenceVisible);
    EXPECT_DOUBLE_EQ(empty.objectMissRate(), 1.0);
    // Each missed pair is seen through one opening or more: each its own gap.
    std::set<std::pair<std::uint32_t, std::uint32_t>> gapPairs;
    for (const Gap& gap : empty.gaps) {
        gapPairs.emplace(gap.cell, gap.object);
        EXPECT_GT(gap.opening.rays, 0u);
        EXPECT_FALSE(gap.witnesses.empty());
    }
    EXPECT_EQ(gapPairs.size(), empty.missed);
    // Inside closed rooms every pixel shows an object, and all are culled.
    EXPECT_EQ(empty.wrongPixels, empty.pixels);
    for (std::size_t c = 0; c < d.cells.size(); ++c)
        for (std::size_t o = 0; o < d.objects.size(); ++o)
            d.rows.set(c, o, true);
    const AccuracyReport full = measureAccuracy(scene, d, r);
    EXPECT_EQ(full.missed, 0u);
    EXPECT_EQ(full.wrongPixels, 0u);
    EXPECT_EQ(full.referenceVisible, empty.referenceVisible);
    // The baked PVS of the door scene: nothing the reference sees is culled.
    d.rows = bakeOf(scene, kRoomCells);
    EXPECT_EQ(measureAccuracy(scene, d, r).missed, 0u);
}

// A 1 mm slit in a wall between a cell and an object: a handful of area rays misses it, the edge
// search along the blockers' edges finds it, and counts it apart (a miss if the PVS culls the pair).
TEST(PvsAccuracy, TheEdgeSearchFindsASlitTheAreaRaysMiss)
{
    Scene scene;
    addBox(scene, "object", {-0.15f, -0.15f, 3.0f}, {0.15f, 0.15f, 3.1f});
    addBox(scene, "left wall", {-5.0f, -5.0f, -0.01f}, {0.05f, 5.0f, 0.01f});
    addBox(scene, "right wall", {0.051f, -5.0f, -0.01f}, {5.0f, 5.0f, 0.01f});
    PvsData d;
    d.sceneSha256 = "12";
    d.cells = {box({-0.15f, -0.15f, -3.15f}, {0.15f, 0.15f, -2.85f})};
    d.objects = sceneObjects(scene, false);
    d.rows = VisibilityRows(1, d.objects.size());
    d.rows.set(0, 1, true);   // the walls are seen; the object behind them is culled
    d.rows.set(0, 2, true);
    ReferenceSettings r;
    r.cellPoints = 2;
    r.objectPoints = 2;
    r.views = 0;
    r.edgeBlockers = 0;
    const AccuracyReport area = measureAccuracy(scene, d, r);
    ASSERT_EQ(area.referenceVisible, 2u) << "the area rays see the walls and miss the slit (the setup)";
    EXPECT_EQ(area.missed, 0u);
    EXPECT_EQ(area.edgeVisible, 0u);
    r.edgeBlockers = 12;
    const AccuracyReport edges = measureAccuracy(scene, d, r);
    EXPECT_EQ(edges.referenceVisible, 2u);
    EXPECT_EQ(edges.edgeVisible, 1u) << "the object, through the slit";
    EXPECT_EQ(edges.edgeMissed, 1u);
    EXPECT_DOUBLE_EQ(edges.adversarialMissRate(), 1.0 / 3.0);
    EXPECT_GT(edges.edgeRays, 0u);
    d.rows.set(0, 0, true);
    const AccuracyReport kept = measureAccuracy(scene, d, r);
    EXPECT_EQ(kept.edgeVisible, 1u);
    EXPECT_EQ(kept.edgeMissed, 0u);
    EXPECT_EQ(kept.extra, 0u) << "a pair the edge search sees is not extra";
    // Closed: nothing to find.
    addBox(scene, "plug", {0.049f, -5.0f, -0.02f}, {0.052f, 5.0f, 0.02f});
    d.objects = sceneObjects(scene, false);
    d.rows = VisibilityRows(1, d.objects.size());
    const AccuracyReport plugged = measureAccuracy(scene, d, r);
    EXPECT_EQ(plugged.edgeVisible, 0u);
    EXPECT_EQ(plugged.referenceVisible, plugged.missed) << "only what the area rays see is missed here";
}

// The editor opens `.pvs.json` files too: the text pvsJson writes reads back to the same data
// (the binary encoding of both is byte-identical), and anything else is one error naming the key.
TEST(PvsFiles, PvsJsonReadsBackAndRefusesWhatItWouldNotWrite)
{
    PvsData d = sampleData();
    d.objects[5].bounds = Bounds{};   // an object without triangles: null corners
    d.objects[6].instances = {6, 9, 12};
    d.cellRows = VisibilityRows(d.cells.size(), d.cells.size());
    d.cellRows.set(1, 3, true);
    const std::string text = pvsJson(d);
    const PvsData back = decodePvsJson(text, "x.pvs.json");
    EXPECT_EQ(encodePvs(back), encodePvs(d));
    EXPECT_EQ(back.objects[6].instances, d.objects[6].instances);
    EXPECT_EQ(back.cellRows, d.cellRows);

    const auto refusal = [](const std::string& json) {
        try {
            decodePvsJson(json, "x.pvs.json");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    const std::string cell = R"({"min": [0, 0, 0], "max": [1, 1, 1]})";
    const std::string object = R"({"name": "a", "instance": 0, "min": [0, 0, 0], "max": [1, 1, 1]})";
    const auto doc = [&](const std::string& cells, const std::string& objects, const std::string& visible) {
        return R"({"version": 1, "scene_sha256": "s", "cells": )" + cells + R"(, "objects": )" + objects + R"(, "visible": )" +
               visible + "}";
    };
    EXPECT_EQ(refusal(doc("[" + cell + "]", "[" + object + "]", "[[0]]")), "accepted");
    const std::pair<std::string, std::string> cases[] = {
        {"not json", "invalid JSON"},
        {"[1, 2]", "must be a JSON object"},
        {R"({"version": 2})", "'version' must be 1"},
        {R"({"version": 1, "cells": []})", "'scene_sha256' is missing"},
        {doc("[" + cell + "]", "[" + object + "]", "[[1]]"), "'visible[0]' must list indices below 1"},
        {doc("[" + cell + "]", "[" + object + "," + object + "]", "[[1, 0]]"), "sorted, each once"},
        {doc("[" + cell + "]", "[" + object + "," + object + "]", "[[0, 0]]"), "sorted, each once"},
        {doc("[" + cell + "]", "[" + object + "]", "[[0], [0]]"), "'visible' must hold one list per cell (1)"},
        {doc("[" + cell + "]", "[" + object + "]", "[[-1]]"), "'visible[0][0]' must be a whole number"},
        {doc("[" + cell + "]", "[" + object + "]", "[[4294967296]]"), "'visible[0][0]' must be a whole number"},
        {doc(R"([{"min": [0, 0, 0], "max": [1, 1]}])", "[]", "[[]]"), "'cells[0].max' must be three numbers"},
        {doc(R"([{"min": [0, 0, 0], "max": [null, null, null]}])", "[]", "[[]]"), "'cells[0]' must have a finite min and max"},
        {doc(R"([{"min": [1, 0, 0], "max": [0, 1, 1]}])", "[]", "[[]]"), "x.pvs.json"},
        {doc(R"([{"min": [0, 0, 0], "max": [1e30, 1, 1]}])", "[]", "[[]]"), "x.pvs.json"},
        {doc("[" + cell + "]", R"([{"name": 3, "instance": 0, "min": [0, 0, 0], "max": [1, 1, 1]}])", "[[]]"), "'objects[0].name' must be a string"},
        {doc("[" + cell + "]", R"([{"name": "a", "min": [0, 0, 0], "max": [1, 1, 1]}])", "[[]]"), "'objects[0].instance' is missing"},
        {doc("[" + cell + "]", R"([{"name": "a", "instance": 0, "min": [2, 0, 0], "max": [1, 1, 1]}])", "[[]]"), "not finite, inverted"},
        {doc("[" + cell + "]", "[" + object + "]", "[[0]]").insert(1, R"("visible_cells": [[5]], )"), "'visible_cells[0]' must list indices below 1"},
        {std::string(5000, '['), "nested deeper"},
    };
    for (const auto& [json, expected] : cases) {
        const std::string why = refusal(json);
        EXPECT_NE(why.find(expected), std::string::npos) << json.substr(0, 120) << " -> " << why;
        EXPECT_EQ(why.find('\n'), std::string::npos) << why;
    }
}

} // namespace
} // namespace sightline::pvs
