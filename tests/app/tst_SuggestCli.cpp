// `sightline-cli suggest` run as a user does (docs/design.md §4): the JSON it prints, the project
// it writes (sampled again by `shaft`), the files it never replaces, and its one-line refusals.
#include <filesystem>
#include <fstream>
#include <string>

#include <QImage>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRunner.h"
#include "TestScenes.h"
#include "base/NpyFile.h"
#include "visibility/suggest/ConvexHull2.h"

using namespace sightline;
using namespace sightline::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

class SuggestCli : public CliFolderTest {
protected:
    void SetUp() override
    {
        CliFolderTest::SetUp();
        // A 2 x 2 m wall with a 1 m hole between the patches: the rays through the hole are the
        // view to cut.
        test::writeWallWithHoleObj(folder / "wall.obj");
        const json project = {
            {"version", 1},
            {"scene", "wall.obj"},
            {"source", {{"corner", {0, 0, 0}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}, {"samples", {32, 32}}}},
            {"receiver", {{"corner", {-0.5, -0.2, 4}}, {"u", {2, 0, 0.3}}, {"v", {0, 1.4, 0}}, {"samples", {32, 32}}}},
            {"keep_me", {{"note", "an unknown key"}}},
        };
        std::ofstream(folder / "p.json") << project.dump(2);
    }
    std::string p(const std::string& name) const { return path(name); }
};

} // namespace

TEST_F(SuggestCli, WrittenProjectLeavesWhatItPrinted)
{
    const json before = runJson("shaft " + p("p.json") + " --method cpu --json");
    for (const std::string shape : {"convex", "rect"}) {
        const std::string out = p(shape + ".json");
        const json s = runJson("suggest " + p("p.json") + " --depth 0.4 --shape " + shape + " --write " + out + " --json");
        for (const char* key : {"area", "unblocked_before", "unblocked_after", "promised"})
            EXPECT_TRUE(s.contains(key)) << key;
        EXPECT_EQ(s["unblocked_before"], before["unblocked"]);
        EXPECT_GT(s["unblocked_before"].get<int>(), 1000);
        EXPECT_EQ(s["promised"], 0);
        EXPECT_EQ(s["unblocked_after"], 0);
        EXPECT_GT(s["area"].get<double>(), 0.0);
        // The saved project, sampled by the exact sampler and by the reference, is cut.
        for (const char* method : {"cpu", "raycast"}) {
            const json after = runJson("shaft " + out + " --method " + std::string(method) + " --json");
            EXPECT_EQ(after["unblocked"], 0) << shape << " " << method;
        }
        const json saved = json::parse(std::ifstream(out));
        EXPECT_EQ(saved["keep_me"]["note"], "an unknown key");
        ASSERT_EQ(saved["occluders"].size(), 1u);
        EXPECT_EQ(saved["occluders"][0]["mesh"], shape == "rect" ? "plane" : "convex-occluder.glb");
        if (shape == "convex") {
            EXPECT_TRUE(fs::exists(p("convex-occluder.glb")));
        }
    }
}

TEST_F(SuggestCli, ConvexAtShareOneIsTheHullOfTheCrossings)
{
    // The crossings computed here from the mask, independently of the tool's own code.
    const json s = runJson("suggest " + p("p.json") + " --depth 0.5 --json");
    ASSERT_EQ(runCli("shaft " + p("p.json") + " --method raycast --mask " + p("m.npy")).code, 0);
    std::ifstream file(p("m.npy"), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    const std::size_t header = 10 + std::size_t(std::uint8_t(bytes[8])) + 256 * std::size_t(std::uint8_t(bytes[9]));
    const glm::dvec3 cs(0.5, 0.5, 0.0), cr(0.5, 0.5, 4.15);   // the patches' centres
    const glm::dvec3 origin = 0.5 * (cs + cr), n = glm::normalize(cr - cs);
    const glm::dvec3 a = glm::normalize(glm::cross(n, glm::dvec3(0, 1, 0))), b = glm::cross(n, a);
    std::vector<suggest::Point2> crossings;
    for (int j = 0; j < 1024; ++j)
        for (int i = 0; i < 1024; ++i) {
            if ((std::uint8_t(bytes[header + std::size_t(j) * 128 + std::size_t(i / 8)]) >> (i % 8)) & 1)
                continue;
            const glm::dvec3 S(( i % 32 + 0.5) / 32, (i / 32 + 0.5) / 32, 0.0);
            const glm::dvec3 R = glm::dvec3(-0.5, -0.2, 4) + (j % 32 + 0.5) / 32 * glm::dvec3(2, 0, 0.3) +
                                 (j / 32 + 0.5) / 32 * glm::dvec3(0, 1.4, 0);
            const double t = glm::dot(origin - S, n) / glm::dot(R - S, n);
            const glm::dvec3 x = S + t * (R - S) - origin;
            crossings.push_back({glm::dot(x, a), glm::dot(x, b)});
        }
    ASSERT_EQ(crossings.size(), s["unblocked_before"].get<std::size_t>());
    const double hull = suggest::polygonArea(suggest::convexHull(crossings));
    EXPECT_GE(s["area"].get<double>(), hull);
    EXPECT_LE(s["area"].get<double>(), hull * 1.002);
}

TEST_F(SuggestCli, ShareAndShapeTradeAreaForRays)
{
    const json all = runJson("suggest " + p("p.json") + " --depth 0.5 --json");
    const json most = runJson("suggest " + p("p.json") + " --depth 0.5 --share 0.9 --json");
    const json rect = runJson("suggest " + p("p.json") + " --depth 0.5 --shape rect --json");
    EXPECT_LT(most["area"].get<double>(), all["area"].get<double>());
    EXPECT_GE(rect["area"].get<double>(), all["area"].get<double>());
    EXPECT_LE(most["unblocked_after"].get<int>(), most["promised"].get<int>());
    EXPECT_GT(most["promised"].get<int>(), 0);
    const CliRun text = runCli("suggest " + p("p.json") + " --depth 0.5");
    EXPECT_EQ(text.code, 0) << text.err;
    EXPECT_NE(text.out.find("promised at most 0"), std::string::npos) << text.out;
}

TEST_F(SuggestCli, NeverReplacesAFile)
{
    // An earlier suggestion's mesh stays; the new one gets the next free name.
    std::ofstream(p("out-occluder.glb")) << "an earlier file";
    runJson("suggest " + p("p.json") + " --depth 0.5 --write " + p("out.json") + " --json");
    EXPECT_EQ(json::parse(std::ifstream(p("out.json")))["occluders"][0]["mesh"], "out-occluder-2.glb");
    std::stringstream kept;
    kept << std::ifstream(p("out-occluder.glb")).rdbuf();
    EXPECT_EQ(kept.str(), "an earlier file");
    // Saved in another folder, the scene path still finds the level.
    fs::create_directories(folder / "sub");
    runJson("suggest " + p("p.json") + " --depth 0.5 --write " + p("sub/q.json") + " --json");
    EXPECT_EQ(runJson("shaft " + p("sub/q.json") + " --method cpu --json")["unblocked"], 0);
    for (const std::string target : {"p.json", "wall.obj"}) {
        const CliRun run = runCli("suggest " + p("p.json") + " --depth 0.5 --write " + p(target));
        EXPECT_NE(run.code, 0) << target;
        EXPECT_NE(run.err.find("would replace"), std::string::npos) << run.err;
    }
}

TEST_F(SuggestCli, RefusalsAreOneLine)
{
    for (const std::string arguments : {"--depth 0", "--depth 1", "--depth nan", "--depth 0.5 --share 0",
                                        "--depth 0.5 --share 1.5", "--depth 0.5 --shape star", "", "--depth 0.5 --write ''"}) {
        const CliRun run = runCli("suggest " + p("p.json") + " " + arguments);
        EXPECT_NE(run.code, 0) << arguments;
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << arguments << ": " << run.err;
        EXPECT_EQ(run.err.rfind("sightline-cli: error: ", 0), 0u) << arguments << ": " << run.err;
    }
    // A closed view: nothing to cut.
    json closed = json::parse(std::ifstream(p("p.json")));
    closed["occluders"] = {{{"name", "door"}, {"mesh", "plane"},
                            {"transform", {4, 0, 0, 0, 0, 0, 1, 0, 0, -4, 0, 0, 0.5, 0.5, 1, 1}}}};
    std::ofstream(p("closed.json")) << closed.dump();
    const CliRun run = runCli("suggest " + p("closed.json") + " --depth 0.5");
    EXPECT_NE(run.code, 0);
    EXPECT_NE(run.err.find("already blocked"), std::string::npos) << run.err;
}

// A surface the designer picked: the wall's own plane (the doorway's frame). The occluder lies in
// it, plugs the hole and nothing more, and the written project is cut by both exact samplers.
TEST_F(SuggestCli, OnAPickedSurfaceItPlugsTheOpening)
{
    for (const std::string normal : {"0 0 -1", "0 0 3"}) {   // either way round, any length
        const std::string out = p("plug.json");
        const json s = runJson("suggest " + p("p.json") + " --at -0.5 1.2 2 --normal " + normal + " --write " + out + " --json");
        EXPECT_TRUE(s["depth"].is_null());
        EXPECT_EQ(s["promised"], 0);
        EXPECT_EQ(s["unblocked_after"], 0);
        EXPECT_NEAR(s["plane"]["normal"][2].get<double>(), 1.0, 1e-12);   // from the source's side to the receiver's
        for (const json& corner : s["corners"]) {
            EXPECT_NEAR(corner[2].get<double>(), 2.0, 1e-6);   // in the wall's plane
            for (int axis : {0, 1}) {                         // within the hole, but for the exactness margin
                EXPECT_GT(corner[axis].get<double>(), -1e-3);
                EXPECT_LT(corner[axis].get<double>(), 1.0 + 1e-3);
            }
        }
        EXPECT_LE(s["area"].get<double>(), 1.0 + 4e-3);
        for (const char* method : {"cpu", "raycast"})
            EXPECT_EQ(runJson("shaft " + out + " --method " + std::string(method) + " --json")["unblocked"], 0) << method;
    }
    // One way of placing the plane, a surface between the patches, finite: else one line each.
    for (const std::string bad : {" --at 0 0 5 --normal 0 0 1", " --at 0 0 -1 --normal 0 0 1", " --at 0 0 2 --normal 0 0 0",
                                  " --at 0 0 2", " --normal 0 0 1", " --at 0 0 2 --normal 0 0 1 --depth 0.5", "",
                                  " --at 0 0 --normal 0 0 1", " --at 0 0 2 --normal 0 0 inf"}) {
        const CliRun run = runCli("suggest " + p("p.json") + bad);
        EXPECT_NE(run.code, 0) << bad;
        EXPECT_TRUE(oneLine(run.err)) << bad << ": " << run.err;
    }
}

// --weighted: the share is of the light the rays carry. A light texture dark on its right half
// leaves only the left half's rays to cut: a smaller occluder for the same share, the light left
// within the promise, by the exact sampler. White light weighs every ray alike: the same occluder.
TEST_F(SuggestCli, WeightedShareIsOfTheLight)
{
    const json plain = runJson("suggest " + p("p.json") + " --depth 0.5 --share 0.8 --json");
    const json white = runJson("suggest " + p("p.json") + " --depth 0.5 --share 0.8 --weighted --json");
    EXPECT_FALSE(plain["weighted"].get<bool>());
    EXPECT_TRUE(white["weighted"].get<bool>());
    EXPECT_EQ(white["light_before"].get<double>(), white["unblocked_before"].get<double>());
    EXPECT_NEAR(white["area"].get<double>(), plain["area"].get<double>(), 1e-9);

    QImage texture(2, 1, QImage::Format_RGB32);
    texture.setPixel(0, 0, qRgb(255, 255, 255));
    texture.setPixel(1, 0, qRgb(0, 0, 0));
    ASSERT_TRUE(texture.save(QString::fromStdString(p("half.png"))));
    json project = json::parse(readAll(folder / "p.json"));
    project["light"] = {{"texture", "half.png"}};
    std::ofstream(folder / "half.json") << project.dump(2);
    const json half = runJson("suggest " + p("half.json") + " --depth 0.5 --share 0.8 --weighted --json");
    EXPECT_TRUE(half["weighted"].get<bool>());
    EXPECT_LT(half["light_before"].get<double>(), 0.75 * white["light_before"].get<double>());
    EXPECT_LE(half["light_after"].get<double>(), 0.2 * half["light_before"].get<double>() + 1e-9);
    EXPECT_LT(half["area"].get<double>(), plain["area"].get<double>());
}
