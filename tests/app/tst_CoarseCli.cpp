// `sightline-cli coarse` as a user runs it: the conservative (inner) kind never blocks a ray the
// original lets through, counted over every one of 32x32 x 32x32 rays by the exact sampler; the
// closest kind keeps to its triangle budget and says how many rays it answers differently; a
// sweep is the same measurement at several counts, charted; --tolerance finds the fewest triangles
// within a share of the rays; --write keeps the stand-ins so that
// the copy's rays are the coarse level's.
#include <filesystem>
#include <fstream>

#include <QImage>
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
        writeTorusProject(folder, "p.json");
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

TEST_F(CoarseCli, SweepChartsAndWriteKeepsTheStandInsForTheRays)
{
    const std::string project = (folder / "p.json").string();
    // A sweep: one point per count, each the same measurement as a single run at that count.
    const fs::path chart = folder / "chart.png";
    const json sweep = runJson("coarse " + project + " --sweep 6000,1500 --chart " + chart.string() + " --repeat 1 --json");
    ASSERT_EQ(sweep["sweep"].size(), 2u);
    EXPECT_EQ(sweep["triangles_before"], 192 * 48 * 2);
    const json single = runJson("coarse " + project + " --triangles 1500 --repeat 1 --json");
    EXPECT_EQ(sweep["sweep"][1]["false_blocked"], single["false_blocked"]);
    EXPECT_EQ(sweep["sweep"][1]["false_free"], single["false_free"]);
    EXPECT_EQ(sweep["sweep"][1]["triangles"], single["triangles_after"]);
    const QImage image(QString::fromStdString(chart.string()));
    EXPECT_EQ(image.size(), QSize(1100, 700));

    // --write: the copy's rays are the coarse level's (shaft counts what the single run measured),
    // the original project is untouched.
    const std::string before = readAll(folder / "p.json");
    const json written = runJson("coarse " + project + " --triangles 1500 --repeat 1 --write " + (folder / "c.json").string() + " --json");
    EXPECT_EQ(written["written"], (folder / "c.json").string());
    EXPECT_EQ(readAll(folder / "p.json"), before);
    const json copy = json::parse(readAll(folder / "c.json"));
    EXPECT_EQ(copy["coarse_occluders"], json::parse(R"([{"instance": 0, "kind": "closest", "triangles": 1500}])"));
    const json fullShaft = runJson("shaft " + project + " --method cpu --json");
    const json coarseShaft = runJson("shaft " + (folder / "c.json").string() + " --method cpu --json");
    EXPECT_EQ(coarseShaft["coarse_occluders"], 1);
    EXPECT_EQ(coarseShaft["blocked"].get<std::int64_t>(),
              fullShaft["blocked"].get<std::int64_t>() + written["false_blocked"].get<std::int64_t>() -
                  written["false_free"].get<std::int64_t>());
    EXPECT_EQ(coarseShaft["triangles"], written["triangles_after"]);
    // `coarse` itself measures from the full meshes, whatever the project keeps.
    EXPECT_EQ(runJson("coarse " + (folder / "c.json").string() + " --triangles 1500 --repeat 1 --json")["false_free"],
              written["false_free"]);

    // Refusals, one line each, nothing written.
    for (const std::string& bad : {std::string(" --chart x.png"), std::string(" --sweep 100,abc"), std::string(" --sweep 3"),
                                   std::string(" --sweep -5"), std::string(" --sweep auto --kind inner"),
                                   std::string(" --sweep auto --write y.json"), std::string(" --write ") + project,
                                   std::string(" --sweep 1000 --chart ") + (folder / "torus.glb").string()}) {
        const CliRun run = runCli("coarse " + project + bad);
        EXPECT_NE(run.code, 0) << bad;
        EXPECT_TRUE(oneLine(run.err)) << bad << ": " << run.err;
    }
    EXPECT_EQ(readAll(folder / "p.json"), before);
    EXPECT_FALSE(fs::exists(folder / "x.png"));
    EXPECT_FALSE(fs::exists(folder / "y.json"));
}

// --tolerance: the fewest triangles (to the bisection's 5%) whose level answers at most that share
// of the rays differently, kept as a single run at that count would measure it; a count 10% below
// it, measured the same way, exceeds the tolerance or was itself tried and refused.
TEST_F(CoarseCli, ToleranceFindsTheFewestTrianglesWithinIt)
{
    const std::string project = (folder / "p.json").string();
    const double tolerance = 0.002;
    const json fit = runJson("coarse " + project + " --tolerance 0.002 --repeat 1 --json");
    const std::int64_t rays = fit["rays"].get<std::int64_t>();
    const std::int64_t differ = fit["false_blocked"].get<std::int64_t>() + fit["false_free"].get<std::int64_t>();
    EXPECT_LE(double(differ), tolerance * double(rays));
    const int chosen = fit["triangles"].get<int>();
    EXPECT_LT(chosen, 192 * 48 * 2);
    ASSERT_FALSE(fit["tried"].empty());
    bool tried = false;
    for (const json& point : fit["tried"])
        tried = tried || (point["asked"] == chosen &&
                          point["false_blocked"].get<std::int64_t>() + point["false_free"].get<std::int64_t>() == differ);
    EXPECT_TRUE(tried) << fit.dump();
    const json single = runJson("coarse " + project + " --triangles " + std::to_string(chosen) + " --repeat 1 --json");
    EXPECT_EQ(single["false_blocked"], fit["false_blocked"]);
    EXPECT_EQ(single["false_free"], fit["false_free"]);
    // Fewer triangles than the bisection's resolution below it were over the tolerance when tried.
    for (const json& point : fit["tried"]) {
        if (point["asked"].get<int>() < chosen) {
            EXPECT_GT(double(point["false_blocked"].get<std::int64_t>() + point["false_free"].get<std::int64_t>()),
                      tolerance * double(rays));
        }
    }

    for (const std::string& bad : {std::string(" --tolerance 2"), std::string(" --tolerance 0.01 --sweep auto"),
                                   std::string(" --tolerance 0.01 --kind inner"), std::string(" --tolerance 0.01 --triangles 500"),
                                   std::string(" --tolerance 0")}) {
        const CliRun run = runCli("coarse " + project + bad);
        EXPECT_NE(run.code, 0) << bad;
        EXPECT_TRUE(oneLine(run.err)) << bad << ": " << run.err;
    }
}
