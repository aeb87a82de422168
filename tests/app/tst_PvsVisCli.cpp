// sightline-cli pvs vis: an original Quake level in, a copy with new visibility rows out that an
// engine's reading of the format accepts; the input is never written; bad files get one line.

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRunner.h"
#include "EngineBspReader.h"

namespace sightline::test {
namespace {

const std::string kLevel = SIGHTLINE_TEST_DATA "/levels/quake-dm4.bsp";

std::string slurp(const fs::path& file)
{
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

class PvsVisCli : public CliFolderTest {
protected:
    void SetUp() override
    {
        CliFolderTest::SetUp();
        level = folder / "dm4.bsp";
        fs::copy_file(kLevel, level);
    }
    fs::path level;
};

TEST_F(PvsVisCli, WritesACopyAnEngineReadsWithRowsNoWitnessContradicts)
{
    const fs::path out = folder / "dm4-vis.bsp", prt = folder / "dm4.prt";
    const std::string before = slurp(level);
    const CliRun run = runCli("pvs vis " + level.string() + " --out " + out.string() + " --prt " + prt.string() +
                                  " --check 16 --threads 2 --print-json",
                              300);
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_EQ(slurp(level), before) << "the input is never written";
    const nlohmann::json report = nlohmann::json::parse(run.out);
    EXPECT_EQ(report["format"], "BSP29");
    EXPECT_EQ(report["visleafs"], 434);
    EXPECT_EQ(report["liquids"], "clear");
    EXPECT_EQ(report["check"]["culled"]["witnessed"], 0);
    EXPECT_GT(report["check"]["culled"]["pairs"].get<int>(), 50000);
    EXPECT_GT(report["check"]["kept"]["witnessed"].get<int>(), 0);
    EXPECT_GT(report["level"]["visible_mean"].get<double>(), 1.0);

    const EngineBsp engine = readEngineBsp(slurp(out));
    const EngineBsp original = readEngineBsp(before);
    EXPECT_EQ(engine.visleafs, original.visleafs);
    for (int lump : {1, 5, 7, 14})
        EXPECT_EQ(engine.lumpBytes(lump), original.lumpBytes(lump)) << "lump " << lump << " unchanged";
    std::size_t visible = 0;
    for (int leaf = 1; leaf <= engine.visleafs; ++leaf) {
        const std::vector<bool> row = engineLeafPvs(engine, leaf);
        EXPECT_TRUE(row[std::size_t(leaf) - 1]) << "a leaf sees itself";
        for (bool b : row)
            visible += b;
    }
    EXPECT_NEAR(double(visible) / engine.visleafs, report["visible_mean"].get<double>(), 1e-9);
    EXPECT_EQ(int(engine.lumpBytes(4).size()), report["lump_bytes"].get<int>());

    std::istringstream portals(slurp(prt));
    std::string magic;
    int leaves = 0, count = 0;
    portals >> magic >> leaves >> count;
    EXPECT_EQ(magic, "PRT1");
    EXPECT_EQ(leaves, 434);
    EXPECT_EQ(count, report["portals"].get<int>());
}

TEST_F(PvsVisCli, NeverWritesOverTheLevelOrOneOutputWithAnother)
{
    const std::string before = slurp(level);
    expectOneLineError(runCli("pvs vis " + level.string() + " --out " + level.string()), "would replace the level");
    expectOneLineError(runCli("pvs vis " + level.string() + " --out " + (folder / "./dm4.bsp").string()), "would replace");
    const fs::path same = folder / "same";
    expectOneLineError(runCli("pvs vis " + level.string() + " --out " + same.string() + " --prt " + same.string()), "--prt");
    EXPECT_FALSE(fs::exists(same));
    EXPECT_EQ(slurp(level), before);
}

TEST_F(PvsVisCli, BadFilesGetOneLine)
{
    const std::string bytes = slurp(level);
    const fs::path truncated = folder / "truncated.bsp", quake2 = folder / "q2.bsp", lumps = folder / "lumps.bsp";
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 3);
    std::string ibsp = bytes;
    ibsp.replace(0, 4, "IBSP");
    std::ofstream(quake2, std::ios::binary) << ibsp;
    std::string bad = bytes;
    bad[4 + 8 * 10 + 7] = char(0x7f);   // the leaves lump's length, far past the file
    std::ofstream(lumps, std::ios::binary) << bad;
    expectOneLineError(runCli("pvs vis " + truncated.string(), 60), "lies outside the file");
    expectOneLineError(runCli("pvs vis " + quake2.string(), 60), "Quake 2");
    expectOneLineError(runCli("pvs vis " + lumps.string(), 60), "lump 10");
    expectOneLineError(runCli("pvs vis " + folder.string(), 60), "not a regular file");
    expectOneLineError(runCli("pvs vis " + (folder / "missing.bsp").string(), 60), "missing.bsp");
}

TEST_F(PvsVisCli, ADamagedVisibilityLumpIsReplacedWithAWarning)
{
    // Leaf 1's row pointed at the lump's last byte, made a zero: its run's count lies past the end.
    std::string bytes = slurp(level);
    std::int32_t visOffset = 0, visLength = 0, leafOffset = 0;
    std::memcpy(&visOffset, bytes.data() + 4 + 8 * 4, 4);
    std::memcpy(&visLength, bytes.data() + 4 + 8 * 4 + 4, 4);
    std::memcpy(&leafOffset, bytes.data() + 4 + 8 * 10, 4);
    const std::int32_t last = visLength - 1;
    std::memcpy(bytes.data() + leafOffset + 28 + 4, &last, 4);
    bytes[std::size_t(visOffset + last)] = 0;
    const fs::path damaged = folder / "damaged.bsp", out = folder / "fixed.bsp";
    std::ofstream(damaged, std::ios::binary) << bytes;
    const CliRun run = runCli("pvs vis " + damaged.string() + " --out " + out.string() + " --threads 2 --print-json", 300);
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_NE(run.err.find("visibility lump is damaged"), std::string::npos) << run.err;
    EXPECT_TRUE(oneLine(run.err)) << run.err;
    const nlohmann::json report = nlohmann::json::parse(run.out);
    EXPECT_TRUE(report.contains("level_damage"));
    EXPECT_FALSE(report.contains("level"));
    const EngineBsp fixed = readEngineBsp(slurp(out));   // every row decodes again
    EXPECT_EQ(fixed.visleafs, 434);
}

} // namespace
} // namespace sightline::test
