// `sightline-cli coarse` as a user runs it: the conservative (inner) kind never blocks a ray the
// original lets through, counted over every one of 32x32 x 32x32 rays by the exact sampler; the
// closest kind keeps to its triangle budget and says how many rays it answers differently.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRunner.h"
#include "TestScenes.h"
#include "plugins/SceneFormats.h"

using namespace sightline;
using namespace sightline::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

class CoarseCli : public CliFolderTest {
protected:
    void SetUp() override
    {
        CliFolderTest::SetUp();
        // A lumpy closed torus of 18,432 triangles standing across the view, 2 m from each patch.
        Scene level;
        level.addMeshInstance(closedTorus({0.5, 0.5, 2.0}, 0.6, 0.25, 192, 48, 0.15));
        saveScene(level, folder / "torus.glb");
        const json project = {
            {"version", 1},
            {"scene", "torus.glb"},
            {"source", {{"corner", {-0.5, -0.5, 0}}, {"u", {2, 0, 0}}, {"v", {0, 2, 0}}, {"samples", {32, 32}}}},
            {"receiver", {{"corner", {-0.3, -0.4, 4}}, {"u", {1.8, 0, 0.2}}, {"v", {0, 1.8, 0}}, {"samples", {32, 32}}}}};
        std::ofstream(folder / "p.json") << project.dump(2);
    }
};

} // namespace

TEST_F(CoarseCli, InnerOccludersNeverBlockARayTheOriginalLetsThrough)
{
    for (const int resolution : {16, 48}) {
        const json r = runJson("coarse " + (folder / "p.json").string() + " --kind inner --resolution " +
                               std::to_string(resolution) + " --repeat 1 --json");
        EXPECT_EQ(r["rays"], 1024 * 1024);
        EXPECT_EQ(r["false_blocked"], 0) << resolution;
        EXPECT_EQ(r["meshes_replaced"], 1);
        EXPECT_LT(r["triangles_after"].get<int>(), r["triangles_before"].get<int>());
        EXPECT_GT(r["false_free"].get<int>(), 0);   // the shell between the inside and the surface
    }
}

TEST_F(CoarseCli, ClosestKeepsItsBudgetAndCountsBothWays)
{
    const json r = runJson("coarse " + (folder / "p.json").string() + " --triangles 3000 --repeat 1 --json");
    EXPECT_LE(r["triangles_after"].get<int>(), 3002);
    EXPECT_EQ(r["triangles_before"], 192 * 48 * 2);
    const double differ = double(r["false_blocked"].get<int>() + r["false_free"].get<int>()) / (1024.0 * 1024.0);
    EXPECT_NEAR(r["disagreeing_fraction"].get<double>(), differ, 1e-12);
    EXPECT_LT(differ, 0.01);
    EXPECT_GT(r["ms_original"].get<double>(), 0.0);
    // Nothing to simplify, or no closed mesh: one line each.
    const CliRun none = runCli("coarse " + (folder / "p.json").string() + " --triangles 100000");
    EXPECT_NE(none.code, 0);
    EXPECT_TRUE(oneLine(none.err)) << none.err;
}
