// sightline-cli as a user runs it: exit codes, one-line errors, JSON and mask outputs.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "BruteForceCaster.h"
#include "CliRunner.h"
#include "TestScenes.h"
#include "demo/BenchScenes.h"
#include "demo/DemoLevel.h"
#include "plugins/SceneFormats.h"
#include "project/Project.h"
#include "visibility/MaskNpy.h"
#include "visibility/RayCastSampler.h"
#include "visibility/ReceiverHeights.h"

using namespace sightline;
using namespace sightline::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {


class Cli : public CliFolderTest {
protected:
    void SetUp() override
    {
        CliFolderTest::SetUp();
        // A 2 x 2 m wall (OBJ) with a 1 m hole in the middle between the patches, plus a box
        // occluder placed in the hole's lower half by the project.
        test::writeWallWithHoleObj(folder / "wall.obj");
        json project = crateInWallProject();
        std::ofstream(folder / "p.json") << project.dump(2);
    }
};

} // namespace

TEST_F(Cli, HelpAndVersion)
{
    const CliRun help = runCli("--help");
    EXPECT_EQ(help.code, 0);
    EXPECT_NE(help.out.find("shaft"), std::string::npos);
    EXPECT_NE(help.out.find("info"), std::string::npos);
    const CliRun shaftHelp = runCli("shaft --help");
    EXPECT_EQ(shaftHelp.code, 0);
    EXPECT_NE(shaftHelp.out.find("--mask"), std::string::npos);
    EXPECT_EQ(runCli("--version").code, 0);
}

TEST_F(Cli, ShaftJsonAndMaskMatchTheReference)
{
    const fs::path mask = folder / "m.npy";
    const CliRun run = runCli("shaft " + (folder / "p.json").string() + " --method raycast --json --mask " + mask.string());
    ASSERT_EQ(run.code, 0) << run.err;
    const json out = json::parse(run.out);
    for (const char* key : {"method", "rays", "blocked", "unblocked", "visible_fraction", "ms"})
        EXPECT_TRUE(out.contains(key)) << key;
    EXPECT_EQ(out["method"], "raycast");
    EXPECT_EQ(out["rays"], 128u * 480u);
    EXPECT_EQ(out["blocked"].get<std::uint64_t>() + out["unblocked"].get<std::uint64_t>(), 128u * 480u);

    const Project project = loadProject(folder / "p.json");
    const HiddenSampleMap expected = RayCastScene(buildScene(project)).sample(project.source, project.receiver);
    EXPECT_EQ(out["blocked"], expected.blockedCount());
    EXPECT_NEAR(out["visible_fraction"].get<double>(), 1.0 - double(expected.blockedCount()) / 61440.0, 1e-12);
    // The wall with its hole and the crate make a real mix of blocked and free rays.
    EXPECT_GT(expected.blockedCount(), 61440u / 10);
    EXPECT_LT(expected.blockedCount(), 61440u * 19 / 20);
    EXPECT_EQ(readMaskNpy(mask, 128), expected);
}

TEST_F(Cli, CpuMethodAgreesWithRaycast)
{
    const fs::path cpuMask = folder / "cpu.npy", rayMask = folder / "ray.npy";
    const CliRun cpu = runCli("shaft " + (folder / "p.json").string() + " --method cpu --strategy bitmask --json --mask " + cpuMask.string());
    const CliRun ray = runCli("shaft " + (folder / "p.json").string() + " --method raycast --mask " + rayMask.string());
    ASSERT_EQ(cpu.code, 0) << cpu.err;
    ASSERT_EQ(ray.code, 0) << ray.err;
    const json out = json::parse(cpu.out);
    EXPECT_EQ(out["method"], "cpu");
    EXPECT_NE(out["strategy"].get<std::string>().find("bitmask-exact-rows"), std::string::npos);
    EXPECT_TRUE(out.contains("bitmask_ms"));
    const HiddenSampleMap a = readMaskNpy(cpuMask, 128), b = readMaskNpy(rayMask, 128);
    EXPECT_LE(a.differenceCount(b) * 10000, a.rayCount());
}

TEST_F(Cli, GlMethodAgreesWithRaycast)
{
    const fs::path glMask = folder / "gl.npy", rayMask = folder / "ray.npy";
    const CliRun gl = runCli("shaft " + (folder / "p.json").string() + " --method gl --json --mask " + glMask.string());
    if (gl.code != 0 && gl.err.find("OSMesa") != std::string::npos)
        GTEST_SKIP() << "no OpenGL context: " << gl.err;
    ASSERT_EQ(gl.code, 0) << gl.err;
    ASSERT_EQ(runCli("shaft " + (folder / "p.json").string() + " --mask " + rayMask.string()).code, 0);
    const json out = json::parse(gl.out);
    EXPECT_EQ(out["method"], "gl");
    EXPECT_TRUE(out.contains("draw_ms"));
    const HiddenSampleMap a = readMaskNpy(glMask, 128), b = readMaskNpy(rayMask, 128);
    EXPECT_LE(a.differenceCount(b) * 10000, a.rayCount());
}

TEST_F(Cli, GlTableModeAgreesWithCpuTableMode)
{
    // The paper's Hough table (§5) on both samplers: the same table and lookups, so the masks
    // agree up to edges within float rounding of a texel boundary. tst_visibility_gl measures
    // that at about 1e-6 of rays and holds each case to 1e-4 (0.01%); the same bound here.
    const std::string project = (folder / "p.json").string();
    const fs::path glMask = folder / "gt.npy", cpuMask = folder / "ct.npy", exactMask = folder / "ge.npy";
    const CliRun gl = runCli("shaft " + project + " --method gl --mode table --table 64 32 --json --mask " + glMask.string());
    if (gl.code != 0 && gl.err.find("OSMesa") != std::string::npos)
        GTEST_SKIP() << "no OpenGL context: " << gl.err;
    ASSERT_EQ(gl.code, 0) << gl.err;
    const CliRun cpu = runCli("shaft " + project + " --method cpu --mode table --table 64 32 --json --mask " + cpuMask.string());
    ASSERT_EQ(cpu.code, 0) << cpu.err;
    ASSERT_EQ(runCli("shaft " + project + " --method gl --json --mask " + exactMask.string()).code, 0);
    const json a = json::parse(gl.out), b = json::parse(cpu.out);
    EXPECT_EQ(a["method"], "gl");
    EXPECT_NE(a["strategy"].get<std::string>().find("gl-bitmask-hough-table-64x32"), std::string::npos) << a["strategy"];
    EXPECT_NE(b["strategy"].get<std::string>().find("bitmask-hough-table-64x32"), std::string::npos) << b["strategy"];
    EXPECT_GT(a["table_ms"].get<double>(), 0.0);
    EXPECT_EQ(a["rays"], b["rays"]);
    const double rays = a["rays"].get<double>();
    EXPECT_LE(std::abs(a["blocked"].get<double>() - b["blocked"].get<double>()), 1e-4 * rays);
    const HiddenSampleMap onGl = readMaskNpy(glMask, 128), onCpu = readMaskNpy(cpuMask, 128), exact = readMaskNpy(exactMask, 128);
    EXPECT_EQ(onGl.blockedCount(), a["blocked"].get<std::uint64_t>());
    EXPECT_LE(double(onGl.differenceCount(onCpu)), 1e-4 * rays);
    EXPECT_GT(onGl.differenceCount(exact), 0u);   // a 64x32 table is visibly approximate

    const CliRun bad = runCli("shaft " + project + " --method gl --mode table --table 2 1");
    EXPECT_NE(bad.code, 0);
    EXPECT_TRUE(oneLine(bad.err)) << bad.err;
}

TEST_F(Cli, BenchRunsGlTableModeOnTheChosenBackend)
{
    const std::string project = (folder / "p.json").string();
    const CliRun run = runCli("bench " + project + " --sources 128 --receivers 12 --repeat 1 --min-time 0 --gl-backend osmesa "
                              "--methods cpu-table-64x32,gl-table-64x32 --csv " + (folder / "t.csv").string());
    if (run.code != 0 && run.err.find("OSMesa") != std::string::npos)
        GTEST_SKIP() << "no OpenGL context: " << run.err;
    ASSERT_EQ(run.code, 0) << run.err;
    std::ifstream csv(folder / "t.csv");
    std::string header;
    std::getline(csv, header);
    // Fields after the quoted project: method, source_samples, receiver, rays, ms, blocked,
    // wrongly_blocked, wrongly_free, error_fraction, light_mae, dense_light_mae (empty without
    // --shadow), thread_ms, ties (empty where the differences were too many to judge), variant
    // (embree-tuned's traversal, the CPU sampler's strategy; empty for the other methods), runs.
    std::vector<std::vector<std::string>> rows;
    for (std::string line; std::getline(csv, line);) {
        std::vector<std::string> fields;
        std::stringstream in(line.substr(line.rfind('"') + 2));
        for (std::string field; std::getline(in, field, ',');)
            fields.push_back(field);
        if (!line.empty() && line.back() == ',')
            fields.emplace_back();
        ASSERT_EQ(fields.size(), 15u) << line;
        EXPECT_EQ(fields[10], "") << line;
        EXPECT_GT(std::stod(fields[11]), 0.0) << line;
        // A coarse table's few hundred differences are judged: every one is a real error here.
        EXPECT_EQ(fields[12], "0") << line;
        rows.push_back(fields);
    }
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0][0], "cpu-table-64x32");
    EXPECT_EQ(rows[1][0], "gl-table-64x32");
    EXPECT_EQ(rows[0][13], "bitmask");   // the table mode backprojects every triangle
    EXPECT_EQ(rows[1][13], "");
    EXPECT_EQ(rows[0][14], "1");   // --repeat 1 --min-time 0: one timed run
    const double rays = std::stod(rows[0][3]);
    EXPECT_GT(std::stod(rows[0][8]), 0.0);   // the table's error against the reference
    EXPECT_LE(std::abs(std::stod(rows[0][5]) - std::stod(rows[1][5])), 1e-4 * rays);
    EXPECT_LE(std::abs(std::stod(rows[0][8]) - std::stod(rows[1][8])), 1e-4);

    for (const std::string& arguments : {"bench " + project + " --methods gl --gl-backend vulkan",
                                         "bench " + project + " --methods gl-table-3x1"}) {
        const CliRun bad = runCli(arguments);
        EXPECT_NE(bad.code, 0) << arguments;
        EXPECT_TRUE(oneLine(bad.err)) << arguments << " -> [" << bad.err << "]";
    }
}

TEST_F(Cli, JitterGivesTheSameMaskInCpuAndRaycast)
{
    const std::string project = (folder / "p.json").string();
    const fs::path cpuMask = folder / "jc.npy", rayMask = folder / "jr.npy", plainMask = folder / "jp.npy";
    const CliRun cpu = runCli("shaft " + project + " --method cpu --jitter 77 --json --mask " + cpuMask.string());
    ASSERT_EQ(cpu.code, 0) << cpu.err;
    EXPECT_EQ(json::parse(cpu.out)["jitter_seed"], 77);
    ASSERT_EQ(runCli("shaft " + project + " --method raycast --jitter 77 --mask " + rayMask.string()).code, 0);
    ASSERT_EQ(runCli("shaft " + project + " --method raycast --mask " + plainMask.string()).code, 0);
    const HiddenSampleMap a = readMaskNpy(cpuMask, 128), b = readMaskNpy(rayMask, 128), plain = readMaskNpy(plainMask, 128);
    EXPECT_LE(a.differenceCount(b) * 10000, a.rayCount());
    EXPECT_GT(b.differenceCount(plain), 0u);
    const CliRun hh = runCli("shaft " + project + " --method hh --jitter 3");
    EXPECT_NE(hh.code, 0);
    EXPECT_TRUE(oneLine(hh.err)) << hh.err;
}

TEST_F(Cli, ShaftHonoursReceiverHeightsInRaycastAndCpu)
{
    // The receiver's right half raised 0.3 m toward the source (heights as float32 (nb, na)).
    std::vector<float> metres(24 * 20);
    for (std::size_t j = 0; j < metres.size(); ++j)
        metres[j] = j % 24 >= 12 ? 0.3f : 0.0f;
    writeFloatNpy(metres, 20, 24, folder / "h.npy");
    json document = json::parse(std::ifstream(folder / "p.json"));
    document["receiver_heights"] = {{"npy", "h.npy"}};
    std::ofstream(folder / "bumpy.json") << document.dump();
    const std::string flat = (folder / "p.json").string(), bumpy = (folder / "bumpy.json").string();

    const fs::path flatMask = folder / "flat.npy", rayMask = folder / "ray.npy", cpuMask = folder / "cpu.npy",
                   cpuRayMask = folder / "cpu-ray.npy";
    ASSERT_EQ(runCli("shaft " + flat + " --method raycast --mask " + flatMask.string()).code, 0);
    const CliRun ray = runCli("shaft " + bumpy + " --method raycast --json --mask " + rayMask.string());
    ASSERT_EQ(ray.code, 0) << ray.err;
    EXPECT_EQ(json::parse(ray.out)["height_field"], true);
    const CliRun cpu = runCli("shaft " + bumpy + " --method cpu --json --mask " + cpuMask.string());
    ASSERT_EQ(cpu.code, 0) << cpu.err;
    EXPECT_EQ(json::parse(cpu.out)["height_field"], true);
    // The cpu sampler's own ray casting must take the heights too.
    ASSERT_EQ(runCli("shaft " + bumpy + " --method cpu --strategy raycast --mask " + cpuRayMask.string()).code, 0);

    // The reference in process, with the same heights: the CLI's raycast answer exactly.
    const Project project = loadProject(folder / "bumpy.json");
    ReceiverHeights heights;
    heights.metres.assign(metres.begin(), metres.end());
    const HiddenSampleMap expected =
        RayCastScene(buildScene(project)).sample(project.source, project.receiver, {.heights = &heights});
    const HiddenSampleMap onFlat = readMaskNpy(flatMask, 128), onRay = readMaskNpy(rayMask, 128),
                          onCpu = readMaskNpy(cpuMask, 128), onCpuRay = readMaskNpy(cpuRayMask, 128);
    EXPECT_EQ(onRay, expected);
    // The bumps change the answer on many rays (the raised half sees past the wall differently) ...
    EXPECT_GT(onRay.differenceCount(onFlat), onRay.rayCount() / 50);
    // ... and cpu gives the reference's answer (grazing rays aside, as for the flat receiver).
    EXPECT_LE(onCpu.differenceCount(onRay) * 10000, onRay.rayCount());
    EXPECT_LE(onCpuRay.differenceCount(onRay) * 10000, onRay.rayCount());

    // The GL sampler and Heckbert-Herf take a flat receiver only: refused before any GL context
    // is made, so these need no OpenGL.
    for (const char* method : {"gl", "hh"}) {
        const CliRun refused = runCli("shaft " + bumpy + " --method " + method);
        EXPECT_NE(refused.code, 0) << method;
        EXPECT_TRUE(oneLine(refused.err)) << method << " -> [" << refused.err << "]";
        EXPECT_NE(refused.err.find("receiver_heights"), std::string::npos) << refused.err;
        EXPECT_TRUE(refused.out.empty()) << method;
    }
}

TEST_F(Cli, HeckbertHerfCountsAgreeWithRaycastAndRefuseMasks)
{
    const std::string project = (folder / "p.json").string();
    const CliRun hh = runCli("shaft " + project + " --method hh --json");
    if (hh.code != 0 && hh.err.find("OSMesa") != std::string::npos)
        GTEST_SKIP() << "no OpenGL context: " << hh.err;
    ASSERT_EQ(hh.code, 0) << hh.err;
    const CliRun ray = runCli("shaft " + project + " --json");
    ASSERT_EQ(ray.code, 0) << ray.err;
    const json a = json::parse(hh.out), b = json::parse(ray.out);
    EXPECT_EQ(a["method"], "hh");
    EXPECT_EQ(a["rays"], b["rays"]);
    EXPECT_EQ(a["renders"], 128);   // one per source sample
    const double blocked = a["blocked"].get<double>(), expected = b["blocked"].get<double>();
    EXPECT_GT(expected, 0.0);
    EXPECT_LE(std::abs(blocked - expected), 1e-3 * b["rays"].get<double>());

    const CliRun mask = runCli("shaft " + project + " --method hh --mask " + (folder / "hh.npy").string());
    EXPECT_NE(mask.code, 0);
    EXPECT_TRUE(oneLine(mask.err)) << mask.err;
    EXPECT_NE(mask.err.find("counts"), std::string::npos) << mask.err;
    EXPECT_FALSE(fs::exists(folder / "hh.npy"));
}

TEST_F(Cli, BenchWritesCsvAndChart)
{
    const CliRun run = runCli("bench " + (folder / "p.json").string() +
                              " --sources 32 --receivers 8,12 --repeat 1 --methods raycast,cpu,cpu-table-32x16 --csv " +
                              (folder / "b.csv").string() + " --chart " + (folder / "b.png").string());
    ASSERT_EQ(run.code, 0) << run.err;
    std::ifstream csv(folder / "b.csv");
    int lines = 0;
    for (std::string line; std::getline(csv, line);)
        ++lines;
    EXPECT_EQ(lines, 1 + 3 * 2);
    EXPECT_GT(fs::file_size(folder / "b.png"), 1000u);
    EXPECT_NE(run.out.find("cpu-table-32x16"), std::string::npos);

    const CliRun bad = runCli("bench " + (folder / "p.json").string() + " --methods warp");
    EXPECT_NE(bad.code, 0);
    EXPECT_TRUE(oneLine(bad.err)) << bad.err;
}

TEST_F(Cli, TextOutputByDefault)
{
    const CliRun run = runCli("shaft " + (folder / "p.json").string());
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_NE(run.out.find("visible"), std::string::npos);
}

TEST_F(Cli, FailuresAreOneLineAndNonZero)
{
    const std::string project = (folder / "p.json").string();
    for (const std::string& arguments : std::vector<std::string>{
             "shaft " + project + " --gl-backend vulkan",
          "shaft " + project + " --method warp", "shaft " + (folder / "missing.json").string(),
          "info " + (folder / "missing.obj").string(), std::string("shaft"), std::string("frobnicate"),
          "shaft " + project + " --mask " + (folder / "no" / "dir" / "m.npy").string()}) {
        const CliRun run = runCli(arguments);
        EXPECT_NE(run.code, 0) << arguments;
        EXPECT_TRUE(oneLine(run.err)) << arguments << " -> [" << run.err << "]";
        EXPECT_TRUE(run.out.empty()) << arguments;
    }

    // A misspelt subcommand is named, with the ones there are (it read "A subcommand is required").
    const CliRun misspelt = runCli("shaf " + project);
    EXPECT_EQ(misspelt.code, 2);
    EXPECT_NE(misspelt.err.find("unknown subcommand 'shaf'"), std::string::npos) << misspelt.err;
    EXPECT_NE(misspelt.err.find("shaft, info"), std::string::npos) << misspelt.err;

    // An invalid patch pair is refused, never computed.
    json bad = json::parse(std::ifstream(folder / "p.json"));
    bad["receiver"]["corner"] = {-0.5, -0.2, -1};
    bad["receiver"]["v"] = {0, 0, 3};
    std::ofstream(folder / "bad.json") << bad.dump();
    const CliRun run = runCli("shaft " + (folder / "bad.json").string() + " --json");
    EXPECT_NE(run.code, 0);
    EXPECT_TRUE(oneLine(run.err)) << run.err;
    EXPECT_NE(run.err.find("patch pair"), std::string::npos) << run.err;
}

TEST_F(Cli, OptionsTheMethodWouldIgnoreAreRefused)
{
    const std::string project = (folder / "p.json").string();
    const std::string png = " --out " + (folder / "x.png").string();
    struct Case {
        std::string arguments, option;   // the option the one-line error must name
    };
    const std::vector<Case> refused = {
        {"shaft " + project + " --strategy bitmask", "--strategy"},   // the default method is raycast
        {"shaft " + project + " --method raycast --mode table", "--mode"},
        {"shaft " + project + " --method raycast --scalar", "--scalar"},
        {"shaft " + project + " --method gl --strategy hybrid", "--strategy"},
        {"shaft " + project + " --method hh --mode table", "--mode"},
        {"shaft " + project + " --method cpu --single-rays", "--single-rays"},
        {"shaft " + project + " --method gl --single-rays", "--single-rays"},
        {"shaft " + project + " --method hh --single-rays", "--single-rays"},
        {"shaft " + project + " --method gl --threads 1", "--threads"},
        {"shaft " + project + " --method hh --threads 2", "--threads"},
        {"shaft " + project + " --method cpu --table 64 32", "--table"},
        {"shaft " + project + " --method gl --mode exact --table 64 32", "--table"},
        {"shaft " + project + " --method cpu --mode table --strategy bitmask", "--strategy"},
        {"shaft " + project + " --method cpu --mode table --scalar", "--scalar"},
        {"shaft " + project + " --method cpu --gl-backend osmesa", "--gl-backend"},
        {"shaft " + project + " --gl-backend egl", "--gl-backend"},
        {"shaft " + project + " --method hh --jitter 3", "--jitter"},
        {"shaft " + project + " --repeat 0", "--repeat"},
        {"importance " + project + png + " --gl-backend osmesa", "--gl-backend"},
        {"importance " + project + png + " --method raycast --gl-backend egl", "--gl-backend"},
        {"importance " + project + png + " --method gl --threads 1", "--threads"},
        {"shadow " + project + png + " --method cpu --gl-backend osmesa", "--gl-backend"},
        {"shadow " + project + png + " --method gl --threads 1", "--threads"},
        {"shadow " + project + png + " --method hh --threads 1", "--threads"},
        {"bench " + project + " --methods raycast,cpu --gl-backend osmesa --repeat 1", "--gl-backend"},
    };
    for (const Case& c : refused) {
        const CliRun run = runCli(c.arguments);
        EXPECT_NE(run.code, 0) << c.arguments;
        EXPECT_TRUE(oneLine(run.err)) << c.arguments << " -> [" << run.err << "]";
        EXPECT_NE(run.err.find(c.option), std::string::npos) << c.arguments << " -> [" << run.err << "]";
        EXPECT_TRUE(run.out.empty()) << c.arguments;
        EXPECT_FALSE(fs::exists(folder / "x.png")) << c.arguments;
    }
    // The same options where they apply still run.
    for (const std::string& arguments : {"shaft " + project + " --method cpu --strategy bitmask --scalar --threads 1",
                                         "shaft " + project + " --method cpu --mode table --table 64 32",
                                         "shaft " + project + " --method raycast --single-rays --threads 1",
                                         "shaft " + project + " --method raycast --jitter 0"}) {
        const CliRun run = runCli(arguments);
        EXPECT_EQ(run.code, 0) << arguments << " -> " << run.err;
    }
}

TEST_F(Cli, ForcedRaycastStrategySaysSo)
{
    const CliRun run = runCli("shaft " + (folder / "p.json").string() + " --method cpu --strategy raycast --json");
    ASSERT_EQ(run.code, 0) << run.err;
    const std::string strategy = json::parse(run.out)["strategy"];
    EXPECT_EQ(strategy, "raycast: embree float rays, hits proven, free rays confirmed (forced by --strategy)");
}

TEST_F(Cli, RepeatWarmsUpOnceThenTimesNRuns)
{
    const std::string project = (folder / "p.json").string();
    const json cold = json::parse(runCli("shaft " + project + " --json").out);
    EXPECT_EQ(cold["repeat"], 1);
    EXPECT_EQ(cold["warm_up"], false);
    const json once = json::parse(runCli("shaft " + project + " --json --repeat 1").out);
    EXPECT_EQ(once["repeat"], 1);
    EXPECT_EQ(once["warm_up"], true);
    const json five = json::parse(runCli("shaft " + project + " --json --repeat 5").out);
    EXPECT_EQ(five["repeat"], 5);
    EXPECT_EQ(five["warm_up"], true);
    EXPECT_EQ(five["blocked"], cold["blocked"]);
}

TEST_F(Cli, InfoCountsInstances)
{
    const CliRun run = runCli("info " + (folder / "p.json").string() + " --json");
    ASSERT_EQ(run.code, 0) << run.err;
    const json out = json::parse(run.out);
    EXPECT_EQ(out["triangles"], 8u + 12u);
    EXPECT_EQ(out["instances"], 2u);
    EXPECT_FLOAT_EQ(out["bounds"]["max"][1].get<float>(), 1.5f);
}

TEST_F(Cli, DemoWritesARunnableProject)
{
    const CliRun demo = runCli("demo " + (folder / "demo").string());
    ASSERT_EQ(demo.code, 0) << demo.err;
    ASSERT_TRUE(fs::exists(folder / "demo" / "demo.json"));
    ASSERT_TRUE(fs::exists(folder / "demo" / "demo_level.glb"));
    // The level's watertight flags survive the file: the importer re-checks each (closedAndOutward).
    std::vector<std::string> warnings;
    const Scene loaded = loadScene(folder / "demo" / "demo_level.glb", &warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    std::map<std::string, bool> flags;   // mesh name -> flag as generated
    for (const Mesh& mesh : demo::makeDemoLevel().meshes)
        flags[mesh.name] = mesh.watertight;
    ASSERT_EQ(loaded.meshes.size(), flags.size());
    int flagged = 0;
    for (const Mesh& mesh : loaded.meshes) {
        ASSERT_TRUE(flags.contains(mesh.name)) << mesh.name;
        EXPECT_EQ(mesh.watertight, flags[mesh.name]) << mesh.name;
        flagged += mesh.watertight;
    }
    EXPECT_GE(flagged, 10);
    for (const char* bench : {"few-occluders", "dense-mesh"}) {
        ASSERT_TRUE(fs::exists(folder / "demo" / (std::string(bench) + ".json"))) << bench;
        const CliRun run = runCli("shaft " + (folder / "demo" / (std::string(bench) + ".json")).string() + " --json");
        ASSERT_EQ(run.code, 0) << run.err;
    }
    // Seeds 1-3 of every generated kind under bench/. Seed 1 of each must come back from its files
    // as generated: flags kept, the same patches, the same rays blocked.
    for (const demo::BenchKind kind : demo::kBenchKinds)
        for (int seed = 1; seed <= 3; ++seed) {
            const std::string stem = std::string(demo::benchKindName(kind)) + "-" + std::to_string(seed);
            const fs::path project = folder / "demo" / "bench" / (stem + ".json");
            ASSERT_TRUE(fs::exists(project)) << stem;
            ASSERT_TRUE(fs::exists(folder / "demo" / "bench" / (stem + ".glb"))) << stem;
            if (seed != 1)
                continue;
            const demo::BenchScene bench = demo::makeBenchScene(kind, 1);
            std::vector<std::string> benchWarnings;
            const Scene benchLoaded = loadScene(folder / "demo" / "bench" / (stem + ".glb"), &benchWarnings);
            EXPECT_TRUE(benchWarnings.empty()) << stem << ": " << benchWarnings.front();
            EXPECT_EQ(benchLoaded.triangleCount(), bench.scene.triangleCount()) << stem;
            const Project loadedProject = loadProject(project);
            EXPECT_EQ(loadedProject.source.corner, bench.source.corner) << stem;
            EXPECT_EQ(loadedProject.receiver.u, bench.receiver.u) << stem;
            const CliRun run = runCli("shaft " + project.string() + " --json");
            ASSERT_EQ(run.code, 0) << run.err;
            const HiddenSampleMap expected = RayCastScene(bench.scene).sample(bench.source, bench.receiver);
            EXPECT_EQ(json::parse(run.out)["blocked"].get<std::uint64_t>(), expected.blockedCount()) << stem;
        }
    const CliRun shaft = runCli("shaft " + (folder / "demo" / "demo.json").string() + " --json");
    ASSERT_EQ(shaft.code, 0) << shaft.err;
    const json out = json::parse(shaft.out);
    EXPECT_EQ(out["rays"], 1024u * 1024u);
    EXPECT_GE(out["triangles"].get<std::size_t>(), 70000u);
    // The demo view is neither open nor shut.
    EXPECT_GT(out["visible_fraction"].get<double>(), 0.1);
    EXPECT_LT(out["visible_fraction"].get<double>(), 0.9);
}

TEST_F(Cli, MaskAgreesWithAnIndependentCasterOnMixedProjects)
{
    // A glTF scene (written by our exporter) of random triangles, an OBJ occluder, the built-in
    // box and a rotated built-in plane; tilted, non-parallel patches with odd grids. The mask the
    // CLI writes must equal a double-precision brute-force caster outside grazing rays.
    const Mesh soup = test::randomSoup(2024, 120, -0.5f, 2.0f, 0.8f, 3.2f, 0.25f);
    Scene level;
    const std::uint32_t mesh = level.addMesh(soup);
    level.instances.push_back({"soup a", mesh, glm::mat4(1.0f)});
    glm::mat4 shifted(1.0f);
    shifted[3] = glm::vec4(0.4f, -0.3f, 0.2f, 1.0f);
    level.instances.push_back({"soup b", mesh, shifted});
    saveScene(level, folder / "level.glb");

    json project = {
        {"version", 1},
        {"scene", "level.glb"},
        {"source", {{"corner", {0.1, 0.0, 0.0}}, {"u", {1.2, 0.1, -0.2}}, {"v", {0.0, 1.1, 0.15}}, {"samples", {13, 7}}}},
        {"receiver", {{"corner", {-0.4, -0.2, 4.0}}, {"u", {2.2, 0.0, 0.6}}, {"v", {0.2, 1.8, -0.3}}, {"samples", {23, 19}}}},
        {"occluders", {{{"name", "wall"}, {"mesh", "wall.obj"}},
                       {{"name", "crate"}, {"mesh", "box"},
                        {"transform", {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0.6, 0.5, 2.6, 1}}},
                       {{"name", "board"}, {"mesh", "plane"},   // rotated 90 degrees about X: stands in XY
                        {"transform", {0.8, 0, 0, 0, 0, 0, 1, 0, 0, -0.6, 0, 0, 1.2, 1.0, 3.0, 1}}}}},
    };
    std::ofstream(folder / "mixed.json") << project.dump();
    const fs::path mask = folder / "mixed.npy";
    const CliRun run = runCli("shaft " + (folder / "mixed.json").string() + " --json --mask " + mask.string());
    ASSERT_EQ(run.code, 0) << run.err;

    const Project loaded = loadProject(folder / "mixed.json");
    const Scene scene = buildScene(loaded);
    EXPECT_EQ(scene.triangleCount(), 240u + 8u + 12u + 2u);
    const test::BruteForceMap reference = test::bruteForceSample(worldTriangles(scene), loaded.source, loaded.receiver);
    const HiddenSampleMap written = readMaskNpy(mask, 13 * 7);
    EXPECT_EQ(test::mismatchesOutsideGrazing(written, reference), 0u);
    EXPECT_LT(reference.grazing.blockedCount(), written.rayCount() / 1000);
    EXPECT_GT(written.blockedCount(), written.rayCount() / 10);
    EXPECT_LT(written.blockedCount(), written.rayCount() * 9 / 10);
}

TEST_F(Cli, DemoMaskAgreesWithAnIndependentCasterOnSampledRays)
{
    // 1M rays x 83k triangles is too many for brute force; 3000 random rays are not.
    ASSERT_EQ(runCli("demo " + (folder / "demo").string()).code, 0);
    const fs::path mask = folder / "demo.npy";
    const CliRun run = runCli("shaft " + (folder / "demo" / "demo.json").string() + " --mask " + mask.string());
    ASSERT_EQ(run.code, 0) << run.err;
    const Project project = loadProject(folder / "demo" / "demo.json");
    const WorldTriangles triangles = worldTriangles(buildScene(project));
    const HiddenSampleMap written = readMaskNpy(mask, project.source.sampleCount());
    std::mt19937 rng(99);
    int checked = 0, blocked = 0, mismatches = 0;
    for (int k = 0; k < 3000; ++k) {
        const int j = int(rng() % unsigned(project.receiver.sampleCount()));
        const int i = int(rng() % unsigned(project.source.sampleCount()));
        const test::SegmentResult r = test::bruteForceSegment(triangles, project.receiver.sample(j), project.source.sample(i));
        if (r.margin < 1e-5)
            continue;
        ++checked;
        blocked += r.blocked;
        mismatches += r.blocked != written.blocked(j, i);
    }
    EXPECT_GT(checked, 2900);
    EXPECT_EQ(mismatches, 0) << "of " << checked << " rays";
    EXPECT_GT(blocked, checked / 10);
}

// docs/design.md §3's import settings: the same wall written Z-up in half-metre units is, with
// "scene_up": "+z" and "scene_scale": 0.5, the same world, so shaft gives the same mask (a scale
// of a power of two keeps every coordinate exact, so not even a tie can differ).
TEST_F(Cli, AZUpLevelInOtherUnitsGivesTheSameMaskAsItsYUpMetreCopy)
{
    std::ifstream in(folder / "wall.obj");
    std::ofstream out(folder / "wall_zup.obj");
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string tag;
        double x = 0, y = 0, z = 0;
        if (words >> tag && tag == "v" && words >> x >> y >> z)   // world (x, y, z) = 0.5 (fx, fz, -fy)
            out << "v " << x / 0.5 << ' ' << -z / 0.5 << ' ' << y / 0.5 << '\n';
        else
            out << line << '\n';
    }
    out.close();
    json project = json::parse(std::ifstream(folder / "p.json"));
    project["scene"] = "wall_zup.obj";
    project["scene_up"] = "+z";
    project["scene_scale"] = 0.5;
    std::ofstream(folder / "p_zup.json") << project.dump(2);
    const fs::path yUp = folder / "y.npy", zUp = folder / "z.npy";
    const CliRun a = runCli("shaft " + (folder / "p.json").string() + " --method raycast --json --mask " + yUp.string());
    const CliRun b = runCli("shaft " + (folder / "p_zup.json").string() + " --method raycast --json --mask " + zUp.string());
    ASSERT_EQ(a.code, 0) << a.err;
    ASSERT_EQ(b.code, 0) << b.err;
    EXPECT_EQ(json::parse(a.out)["blocked"], json::parse(b.out)["blocked"]);
    EXPECT_EQ(readMaskNpy(yUp, 128), readMaskNpy(zUp, 128));
    EXPECT_GT(json::parse(b.out)["blocked"].get<std::uint64_t>(), 0u);

    // A bad setting is one line naming the key.
    project["scene_up"] = "up";
    std::ofstream(folder / "p_bad.json") << project.dump(2);
    const CliRun bad = runCli("shaft " + (folder / "p_bad.json").string());
    EXPECT_NE(bad.code, 0);
    EXPECT_NE(bad.err.find("'scene_up' must be one of +y, -y, +z, -z, +x, -x, not 'up'"), std::string::npos) << bad.err;
}
