// sightline-cli pvs (docs/design.md §4): one-process, threaded, sharded, resumed and MPI
// bakes give byte-identical files; merge and bake refuse what does not fit, in one line.

#include <cstdlib>
#include <filesystem>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <functional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRunner.h"
#include "visibility/pvs/Sha256.h"

namespace sightline::test {
namespace {

std::string slurp(const fs::path& file)
{
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string sha(const fs::path& file) { return pvs::sha256Hex(slurp(file)); }

class PvsCli : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir = uniqueFolder();
        fs::remove_all(dir);
        fs::create_directories(dir);
        const CliRun made = runCli("pvs level " + (dir / "level").string() + " --rooms 2 --objects 24");
        ASSERT_EQ(made.code, 0) << made.err;
        project = (dir / "level" / "pvs_level.json").string();
    }
    void TearDown() override { fs::remove_all(dir); }

    /// Bakes with `extra` options into `name`; asserts success.
    fs::path bake(const std::string& name, const std::string& extra = "", const std::string& of = "")
    {
        const fs::path out = dir / name;
        const CliRun run = runCli("pvs bake " + (of.empty() ? project : of) + " --out " + out.string() + " " + extra, 300);
        EXPECT_EQ(run.code, 0) << run.err;
        return out;
    }
    /// The project with its "pvs" key changed by `edit`, saved as `name`.
    std::string editedProject(const std::string& name, const std::function<void(nlohmann::json&)>& edit)
    {
        nlohmann::json p = nlohmann::json::parse(slurp(project));
        edit(p["pvs"]);
        const fs::path file = dir / "level" / name;
        std::ofstream(file) << p.dump();
        return file.string();
    }

    fs::path dir;
    std::string project;
};

TEST_F(PvsCli, ShardedAndThreadedBakesAreByteIdenticalToOneProcess)
{
    // With the cell-to-cell rows too (the Quake formats' clusters).
    const fs::path whole = bake("whole.pvs", "--cell-rows --json " + (dir / "whole.pvs.json").string());
    const std::string reference = sha(whole);
    EXPECT_EQ(sha(bake("t1.pvs", "--cell-rows --threads 1")), reference);
    EXPECT_EQ(sha(bake("t2.pvs", "--cell-rows --threads 2")), reference);
    for (int n : {1, 2, 3, 7}) {
        std::string parts;
        for (int i = 0; i < n; ++i) {
            // Built by appending (GCC 12 warns falsely, -Wrestrict, on "literal" + std::string here).
            std::string name = "part", shard = "--shard ";
            name.append(std::to_string(i)).append("of").append(std::to_string(n));
            shard.append(std::to_string(i)).append("/").append(std::to_string(n)).append(" --cell-rows --threads ");
            shard.append(std::to_string(1 + i % 2));
            parts.append(" ").append(bake(name, shard).string());
        }
        const fs::path merged = dir / ("merged" + std::to_string(n) + ".pvs");
        const fs::path mergedJson = dir / ("merged" + std::to_string(n) + ".pvs.json");
        const CliRun run = runCli("pvs merge" + parts + " --out " + merged.string() + " --json " + mergedJson.string());
        ASSERT_EQ(run.code, 0) << run.err;
        EXPECT_EQ(sha(merged), reference) << n << " shards";
        EXPECT_EQ(slurp(mergedJson), slurp(dir / "whole.pvs.json")) << n << " shards";
    }
    // The manifest beside a part names its scene, settings and shard.
    const auto manifest = nlohmann::json::parse(slurp(dir / "part1of3.manifest.json"));
    EXPECT_EQ(manifest["shard"], 1);
    EXPECT_EQ(manifest["shards"], 3);
    EXPECT_EQ(manifest["part_sha256"], sha(dir / "part1of3"));
    EXPECT_EQ(manifest["scene_sha256"], sha(dir / "level" / "pvs_level.glb"));
}

TEST_F(PvsCli, AShardKilledAndRerunGivesTheSameOutput)
{
    const std::string reference = sha(bake("whole.pvs"));
    std::string parts;
    for (int i = 0; i < 3; ++i)
        parts += " " + bake("p" + std::to_string(i), "--shard " + std::to_string(i) + "/3").string();
    // A part cut short (as a killed copy would leave it) is refused by merge...
    const std::string good = slurp(dir / "p1");
    std::ofstream(dir / "p1", std::ios::binary | std::ios::trunc) << good.substr(0, good.size() / 2);
    expectOneLineError(runCli("pvs merge" + parts + " --out " + (dir / "m.pvs").string()), "damaged");
    // ... and --resume bakes it again, while it keeps a complete one.
    const CliRun kept = runCli("pvs bake " + project + " --shard 0/3 --resume --out " + (dir / "p0").string());
    EXPECT_EQ(kept.code, 0) << kept.err;
    EXPECT_NE(kept.out.find("kept"), std::string::npos) << kept.out;
    const CliRun rerun = runCli("pvs bake " + project + " --shard 1/3 --resume --out " + (dir / "p1").string());
    EXPECT_EQ(rerun.code, 0) << rerun.err;
    EXPECT_EQ(rerun.out.find("kept"), std::string::npos) << rerun.out;
    ASSERT_EQ(runCli("pvs merge" + parts + " --out " + (dir / "m.pvs").string()).code, 0);
    EXPECT_EQ(sha(dir / "m.pvs"), reference);
}

TEST_F(PvsCli, ShardsKilledWithSignalNineAtAnyMomentResumeToTheSameOutput)
{
    const std::string reference = sha(bake("whole.pvs", "--cell-rows"));
    std::string parts;
    for (int i = 0; i < 3; ++i)
        parts += " " + (dir / ("p" + std::to_string(i))).string();
    // Killed at several moments (loading, baking, writing): whatever a kill leaves, --resume keeps
    // only a part that is whole and matches its manifest, and the merge equals the one-process bake.
    for (const char* after : {"0.05", "0.2", "0.5", "1"}) {
        for (int i = 0; i < 3; ++i)
            runProgram(std::string("timeout -s KILL ") + after, std::string(SIGHTLINE_CLI) + " pvs bake " + project +
                                                                     " --cell-rows --resume --shard " + std::to_string(i) +
                                                                     "/3 --out " + (dir / ("p" + std::to_string(i))).string());
        for (int i = 0; i < 3; ++i) {
            const CliRun rerun = runCli("pvs bake " + project + " --cell-rows --resume --shard " + std::to_string(i) +
                                        "/3 --out " + (dir / ("p" + std::to_string(i))).string());
            ASSERT_EQ(rerun.code, 0) << rerun.err;
        }
        const CliRun merged = runCli("pvs merge" + parts + " --out " + (dir / "m.pvs").string());
        ASSERT_EQ(merged.code, 0) << merged.err;
        EXPECT_EQ(sha(dir / "m.pvs"), reference) << "killed after " << after << " s";
        for (int i = 0; i < 3; ++i) {   // the next round starts from nothing again
            fs::remove(dir / ("p" + std::to_string(i)));
            fs::remove(dir / ("p" + std::to_string(i) + ".manifest.json"));
        }
    }
}

TEST_F(PvsCli, DamagedPartsAreRefusedByMergeAndBakedAgainByResume)
{
    const std::string reference = sha(bake("whole.pvs"));
    const fs::path p0 = bake("p0", "--shard 0/2"), p1 = bake("p1", "--shard 1/2");
    const std::string good = slurp(p1);
    const std::string merge = "pvs merge " + p0.string() + " " + p1.string() + " --out " + (dir / "m.pvs").string();
    std::mt19937 random(11);
    for (int k = 0; k < 30; ++k) {
        std::string flipped = good;
        const std::size_t at = random() % good.size();
        flipped[at] = char(flipped[at] ^ (1 << (random() % 8)));
        std::ofstream(p1, std::ios::binary | std::ios::trunc) << flipped;
        expectOneLineError(runCli(merge), p1.string());
        EXPECT_FALSE(fs::exists(dir / "m.pvs")) << "merged a part flipped at byte " << at;
    }
    // --resume bakes the damaged part again instead of keeping it.
    const CliRun rerun = runCli("pvs bake " + project + " --shard 1/2 --resume --out " + p1.string());
    ASSERT_EQ(rerun.code, 0) << rerun.err;
    EXPECT_EQ(rerun.out.find("kept"), std::string::npos) << rerun.out;
    EXPECT_EQ(slurp(p1), good);
    // A part that does not match the manifest beside it (another bake's part copied over it).
    const fs::path fine = bake("fine1", "--shard 1/2 --fine 4");
    fs::copy_file(fine, p1, fs::copy_options::overwrite_existing);
    expectOneLineError(runCli(merge), "does not match its manifest");
    const CliRun again = runCli("pvs bake " + project + " --shard 1/2 --resume --out " + p1.string());
    ASSERT_EQ(again.code, 0) << again.err;
    EXPECT_EQ(again.out.find("kept"), std::string::npos) << again.out;
    ASSERT_EQ(runCli(merge).code, 0);
    EXPECT_EQ(sha(dir / "m.pvs"), reference);
}

TEST_F(PvsCli, NoPvsCommandWritesOverWhatItReadsOrWhatItWasNotAskedToWrite)
{
    // The implicit PART.manifest.json is an output: here it would have replaced the project.
    const fs::path level = dir / "level" / "level";
    fs::copy_file(project, level.string() + ".manifest.json");
    const std::string before = slurp(level.string() + ".manifest.json");
    expectOneLineError(runCli("pvs bake " + level.string() + ".manifest.json --shard 0/1 --out " + level.string()),
                       "the part's manifest");
    EXPECT_EQ(slurp(level.string() + ".manifest.json"), before);
    EXPECT_FALSE(fs::exists(level));
    // merge reads the manifests beside its parts: --out may not name one.
    const fs::path p0 = bake("p0", "--shard 0/1");
    const std::string manifest = slurp(p0.string() + ".manifest.json");
    expectOneLineError(runCli("pvs merge " + p0.string() + " --out " + p0.string() + ".manifest.json"), "would replace");
    EXPECT_EQ(slurp(p0.string() + ".manifest.json"), manifest);
    // pvs level does not replace a level already in the folder, unless told to.
    const std::string projectBefore = slurp(project);
    expectOneLineError(runCli("pvs level " + (dir / "level").string() + " --rooms 3"), "already exists");
    EXPECT_EQ(slurp(project), projectBefore);
    ASSERT_EQ(runCli("pvs level " + (dir / "level").string() + " --rooms 2 --objects 24 --force").code, 0);
    EXPECT_EQ(slurp(project), projectBefore);   // the same level, written again
}

TEST_F(PvsCli, EmptyNamesNaNsAndWrappedIntegersAreRefusedInOneLine)
{
    const std::string out = " --out " + (dir / "x.pvs").string();
    expectOneLineError(runCli("pvs bake " + project + " --out \"\""), "empty file name");
    expectOneLineError(runCli("pvs bake " + project + " --shard \"\"" + out), "empty shard");
    expectOneLineError(runCli("pvs bake " + project + " --json \"\"" + out), "empty file name");
    expectOneLineError(runCli("pvs level \"\""), "empty folder name");
    expectOneLineError(runCli("pvs bake " + project + " --prt-scale nan --prt " + (dir / "x.prt").string() + out),
                       "--prt-scale");
    expectOneLineError(runCli("pvs bake " + project + " --smallest-gap nan" + out), "--smallest-gap");
    expectOneLineError(runCli("pvs bake " + project + " --max-distance nan" + out), "--max-distance");
    for (const char* shard : {"4294967296/4294967297", "-1/4", "1/0", "0/1000001", "0x1/4", "1/2/3", " 0/2"})
        expectOneLineError(runCli("pvs bake " + project + " --shard '" + shard + "'" + out), "--shard");
    EXPECT_FALSE(fs::exists(dir / "x.pvs"));
    // Integers in the project are range-checked as integers: 2^32 must not wrap to 0.
    for (const auto& [key, value] : std::vector<std::pair<std::string, std::uint64_t>>{
             {"residue_rays", 4294967296ull}, {"coarse_shafts", 4294967296ull + 16}, {"fine_shafts", 4294967296ull + 4},
             {"residue_rays", 18446744073709551615ull}})
        expectOneLineError(runCli("pvs bake " + editedProject("wrapped.json", [&](nlohmann::json& p) { p[key] = value; }) + out),
                           "pvs." + key + " must be an integer in");
    expectOneLineError(
        runCli("pvs bake " + editedProject("negative.json", [](nlohmann::json& p) { p["fine_shafts"] = -4294967295ll; }) + out),
        "pvs.fine_shafts must be an integer in");
    EXPECT_FALSE(fs::exists(dir / "x.pvs"));
}

TEST_F(PvsCli, CheckRefusesAPvsWithBadCellBoxes)
{
    const fs::path good = bake("good.pvs", "--raw");
    const std::string bytes = slurp(good);
    // The first cell's min x (docs/pvs.md: the cell table starts at byte 160).
    for (const float bad : {std::nanf(""), std::numeric_limits<float>::infinity(), 1e30f, 1e9f}) {
        std::string damaged = bytes;
        std::memcpy(damaged.data() + 160, &bad, 4);
        std::ofstream(dir / "bad.pvs", std::ios::binary | std::ios::trunc) << damaged;
        expectOneLineError(runCli("pvs check " + project + " " + (dir / "bad.pvs").string() + " --cells 1"), "cell[0]");
    }
    std::string inverted = bytes;   // min x above max x
    const float above = 1e5f;
    std::memcpy(inverted.data() + 160, &above, 4);
    std::ofstream(dir / "bad.pvs", std::ios::binary | std::ios::trunc) << inverted;
    expectOneLineError(runCli("pvs check " + project + " " + (dir / "bad.pvs").string() + " --cells 1"), "inverted");
}

TEST_F(PvsCli, MpiBakeOverThreeRanksIsByteIdentical)
{
    if (std::system("command -v mpirun > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "mpirun not installed (Debian: openmpi-bin)";
    const std::string reference = sha(bake("whole.pvs", "--cell-rows --json " + (dir / "whole.pvs.json").string()));
    const fs::path out = dir / "mpi.pvs";
    const CliRun run = runProgram("env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_plm=isolated "
                                  "OMPI_MCA_btl_vader_single_copy_mechanism=none mpirun --oversubscribe -np 3",
                                  std::string(SIGHTLINE_CLI) + " pvs bake " + project + " --mpi --cell-rows --threads 1 --out " +
                                      out.string() + " --json " + (dir / "mpi.pvs.json").string() + " --print-json",
                                  300);
    ASSERT_EQ(run.code, 0) << run.err << run.out;
    EXPECT_EQ(sha(out), reference);
    EXPECT_EQ(slurp(dir / "mpi.pvs.json"), slurp(dir / "whole.pvs.json"));
    EXPECT_NE(run.out.find("\"ranks\":3"), std::string::npos) << run.out;
}

TEST_F(PvsCli, PartsFromAnotherSceneOrOtherSettingsAreRefused)
{
    const fs::path p0 = bake("p0", "--shard 0/2");
    const fs::path p1 = bake("p1", "--shard 1/2");
    // Other settings: a finer refine pass.
    const fs::path fine = bake("fine1", "--shard 1/2 --fine 4");
    expectOneLineError(runCli("pvs merge " + p0.string() + " " + fine.string() + " --out " + (dir / "m.pvs").string()),
                       "baked with other settings");
    // Another scene: a level of another seed.
    ASSERT_EQ(runCli("pvs level " + (dir / "other").string() + " --rooms 2 --objects 24 --seed 2").code, 0);
    const fs::path foreign = bake("foreign1", "--shard 1/2", (dir / "other" / "pvs_level.json").string());
    expectOneLineError(runCli("pvs merge " + p0.string() + " " + foreign.string() + " --out " + (dir / "m.pvs").string()),
                       "is of another scene");
    expectOneLineError(runCli("pvs merge " + p0.string() + " --out " + (dir / "m.pvs").string()), "shard 1/2 is missing");
    expectOneLineError(runCli("pvs merge " + p0.string() + " " + p0.string() + " " + p1.string() + " --out " +
                              (dir / "m.pvs").string()),
                       "given twice");
    expectOneLineError(runCli("pvs merge " + project + " --out " + (dir / "m.pvs").string()), "not a PVS part file");
    expectOneLineError(runCli("pvs bake " + project + " --shard 2/2 --out x"), "--shard: expected I/N");
    expectOneLineError(runCli("pvs bake " + project + " --shard 0/2 --mpi --out x"), "--mpi and --shard");
    expectOneLineError(runCli("pvs bake " + project + " --shard 0/2 --json x.json --out x"), "part file only");
}

TEST_F(PvsCli, OverridesAreAppliedAndBadOnesRefused)
{
    const fs::path plain = bake("plain.pvs", "--json " + (dir / "plain.pvs.json").string());
    const auto before = nlohmann::json::parse(slurp(dir / "plain.pvs.json"));
    // Instance 23 is a prop in one room: from some cell it is hidden. Always and never override it.
    const std::string always = editedProject("always.json", [](nlohmann::json& p) {
        p["overrides"] = {{{"instance", 23}, {"visible", "always"}}, {{"object", "floor"}, {"visible", "never"}, {"cells", {0}}}};
    });
    bake("always.pvs", "--json " + (dir / "always.pvs.json").string(), always);
    const auto after = nlohmann::json::parse(slurp(dir / "always.pvs.json"));
    std::size_t hiddenBefore = 0;
    for (std::size_t c = 0; c < after["visible"].size(); ++c) {
        const auto& row = after["visible"][c];
        EXPECT_NE(std::find(row.begin(), row.end(), 23), row.end()) << "cell " << c;
        const auto& old = before["visible"][c];
        hiddenBefore += std::find(old.begin(), old.end(), 23) == old.end();
    }
    EXPECT_GT(hiddenBefore, 0u);   // the override changed something
    const auto& cell0 = after["visible"][0];
    EXPECT_EQ(std::find(cell0.begin(), cell0.end(), 0), cell0.end());   // the floor is object 0
    const auto& before0 = before["visible"][0];
    EXPECT_NE(std::find(before0.begin(), before0.end(), 0), before0.end());

    expectOneLineError(runCli("pvs bake " + editedProject("bad1.json", [](nlohmann::json& p) {
                                  p["overrides"] = {{{"object", "no_such_thing"}, {"visible", "always"}}};
                              }) + " --out x"),
                       "no object is named 'no_such_thing'");
    expectOneLineError(runCli("pvs bake " + editedProject("bad2.json", [](nlohmann::json& p) {
                                  p["overrides"] = {{{"instance", 5}, {"visible", "sometimes"}}};
                              }) + " --out x"),
                       "must be \"always\" or \"never\"");
    expectOneLineError(runCli("pvs bake " + editedProject("bad3.json", [](nlohmann::json& p) {
                                  p["overrides"] = {{{"instance", 5000}, {"visible", "never"}}};
                              }) + " --out x"),
                       "instance 5000 is not in the scene");
    expectOneLineError(runCli("pvs bake " + editedProject("bad4.json", [](nlohmann::json& p) {
                                  p["overrides"] = {{{"instance", 5}, {"visible", "never"}, {"cells", {64}}}};
                              }) + " --out x"),
                       "is not a cell index");
}

TEST_F(PvsCli, BadCellsAreRefusedInOneLine)
{
    auto withCell = [&](const std::string& name, nlohmann::json cell) {
        return editedProject(name, [cell](nlohmann::json& p) { p["cells"] = {cell}; });
    };
    expectOneLineError(runCli("pvs bake " + withCell("inv.json", {{"min", {0, 2, 0}}, {"max", {1, 1, 1}}}) + " --out x"),
                       "pvs.cells[0]: inverted box");
    expectOneLineError(runCli("pvs bake " + withCell("flat.json", {{"min", {0, 1, 0}}, {"max", {1, 1, 1}}}) + " --out x"),
                       "pvs.cells[0]: empty box");
    expectOneLineError(runCli("pvs bake " + withCell("nan.json", {{"min", {0, nullptr, 0}}, {"max", {1, 1, 1}}}) + " --out x"),
                       "must be three finite numbers");
    expectOneLineError(runCli("pvs bake " + editedProject("none.json", [](nlohmann::json& p) { p["cells"] = nlohmann::json::array(); }) +
                              " --out x"),
                       "no view cells");
    expectOneLineError(runCli("pvs bake " + editedProject("size.json", [](nlohmann::json& p) {
                                  p.erase("cells");
                                  p["cell_size"] = -1;
                              }) + " --out x"),
                       "pvs.cell_size must be a positive number");
}

/// Quake's row decompression, written from the format's description (not Sightline's code).
std::vector<bool> quakeRow(const std::string& lump, std::size_t at, std::size_t bits)
{
    std::vector<bool> row;
    while (row.size() < bits) {
        const unsigned char b = static_cast<unsigned char>(lump.at(at++));
        if (b == 0) {
            row.insert(row.end(), 8 * static_cast<unsigned char>(lump.at(at++)), false);
            continue;
        }
        for (int k = 0; k < 8; ++k)
            row.push_back((b >> k) & 1);
    }
    row.resize(bits);
    return row;
}

std::uint32_t le32(const std::string& s, std::size_t at)
{
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k)
        v |= std::uint32_t(static_cast<unsigned char>(s.at(at + std::size_t(k)))) << (8 * k);
    return v;
}

TEST_F(PvsCli, QuakeRowsAreCellToCellAndMatchTheJson)
{
    // 2 x 2 rooms, 16 cells each: the Quake lumps hold cluster (cell) rows, decoded here by a
    // decoder of the test's own; each row equals the .pvs.json's visible_cells, and every cell
    // sees itself.
    const fs::path out = bake("q.pvs", "--quake1 " + (dir / "q.q1").string() + " --quake2 " + (dir / "q.q2").string() +
                                           " --json " + (dir / "q.pvs.json").string());
    const auto j = nlohmann::json::parse(slurp(dir / "q.pvs.json"));
    ASSERT_TRUE(j.contains("visible_cells"));
    const std::size_t cells = j["cells"].size();
    ASSERT_EQ(cells, 64u);
    const std::string q1 = slurp(dir / "q.q1"), q2 = slurp(dir / "q.q2");
    ASSERT_EQ(le32(q1, 0), cells);
    ASSERT_EQ(le32(q2, 0), cells);
    for (std::size_t c = 0; c < cells; ++c) {
        std::vector<bool> expected(cells, false);
        for (const auto& d : j["visible_cells"][c])
            expected[d.get<std::size_t>()] = true;
        EXPECT_TRUE(expected[c]) << "cell " << c << " sees itself";
        EXPECT_EQ(quakeRow(q1, 4 + 4 * cells + le32(q1, 4 + 4 * c), cells), expected) << "quake1 cell " << c;
        EXPECT_EQ(quakeRow(q2, le32(q2, 4 + 8 * c), cells), expected) << "quake2 cell " << c;
    }
    // Parts baked without cell rows cannot make Quake lumps: one line says how to bake them.
    const fs::path p0 = bake("n0", "--shard 0/1");
    expectOneLineError(runCli("pvs merge " + p0.string() + " --out " + (dir / "n.pvs").string() + " --quake1 " +
                              (dir / "n.q1").string()),
                       "--cell-rows");
    EXPECT_TRUE(fs::exists(out));
}

TEST_F(PvsCli, EngineFormatsAndCheckAreWritten)
{
    const fs::path out = bake("a.pvs", "--quake1 " + (dir / "a.q1").string() + " --quake2 " + (dir / "a.q2").string() +
                                           " --prt " + (dir / "a.prt").string() + " --prt-scale 39.37");
    const std::string prt = slurp(dir / "a.prt");
    EXPECT_EQ(prt.substr(0, 8), "PRT1\n64\n");
    const std::string q2 = slurp(dir / "a.q2");
    ASSERT_GE(q2.size(), 4u);
    EXPECT_EQ(std::uint8_t(q2[0]), 64);   // numclusters, little-endian
    const CliRun check = runCli("pvs check " + project + " " + out.string() + " --cells 8 --cell-points 8 --object-points 8 "
                                "--views 1 --print-json --gaps " + (dir / "gaps.json").string());
    ASSERT_EQ(check.code, 0) << check.err;
    const auto report = nlohmann::json::parse(check.out);
    EXPECT_EQ(report["reference_cells"], 8);
    EXPECT_LE(report["missed_pairs"].get<int>(), report["reference_visible_pairs"].get<int>());
    const nlohmann::json gaps = nlohmann::json::parse(slurp(dir / "gaps.json"))["gaps"];
    EXPECT_EQ(gaps.size(), report["gaps"].get<std::size_t>());
    EXPECT_GE(gaps.size(), report["missed_pairs"].get<std::size_t>());   // each missed pair: one opening or more
    for (const nlohmann::json& gap : gaps) {
        EXPECT_GE(gap["opening"]["rays"].get<int>(), 1);
        for (int k = 0; k < 3; ++k) {
            EXPECT_LE(gap["opening"]["min"][k].get<double>(), gap["opening"]["centre"][k].get<double>() + 1e-9);
            EXPECT_GE(gap["opening"]["max"][k].get<double>(), gap["opening"]["centre"][k].get<double>() - 1e-9);
        }
    }
    // A .pvs checked against another scene's project is refused.
    ASSERT_EQ(runCli("pvs level " + (dir / "other").string() + " --rooms 2 --objects 24 --seed 3").code, 0);
    expectOneLineError(runCli("pvs check " + (dir / "other" / "pvs_level.json").string() + " " + out.string()),
                       "baked from another scene");
}

} // namespace
} // namespace sightline::test
