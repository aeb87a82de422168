// The paper's Hough bitmask table (§5) and the CPU sampler's table mode.
#include <gtest/gtest.h>

#include "TestScenes.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"
#include "visibility/HoughMaskTable.h"
#include "visibility/RayCastSampler.h"

using namespace sightline;
using namespace sightline::test;

namespace {
bool has(const std::uint64_t* mask, int bit) { return (mask[bit >> 6] >> (bit & 63)) & 1u; }
} // namespace

TEST(HoughMaskTable, LinesThroughTheSquareSplitTheSamples)
{
    const int na = 8, nb = 4;
    const HoughMaskTable table(na, nb, 256, 128);
    // Upward vertical line at s = 0.5: its left is s < 0.5, the columns a < 4.
    const std::uint64_t* up = table.lookup(0.5, 0.0, 0.5, 1.0);
    // Rightward horizontal line at t = 0.3: its left is t > 0.3, rows b >= 2 (t = 0.625, 0.875),
    // and row 1 (t = 0.375) too.
    const std::uint64_t* right = table.lookup(0.0, 0.3, 1.0, 0.3);
    for (int b = 0; b < nb; ++b)
        for (int a = 0; a < na; ++a) {
            EXPECT_EQ(has(up, b * na + a), a < 4) << a << "," << b;
            EXPECT_EQ(has(right, b * na + a), b >= 1) << a << "," << b;
        }
    // Lines that miss the square: everything or nothing is on their left.
    const std::uint64_t* down = table.lookup(2.0, 1.0, 2.0, 0.0);   // downward at s = 2: left is s > 2
    const std::uint64_t* up2 = table.lookup(2.0, 0.0, 2.0, 1.0);    // upward at s = 2: left is s < 2
    int downCount = 0, upCount = 0;
    for (int i = 0; i < na * nb; ++i) {
        downCount += has(down, i);
        upCount += has(up2, i);
    }
    EXPECT_EQ(downCount, 0);
    EXPECT_EQ(upCount, na * nb);
    EXPECT_THROW(HoughMaskTable(8, 8, 2, 2), Error);
}

TEST(HoughMaskTable, TableModeErrorFallsWithResolution)
{
    const Mesh soup = randomSoup(3, 300, -0.3f, 1.3f, 0.3f, 1.7f, 0.1f);
    const Scene scene = sceneOf({soup});
    const Patch source = xyPatch(0, 32, 32), receiver = xyPatch(2, 32, 32);
    const HiddenSampleMap reference = RayCastScene(scene).sample(source, receiver);
    const CpuBitmaskSampler sampler(scene);
    auto error = [&](int w, int h) {
        BitmaskStats stats;
        const HiddenSampleMap map = sampler.sample(
            source, receiver, {.mode = MaskMode::Table, .tableWidth = w, .tableHeight = h}, &stats);
        EXPECT_STREQ(stats.strategy, "bitmask");
        return double(map.differenceCount(reference)) / double(map.rayCount());
    };
    const double coarse = error(32, 16), medium = error(128, 64), fine = error(1024, 512);
    EXPECT_GT(coarse, medium);
    EXPECT_GT(medium, fine);
    EXPECT_GT(coarse, 0.001);   // the nearest-texel table is visibly approximate when coarse
    EXPECT_LT(fine, 0.01);
}
