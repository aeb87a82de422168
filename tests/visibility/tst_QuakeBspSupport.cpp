// The Quake BSP test support (tests/support/VoxelBsp.h, EngineBspReader.h) checked against each
// other: the voxel levels' files read back as an engine would must put every voxel in the leaf the
// builder says, with its contents, and give back the visibility the builder was asked to write.
// The PVS writer's tests lean on both, so a slip in either would hide a slip in the writer.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "EngineBspReader.h"
#include "VoxelBsp.h"

namespace sightline::test {
namespace {

constexpr BspVersion kVersions[] = {BspVersion::Bsp29, BspVersion::Bsp2};

const char* versionName(BspVersion v) { return v == BspVersion::Bsp29 ? "BSP29" : "BSP2"; }

// Two 3x3x2 rooms side by side in solid, split by a one-voxel wall with an optional door in it.
VoxelLevel twoRooms(bool door)
{
    VoxelLevel level = makeVoxelLevel(9, 5, 4);
    for (int z = 1; z <= 2; ++z)
        for (int y = 1; y <= 3; ++y)
            for (int x = 1; x <= 7; ++x)
                if (x != 4)
                    level.at(x, y, z) = kContentsEmpty;
    if (door)
        level.at(4, 2, 1) = kContentsEmpty;
    return level;
}

// A room with a water pool on its floor, and one voxel each of slime, lava and sky, so every
// contents value passes through both formats; an odd voxel size makes BSP29's boxes round.
VoxelLevel liquids()
{
    VoxelLevel level = makeVoxelLevel(8, 6, 5, kContentsSolid, 40.5);
    for (int z = 1; z <= 3; ++z)
        for (int y = 1; y <= 4; ++y)
            for (int x = 1; x <= 6; ++x)
                level.at(x, y, z) = z == 1 && x <= 4 ? kContentsWater : kContentsEmpty;
    level.at(6, 4, 1) = kContentsSlime;
    level.at(5, 1, 1) = kContentsLava;
    level.at(3, 2, 3) = kContentsSky;
    return level;
}

// A floor of alternating empty and water voxels: every open voxel is its own leaf, 2304 of them,
// so a vis row is 288 bytes and its zero runs pass 255.
VoxelLevel checkerboard()
{
    VoxelLevel level = makeVoxelLevel(50, 50, 3);
    for (int y = 1; y <= 48; ++y)
        for (int x = 1; x <= 48; ++x)
            level.at(x, y, 1) = (x + y) % 2 ? kContentsWater : kContentsEmpty;
    return level;
}

// The contents of each leaf, from a build without visibility (the tree does not depend on it).
std::vector<int> leafContentsOf(const VoxelLevel& level, BspVersion version)
{
    const VoxelBsp built = voxelBsp(level, version);
    std::vector<int> contents(static_cast<std::size_t>(built.visleafs) + 1, kContentsSolid);
    for (std::size_t i = 0; i < level.contents.size(); ++i)
        contents[static_cast<std::size_t>(built.leafOfVoxel[i])] = level.contents[i];
    return contents;
}

void setI32(std::string& bytes, std::size_t at, std::int32_t v)
{
    for (std::size_t i = 0; i < 4; ++i)
        bytes[at + i] = static_cast<char>((static_cast<std::uint32_t>(v) >> (8 * i)) & 0xffu);
}

std::int32_t getI32(const std::string& bytes, std::size_t at)
{
    std::uint32_t v = 0;
    for (std::size_t i = 4; i-- > 0;)
        v = (v << 8) | static_cast<std::uint8_t>(bytes[at + i]);
    return static_cast<std::int32_t>(v);
}

std::size_t lumpOffset(const std::string& bytes, int lump) { return static_cast<std::size_t>(getI32(bytes, 4 + 8 * static_cast<std::size_t>(lump))); }
std::size_t lumpLength(const std::string& bytes, int lump) { return static_cast<std::size_t>(getI32(bytes, 8 + 8 * static_cast<std::size_t>(lump))); }

std::size_t leafRecord(const std::string& bytes, BspVersion version, int leaf)
{
    return lumpOffset(bytes, 10) + (version == BspVersion::Bsp2 ? 44u : 28u) * static_cast<std::size_t>(leaf);
}

// readEngineBsp must throw std::runtime_error, and say why.
void expectRejected(const std::string& bytes, const std::string& why)
{
    try {
        readEngineBsp(bytes);
        ADD_FAILURE() << "read without error, expected: " << why;
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << "message: " << e.what();
    }
}

// Builds `level`, reads it back, and checks the leaves of every voxel and every vis bit.
void checkRoundTrip(const VoxelLevel& level, BspVersion version, const std::function<bool(int, int)>& visible)
{
    SCOPED_TRACE(versionName(version));
    const VoxelBsp built = voxelBsp(level, version, visible);
    const EngineBsp bsp = readEngineBsp(built.bytes);

    if (version == BspVersion::Bsp29) {
        EXPECT_EQ(bsp.version, 29);
    } else {
        EXPECT_EQ(bsp.version, kBsp2Version);
        EXPECT_EQ(built.bytes.substr(0, 4), "BSP2");
    }
    for (int k = 0; k < 15; ++k)
        EXPECT_EQ(bsp.lumps[static_cast<std::size_t>(k)].first % 4, 0) << "lump " << k;
    EXPECT_EQ(bsp.lumpBytes(0), std::string("{\n\"classname\" \"worldspawn\"\n}\n") + '\0');
    EXPECT_EQ(bsp.visleafs, built.visleafs);
    ASSERT_EQ(bsp.leafContents.size(), static_cast<std::size_t>(built.visleafs) + 1);
    EXPECT_EQ(bsp.leafContents[0], kContentsSolid);
    EXPECT_EQ(bsp.leafVisofs[0], -1);
    for (const auto& p : bsp.planes)
        EXPECT_EQ(p[0] + p[1] + p[2], 1.0f) << "kd-tree planes are axis-aligned with positive normals";

    ASSERT_EQ(built.leafOfVoxel.size(), level.contents.size());
    std::vector<int> voxelsInLeaf(bsp.leafContents.size(), 0);
    int wrongLeaf = 0, wrongContents = 0;
    for (int z = 0; z < level.nz; ++z)
        for (int y = 0; y < level.ny; ++y)
            for (int x = 0; x < level.nx; ++x) {
                const std::size_t i = level.index(x, y, z);
                const int leaf = enginePointInLeaf(bsp, (x + 0.5) * level.size, (y + 0.5) * level.size, (z + 0.5) * level.size);
                if (leaf != built.leafOfVoxel[i] && wrongLeaf++ == 0)
                    ADD_FAILURE() << "voxel " << x << "," << y << "," << z << ": engine leaf " << leaf << ", builder leaf "
                                  << built.leafOfVoxel[i];
                if (bsp.leafContents[static_cast<std::size_t>(leaf)] != level.contents[i] && wrongContents++ == 0)
                    ADD_FAILURE() << "voxel " << x << "," << y << "," << z << ": leaf contents "
                                  << bsp.leafContents[static_cast<std::size_t>(leaf)] << ", voxel " << level.contents[i];
                ++voxelsInLeaf[static_cast<std::size_t>(leaf)];
            }
    EXPECT_EQ(wrongLeaf, 0);
    EXPECT_EQ(wrongContents, 0);
    for (int leaf = 1; leaf <= bsp.visleafs; ++leaf)
        EXPECT_GT(voxelsInLeaf[static_cast<std::size_t>(leaf)], 0) << "leaf " << leaf << " holds no voxel";

    int wrongBits = 0;
    for (int a = 1; a <= bsp.visleafs; ++a) {
        const std::vector<bool> pvs = engineLeafPvs(bsp, a);
        ASSERT_EQ(pvs.size(), static_cast<std::size_t>(bsp.visleafs));
        if (!visible) {
            EXPECT_EQ(bsp.leafVisofs[static_cast<std::size_t>(a)], -1);
        }
        for (int b = 1; b <= bsp.visleafs; ++b) {
            const bool expected = visible ? visible(a, b) : true;
            if (pvs[static_cast<std::size_t>(b - 1)] != expected && wrongBits++ == 0)
                ADD_FAILURE() << "leaf " << a << " sees leaf " << b << ": engine " << pvs[static_cast<std::size_t>(b - 1)]
                              << ", expected " << expected;
        }
        // Padding bits past visleafs stay clear in a written row.
        if (visible && bsp.visleafs % 8 != 0) {
            const std::vector<std::uint8_t> row = engineDecompressVis(bsp, a);
            EXPECT_EQ(row.back() >> (bsp.visleafs % 8), 0) << "leaf " << a;
        }
    }
    EXPECT_EQ(wrongBits, 0);
    if (!visible) {
        EXPECT_TRUE(bsp.lumpBytes(4).empty());
    }
}

TEST(QuakeBspSupport, TreeIsTheSpecifiedKdTree)
{
    // [solid, empty, solid]: split at x = 1 (the middle of 3), then the front half at x = 2.
    VoxelLevel level = makeVoxelLevel(3, 1, 1);
    level.at(1, 0, 0) = kContentsEmpty;
    for (const BspVersion version : kVersions) {
        SCOPED_TRACE(versionName(version));
        const VoxelBsp built = voxelBsp(level, version);
        EXPECT_EQ(built.visleafs, 1);
        EXPECT_EQ(built.leafOfVoxel, (std::vector<int>{0, 1, 0}));
        const EngineBsp bsp = readEngineBsp(built.bytes);
        ASSERT_EQ(bsp.planes.size(), 2u);
        EXPECT_EQ(bsp.planes[0], (std::array<float, 4>{1, 0, 0, 64}));
        EXPECT_EQ(bsp.planes[1], (std::array<float, 4>{1, 0, 0, 128}));
        ASSERT_EQ(bsp.nodes.size(), 2u);
        EXPECT_EQ(bsp.nodes[0].plane, 0);
        EXPECT_EQ(bsp.nodes[0].children[0], 1);
        EXPECT_EQ(bsp.nodes[0].children[1], -1);
        EXPECT_EQ(bsp.nodes[1].plane, 1);
        EXPECT_EQ(bsp.nodes[1].children[0], -1);
        EXPECT_EQ(bsp.nodes[1].children[1], -2);
        EXPECT_EQ(bsp.leafContents, (std::vector<int>{kContentsSolid, kContentsEmpty}));
        // On a plane counts as back (d > 0 is front).
        EXPECT_EQ(enginePointInLeaf(bsp, 128.0, 32.0, 32.0), 1);
        EXPECT_EQ(enginePointInLeaf(bsp, 128.5, 32.0, 32.0), 0);
    }
}

TEST(QuakeBspSupport, HomogeneousGridIsRefused)
{
    EXPECT_THROW(voxelBsp(makeVoxelLevel(2, 2, 2, kContentsEmpty)), std::invalid_argument);
    VoxelLevel bad = makeVoxelLevel(2, 1, 1);
    bad.contents.pop_back();
    EXPECT_THROW(voxelBsp(bad), std::invalid_argument);
}

TEST(QuakeBspSupport, TwoRoomsWithDoor)
{
    const VoxelLevel level = twoRooms(true);
    for (const BspVersion version : kVersions) {
        checkRoundTrip(level, version, {});
        const std::vector<int> contents = leafContentsOf(level, version);
        checkRoundTrip(level, version, [&](int a, int b) { return contents[static_cast<std::size_t>(a)] == contents[static_cast<std::size_t>(b)]; });
        checkRoundTrip(level, version, [](int a, int b) { return (a * 7 + b * 13) % 5 < 2; });
    }
}

TEST(QuakeBspSupport, SealedRoomNextToAnother)
{
    const VoxelLevel level = twoRooms(false);
    for (const BspVersion version : kVersions) {
        checkRoundTrip(level, version, {});
        // Each room's leaves see only their own room: x < 4 is the first.
        const VoxelBsp built = voxelBsp(level, version);
        std::vector<int> room(static_cast<std::size_t>(built.visleafs) + 1, -1);
        for (int z = 0; z < level.nz; ++z)
            for (int y = 0; y < level.ny; ++y)
                for (int x = 0; x < level.nx; ++x)
                    if (const int leaf = built.leafOfVoxel[level.index(x, y, z)]; leaf != 0)
                        room[static_cast<std::size_t>(leaf)] = x < 4 ? 0 : 1;
        checkRoundTrip(level, version, [&](int a, int b) { return room[static_cast<std::size_t>(a)] == room[static_cast<std::size_t>(b)]; });
    }
}

TEST(QuakeBspSupport, LiquidsKeepTheirContents)
{
    const VoxelLevel level = liquids();
    for (const BspVersion version : kVersions) {
        checkRoundTrip(level, version, {});
        const std::vector<int> contents = leafContentsOf(level, version);
        checkRoundTrip(level, version, [&](int a, int b) { return contents[static_cast<std::size_t>(a)] == contents[static_cast<std::size_t>(b)]; });
    }
}

TEST(QuakeBspSupport, LongZeroRunsCompressLikeVis)
{
    const VoxelLevel level = checkerboard();
    const auto onlyItself = [](int a, int b) { return a == b; };
    for (const BspVersion version : kVersions) {
        checkRoundTrip(level, version, onlyItself);
        const VoxelBsp built = voxelBsp(level, version, onlyItself);
        ASSERT_EQ(built.visleafs, 48 * 48);
        const EngineBsp bsp = readEngineBsp(built.bytes);
        // Leaf 1's row: its own bit, then 287 zero bytes as a run of 255 and one of 32.
        const std::string vis = bsp.lumpBytes(4);
        EXPECT_EQ(vis.substr(static_cast<std::size_t>(bsp.leafVisofs[1]), 5), std::string("\x01\x00\xff\x00\x20", 5));
    }
}

TEST(QuakeBspSupport, ReaderRejectsBrokenFiles)
{
    const VoxelLevel level = checkerboard();
    const auto onlyItself = [](int a, int b) { return a == b; };
    for (const BspVersion version : kVersions) {
        SCOPED_TRACE(versionName(version));
        const std::string good = voxelBsp(level, version, onlyItself).bytes;
        ASSERT_NO_THROW(readEngineBsp(good));
        const std::size_t visOfs = lumpOffset(good, 4), visLen = lumpLength(good, 4);
        const std::size_t leaf1 = leafRecord(good, version, 1);
        const std::int32_t leaf1Row = getI32(good, leaf1 + 4);

        expectRejected(good.substr(0, 100), "shorter than the header");
        expectRejected(good.substr(0, good.size() - 1), "outside the file");

        std::string bytes = good;
        setI32(bytes, 0, 30);
        expectRejected(bytes, "unknown version");
        bytes.replace(0, 4, "2PSB");
        expectRejected(bytes, "unknown version");

        bytes = good;
        setI32(bytes, 4 + 8 * 10, static_cast<std::int32_t>(good.size() - 4));   // leafs lump starts 4 bytes from the end
        expectRejected(bytes, "outside the file");
        bytes = good;
        setI32(bytes, 8 + 8 * 1, static_cast<std::int32_t>(lumpLength(good, 1) + 1));   // planes
        expectRejected(bytes, "not a multiple");

        bytes = good;
        setI32(bytes, leaf1 + 4, static_cast<std::int32_t>(visLen));
        expectRejected(bytes, "outside the vis lump");
        bytes = good;
        setI32(bytes, leaf1 + 4, -2);
        expectRejected(bytes, "outside the vis lump");
        bytes = good;
        setI32(bytes, leaf1 + 4, static_cast<std::int32_t>(visLen - 1));   // the last row's last byte, then nothing
        expectRejected(bytes, "past the vis lump");
        bytes = good;
        bytes[visOfs + static_cast<std::size_t>(leaf1Row) + 4] = 33;   // 255 + 33 zero bytes overrun the 288-byte row
        expectRejected(bytes, "past the row length");
        bytes[visOfs + static_cast<std::size_t>(leaf1Row) + 4] = 0;
        expectRejected(bytes, "length 0");

        const std::size_t node0 = lumpOffset(good, 5);
        bytes = good;
        setI32(bytes, node0, static_cast<std::int32_t>(lumpLength(good, 1) / 20));
        expectRejected(bytes, "plane");
        bytes = good;
        const auto numNodes = static_cast<std::int32_t>(lumpLength(good, 5) / (version == BspVersion::Bsp2 ? 44 : 24));
        if (version == BspVersion::Bsp2) {
            setI32(bytes, node0 + 4, numNodes);
        } else {
            bytes[node0 + 4] = static_cast<char>(numNodes & 0xff);
            bytes[node0 + 5] = static_cast<char>((numNodes >> 8) & 0xff);
        }
        expectRejected(bytes, "child");

        bytes = good;
        const auto numLeafs = static_cast<std::int32_t>(lumpLength(good, 10) / (version == BspVersion::Bsp2 ? 44 : 28));
        setI32(bytes, lumpOffset(good, 14) + 52, numLeafs);   // visleafs counts leaf 0 too
        expectRejected(bytes, "visleafs");
    }
}

}   // namespace
}   // namespace sightline::test
