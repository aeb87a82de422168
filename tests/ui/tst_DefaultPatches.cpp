// A bare level's first patches (editor/DefaultPatches.h) on levels made elsewhere and on each generated
// kind: both patches inside the level, 1.5 m over a real floor (the first surface straight below
// faces up), facing each other across open space with some rays between them unblocked, nothing
// the placement warnings would call out, and, inside buildings, a ceiling overhead.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "editor/DefaultPatches.h"
#include "EditorDocument.h"
#include "editor/LiveVisibility.h"
#include "editor/PatchWarnings.h"
#include "editor/Picking.h"
#include "UiTestScene.h"
#include "demo/BenchScenes.h"
#include "demo/DemoLevel.h"
#include "plugins/SceneFormats.h"
#include "project/SceneImport.h"

namespace sightline::ui {
namespace {

const std::filesystem::path kLevels = std::filesystem::path(SIGHTLINE_TEST_DATA) / "levels";

bool windingFacesUp(const WorldTriangles& triangles, std::size_t t)
{
    const glm::dvec3 a(triangles.vertices[3 * t]), b(triangles.vertices[3 * t + 1]), c(triangles.vertices[3 * t + 2]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    return n.y > 0.5 * glm::length(n);
}

/// Everything a designer expects of the first pair, for `level` (named `name`).
void expectAPairToLookAcross(const Scene& level, const Patch& source, const Patch& receiver, const std::string& name,
                             bool indoors)
{
    SCOPED_TRACE(name);
    const WorldTriangles triangles = worldTriangles(level);
    const Bounds bounds = level.bounds();
    for (const Patch* patch : {&source, &receiver}) {
        const glm::dvec3 c = patch->centre();
        for (int k = 0; k < 3; ++k) {
            EXPECT_GT(c[k], double(bounds.min[k]));
            EXPECT_LT(c[k], double(bounds.max[k]));
        }
        const auto floor = pickSurface(triangles, Ray{c, {0.0, -1.0, 0.0}});
        ASSERT_TRUE(floor) << "nothing under a patch at " << c.x << ", " << c.y << ", " << c.z;
        EXPECT_NEAR(floor->distance, 1.5, 0.02);
        EXPECT_TRUE(windingFacesUp(triangles, floor->triangle)) << "the surface under a patch is an underside";
        if (indoors) {
            EXPECT_TRUE(pickSurface(triangles, Ray{c, {0.0, 1.0, 0.0}})) << "open sky over an indoor patch";
        }
        EXPECT_NEAR(patch->normal().y, 0.0, 1e-9);   // upright
    }
    EXPECT_GT(glm::length(receiver.centre() - source.centre()), 4.0) << "across the level, not side by side";
    for (const std::string& warning : patchWarnings(triangles, bounds, source, receiver))
        ADD_FAILURE() << warning;
    LiveVisibility live;
    live.setScene(level);
    const VisibilityResult result = live.sample(source, receiver);
    ASSERT_TRUE(result.valid) << result.error;
    EXPECT_GT(result.visibleFraction(), 0.0);
}

} // namespace

// Original Quake maps (tests/data/SOURCES.md): many rooms on several floors, in a void with no
// faces on the outside and none inside the solid brushes; the level's box is mostly that void.
TEST(DefaultPatches, QuakeMapsGetAPairInsideARoomOverItsFloor)
{
    for (const char* map : {"quake-e1m1.ply", "quake-dm3.ply", "quake-e2m1.ply"}) {
        EditorDocument document;
        document.open(kLevels / map);
        EXPECT_EQ(sceneImport(document.project()).up, "+y") << map;   // the up guess keeps it upright
        expectAPairToLookAcross(document.scene(), document.project().source, document.project().receiver, map, true);
    }
}

// The converted files are the ones SOURCES.md describes.
TEST(DefaultPatches, TheQuakeLevelsAreTheOnesTheSourcesName)
{
    const std::pair<const char*, std::size_t> levels[] = {{"quake-e1m1.ply", 14186}, {"quake-dm3.ply", 9200}, {"quake-e2m1.ply", 15548}};
    for (const auto& [map, triangles] : levels)
        EXPECT_EQ(loadScene(kLevels / map).triangleCount(), triangles) << map;
}

// Every generated kind, on two seeds each: rooms with clutter, a dense statue, an architectural
// interior, an open hall; and the demo, a terrain under open sky.
TEST(DefaultPatches, GeneratedLevelsAndATerrainGetAPairOverTheirFloors)
{
    for (const demo::BenchKind kind : demo::kBenchKinds)
        for (const std::uint64_t seed : {1u, 2u}) {
            const demo::BenchScene bench = demo::makeBenchScene(kind, seed);
            const auto [source, receiver] = defaultPatchesInOpenSpace(bench.scene);
            expectAPairToLookAcross(bench.scene, source, receiver, bench.name, false);
        }
    const Scene demo = demo::makeDemoLevel();
    const auto [source, receiver] = defaultPatchesInOpenSpace(demo);
    expectAPairToLookAcross(demo, source, receiver, "demo", true);

    const std::filesystem::path folder = std::filesystem::temp_directory_path() / "sightline-default-patches";
    EditorDocument document;
    document.open(test::writeTerrainObj(folder));
    expectAPairToLookAcross(document.scene(), document.project().source, document.project().receiver, "terrain", false);
}

} // namespace sightline::ui
