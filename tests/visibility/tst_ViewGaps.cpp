// The openings a view or a PVS pair leaks through (visibility/suggest/Openings.h) on scenes whose openings are
// known: a wall with two doors of known widths, a window above a low wall, and the distance grid
// under them against exact distances to a plane.
#include <gtest/gtest.h>

#include "TestScenes.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/suggest/DistanceGrid.h"
#include "visibility/suggest/ViewGaps.h"
#include "visibility/pvs/PvsReference.h"

using namespace sightline;
using namespace sightline::test;

namespace {

/// The wall z = 2, x in [-3, 3], y in [0, 3], less the openings [x0, x1] x [y0, y1].
Scene wallWithOpenings(const std::vector<std::array<float, 4>>& openings)
{
    // Columns between the openings' x ranges, and above / below each opening.
    std::vector<Mesh> parts;
    float x = -3.0f;
    for (const auto& [x0, x1, y0, y1] : openings) {
        parts.push_back(quad({x, 0.0f, 2.0f}, {x0 - x, 0.0f, 0.0f}, {0.0f, 3.0f, 0.0f}, "column"));
        if (y0 > 0.0f)
            parts.push_back(quad({x0, 0.0f, 2.0f}, {x1 - x0, 0.0f, 0.0f}, {0.0f, y0, 0.0f}, "sill"));
        parts.push_back(quad({x0, y1, 2.0f}, {x1 - x0, 0.0f, 0.0f}, {0.0f, 3.0f - y1, 0.0f}, "lintel"));
        x = x1;
    }
    parts.push_back(quad({x, 0.0f, 2.0f}, {3.0f - x, 0.0f, 0.0f}, {0.0f, 3.0f, 0.0f}, "column"));
    return sceneOf(parts);
}

Patch patchAt(double z)
{
    Patch p;
    p.corner = {-2.5, 0.2, z};
    p.u = {4.5, 0.0, 0.0};
    p.v = {0.0, 1.6, 0.0};
    return p;   // 32 x 32 samples
}

} // namespace

TEST(DistanceGrid, MeasuresTheDistanceToAPlaneToAboutAVoxel)
{
    const Scene floor = sceneOf({quad({-5.0f, 0.0f, -5.0f}, {0.0f, 0.0f, 10.0f}, {10.0f, 0.0f, 0.0f}, "floor")});
    const suggest::DistanceGrid grid(worldTriangles(floor), {-2, -1, -2}, {2, 3, 2}, 0.05);
    for (const double y : {-0.8, -0.3, 0.0, 0.12, 0.37, 1.5, 2.9}) {
        const double d = grid.distance({0.3, y, -0.7});
        EXPECT_NEAR(d, std::abs(y), 1.5 * grid.voxel()) << "y = " << y;
    }
}

TEST(ViewGaps, TwoDoorsOfKnownWidthsAreTwoGroupsLargestFirst)
{
    // A 1 m door at x in [-2, -1] and a 0.5 m one at [1, 1.5], both 2 m high.
    const Scene wall = wallWithOpenings({{-2.0f, -1.0f, 0.0f, 2.0f}, {1.0f, 1.5f, 0.0f, 2.0f}});
    const Patch source = patchAt(0.0), receiver = patchAt(4.0);
    const HiddenSampleMap map = CpuBitmaskSampler(wall).sample(source, receiver);
    const std::uint64_t unblocked = map.rayCount() - map.blockedCount();
    ASSERT_GT(unblocked, 1000u);
    const std::vector<suggest::Opening> gaps = suggest::findViewGaps(worldTriangles(wall), source, receiver, {}, map);
    ASSERT_EQ(gaps.size(), 2u);
    EXPECT_EQ(gaps[0].rays + gaps[1].rays, unblocked);
    EXPECT_GT(gaps[0].rays, gaps[1].rays);
    const double slack = 0.1;   // about two voxels of the 6 m box
    const std::array<std::pair<double, double>, 2> doors{{{-2.0, -1.0}, {1.0, 1.5}}};
    for (std::size_t k = 0; k < 2; ++k) {
        const suggest::Opening& gap = gaps[k];
        EXPECT_NEAR(gap.centre.z, 2.0, slack) << k;
        EXPECT_GE(gap.min.x, doors[k].first - slack) << k;
        EXPECT_LE(gap.max.x, doors[k].second + slack) << k;
        EXPECT_GT(gap.max.x - gap.min.x, 0.5 * (doors[k].second - doors[k].first)) << k;
        EXPECT_FALSE(gap.raySample.empty());
        for (std::uint64_t ray : gap.raySample)
            EXPECT_FALSE(map.blocked(int(ray / 1024), int(ray % 1024)));
    }
    // Half the width, more or less: the clearance at a door's middle.
    EXPECT_NEAR(gaps[0].clearance, 0.5, 0.15);
    EXPECT_NEAR(gaps[1].clearance, 0.25, 0.15);
}

TEST(ViewGaps, AWindowAboveALowWallAndAClosedViewHasNone)
{
    const Scene window = wallWithOpenings({{-1.0f, 0.5f, 0.9f, 1.6f}});
    const Patch source = patchAt(0.0), receiver = patchAt(4.0);
    const HiddenSampleMap map = CpuBitmaskSampler(window).sample(source, receiver);
    const std::vector<suggest::Opening> gaps = suggest::findViewGaps(worldTriangles(window), source, receiver, {}, map);
    ASSERT_EQ(gaps.size(), 1u);
    EXPECT_NEAR(gaps[0].centre.z, 2.0, 0.1);
    EXPECT_GT(gaps[0].min.y, 0.8);
    EXPECT_LT(gaps[0].max.y, 1.7);

    const Scene closed = wallWithOpenings({});
    const HiddenSampleMap none = CpuBitmaskSampler(closed).sample(source, receiver);
    EXPECT_TRUE(suggest::findViewGaps(worldTriangles(closed), source, receiver, {}, none).empty());
}

// The PVS reference's gaps are openings by the same mechanism: from a cell in front of the wall
// with two doors, a target behind it that an (empty) PVS culls is seen through both doors, and
// every witness of each gap passes through that gap's door.
TEST(PvsGaps, AMissedPairIsGroupedIntoTheDoorsItIsSeenThrough)
{
    Scene scene = wallWithOpenings({{-2.0f, -1.0f, 0.0f, 2.0f}, {1.0f, 1.5f, 0.0f, 2.0f}});
    const Scene target = sceneOf({quad({-3.0f, 0.0f, 4.0f}, {6.0f, 0.0f, 0.0f}, {0.0f, 3.0f, 0.0f}, "target")});
    scene.meshes.push_back(target.meshes[0]);
    Instance instance = target.instances[0];
    instance.mesh = std::uint32_t(scene.meshes.size() - 1);
    scene.instances.push_back(instance);

    pvs::PvsData pvs;
    pvs.sceneSha256 = std::string(64, 'a');
    pvs.cells = {Bounds{{-1.0f, 0.5f, 0.3f}, {1.0f, 1.5f, 0.8f}}};
    pvs::PvsObject object;
    object.name = "target";
    object.instance = std::uint32_t(scene.instances.size() - 1);
    object.instances = {object.instance};
    object.bounds = Bounds{{-3.0f, 0.0f, 4.0f}, {3.0f, 3.0f, 4.0f}};
    pvs.objects = {object};
    pvs.rows = pvs::VisibilityRows(1, 1);   // everything culled

    const pvs::AccuracyReport report = pvs::measureAccuracy(scene, pvs, {});
    ASSERT_EQ(report.missed, 1u);
    ASSERT_EQ(report.gaps.size(), 2u);
    EXPECT_GE(report.gaps[0].opening.rays, report.gaps[1].opening.rays);
    const std::array<std::pair<double, double>, 2> doors{{{-2.0, -1.0}, {1.0, 1.5}}};
    for (std::size_t k = 0; k < 2; ++k) {
        const pvs::Gap& gap = report.gaps[k];
        EXPECT_EQ(gap.cell, 0u);
        EXPECT_EQ(gap.object, 0u);
        EXPECT_NEAR(gap.opening.centre.z, 2.0, 0.2) << k;
        EXPECT_GT(gap.opening.centre.x, doors[k].first) << k;
        EXPECT_LT(gap.opening.centre.x, doors[k].second) << k;
        ASSERT_FALSE(gap.witnesses.empty());
        EXPECT_LE(gap.witnesses.size(), std::min<std::size_t>(pvs::kGapWitnessSample, gap.opening.rays));
        auto throughDoor = [&](glm::vec3 from, glm::vec3 to) {
            const float t = (2.0f - from.z) / (to.z - from.z);
            const float x = from.x + t * (to.x - from.x);
            return x >= doors[k].first - 1e-3 && x <= doors[k].second + 1e-3;
        };
        EXPECT_TRUE(throughDoor(gap.from, gap.to)) << k;
        EXPECT_NEAR(gap.to.z, 4.0f, 1e-3f);
        for (const auto& [from, to] : gap.witnesses) {
            EXPECT_TRUE(throughDoor(from, to)) << k;
            EXPECT_GE(from.z, 0.3f);
            EXPECT_LE(from.z, 0.8f);
        }
    }
}
