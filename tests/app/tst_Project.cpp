#include <filesystem>
#include <fstream>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "project/Project.h"
#include "base/Error.h"

using namespace sightline;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

json minimalDocument()
{
    return json::parse(R"({
      "version": 1,
      "scene": "level.obj",
      "source":   {"corner": [0, 1, 0], "u": [1, 0, 0], "v": [0, 1, 0], "samples": [8, 4]},
      "receiver": {"corner": [0, 1, 8], "u": [1, 0, 0], "v": [0, 1, 0]},
      "occluders": [{"name": "crate", "mesh": "box", "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 2,0,4,1]}]
    })");
}

std::string errorOf(const json& document)
{
    try {
        parseProject(document, "/tmp", "p.json");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

struct TempFolder {
    fs::path path;
    explicit TempFolder(const std::string& name) : path(fs::temp_directory_path() / name)
    {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempFolder() { fs::remove_all(path); }
};

} // namespace

TEST(Project, ParsesTheContractExample)
{
    const Project p = parseProject(minimalDocument(), "/levels", "p.json");
    EXPECT_EQ(p.scene, "level.obj");
    EXPECT_EQ(p.resolve(p.scene, "scene"), fs::path("/levels/level.obj"));
    EXPECT_EQ(p.resolve("/abs/x.glb", "scene"), fs::path("/abs/x.glb"));
    EXPECT_EQ(p.source.na, 8);
    EXPECT_EQ(p.source.nb, 4);
    EXPECT_EQ(p.receiver.na, 32);   // default
    EXPECT_EQ(p.receiver.corner.z, 8.0);
    ASSERT_EQ(p.occluders.size(), 1u);
    EXPECT_EQ(p.occluders[0].mesh, "box");
    EXPECT_FLOAT_EQ(p.occluders[0].transform[3][2], 4.0f);   // column-major translation
}

TEST(Project, RoundTripKeepsUnknownKeysEverywhere)
{
    json document = minimalDocument();
    document["editor"] = {{"camera", {1, 2, 3}}};
    document["source"]["colour"] = "red";
    document["occluders"][0]["locked"] = true;
    TempFolder folder("sightline_project_rt");
    const Project p = parseProject(document, folder.path, "p.json");
    saveProject(p, folder.path / "p.json");
    const Project q = loadProject(folder.path / "p.json");
    const json saved = toJson(q);
    EXPECT_EQ(saved["editor"]["camera"], json({1, 2, 3}));
    EXPECT_EQ(saved["source"]["colour"], "red");
    EXPECT_EQ(saved["occluders"][0]["locked"], true);
    EXPECT_EQ(saved["receiver"]["samples"], json({32, 32}));
    EXPECT_EQ(q.source.corner, p.source.corner);
    EXPECT_EQ(q.occluders[0].transform, p.occluders[0].transform);
    EXPECT_EQ(toJson(p), saved);
}

// Unknown keys inside scene_transforms entries were dropped, and transforms were
// written back as float32 (1234567.891 as 1234567.875, 0.1 as 0.10000000149).
TEST(Project, SavingWritesBackWhatTheUserWrote)
{
    json document = minimalDocument();
    document["occluders"][0]["transform"] = json::parse("[1,0,0,0, 0,0.1,0,0, 0,0,1,0, 1234567.891,0,4.7,1]");
    document["scene_transforms"] = json::parse(R"([{"instance": 2, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0.3,0,-7.77,1],
                                                  "note": "moved for the sniper", "locked": true}])");
    TempFolder folder("sightline_project_as_written");
    Project p = parseProject(document, folder.path, "p.json");
    saveProject(p, folder.path / "p.json");
    json saved;
    std::ifstream(folder.path / "p.json") >> saved;
    EXPECT_EQ(saved["occluders"][0]["transform"], document["occluders"][0]["transform"]);
    EXPECT_EQ(saved["occluders"][0]["transform"][12].get<double>(), 1234567.891);
    EXPECT_EQ(saved["scene_transforms"], document["scene_transforms"]);

    // An edited transform is written as the shortest decimals its floats read back as.
    p.occluders[0].transform[3][0] = 2.5f;
    p.occluders[0].transform[1][1] = 0.2f;
    const json edited = toJson(p)["occluders"][0]["transform"];
    EXPECT_EQ(edited[12].get<double>(), 2.5);
    EXPECT_EQ(edited[5].get<double>(), 0.2);
    EXPECT_EQ(edited[14].get<double>(), 4.7);   // 4.7f, unedited in value, printed short
    EXPECT_EQ(parseProject(toJson(p), folder.path, "p.json").occluders[0].transform, p.occluders[0].transform);
}

TEST(Project, ErrorsNameTheBadKey)
{
    json d = minimalDocument();
    d.erase("source");
    EXPECT_NE(errorOf(d).find("'source' is missing"), std::string::npos) << errorOf(d);

    d = minimalDocument();
    d["source"]["samples"] = {0, 5};
    EXPECT_NE(errorOf(d).find("source.samples"), std::string::npos) << errorOf(d);

    d = minimalDocument();
    d["receiver"]["samples"] = {2000, 5};
    EXPECT_NE(errorOf(d).find("receiver.samples"), std::string::npos) << errorOf(d);

    d = minimalDocument();
    d["receiver"]["u"] = {1, "x", 0};
    EXPECT_NE(errorOf(d).find("receiver.u[1]"), std::string::npos) << errorOf(d);

    d = minimalDocument();
    d["occluders"][0]["transform"] = json::array({1, 0, 0});
    EXPECT_NE(errorOf(d).find("occluders[0].transform"), std::string::npos) << errorOf(d);

    // A projective last row was dropped without a word (points go through with w = 1, the
    // result's w ignored): the occluder or moved object stood elsewhere than the file said.
    for (const int element : {3, 7, 11, 15}) {
        d = minimalDocument();
        json t = json::array({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 0, 4, 1});
        t[std::size_t(element)] = element == 15 ? 2 : 1;
        d["occluders"][0]["transform"] = t;
        EXPECT_NE(errorOf(d).find("occluders[0].transform' must be affine"), std::string::npos) << errorOf(d);
        d = minimalDocument();
        json moved = json::object();   // spelt out: nested braces would make arrays of pairs
        moved["instance"] = 0;        // a signed integer, as a document built in code has
        moved["transform"] = t;
        d["scene_transforms"] = json::array();
        d["scene_transforms"].push_back(moved);
        EXPECT_NE(errorOf(d).find("scene_transforms[0].transform' must be affine"), std::string::npos) << errorOf(d);
        d["scene_transforms"][0]["instance"] = -1;
        EXPECT_NE(errorOf(d).find("scene_transforms[0].instance' must be a non-negative integer"), std::string::npos) << errorOf(d);
    }

    d = minimalDocument();
    d["version"] = 2;
    EXPECT_NE(errorOf(d).find("version"), std::string::npos) << errorOf(d);

    d = minimalDocument();
    d.erase("version");
    EXPECT_NE(errorOf(d).find("version"), std::string::npos) << errorOf(d);

    EXPECT_NE(errorOf(json::array()).find("JSON object"), std::string::npos);

    TempFolder folder("sightline_project_err");
    std::ofstream(folder.path / "bad.json") << "{\"version\": 1,";
    try {
        loadProject(folder.path / "bad.json");
        FAIL() << "malformed JSON accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("invalid JSON"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
    EXPECT_THROW(loadProject(folder.path / "missing.json"), Error);
}

/// loadProject's error for a file holding `text`: one line naming the file, or a failure.
std::string loadError(const fs::path& file, const std::string& text)
{
    std::ofstream(file, std::ios::binary) << text;
    try {
        loadProject(file);
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_NE(message.find(file.filename().string()), std::string::npos) << message;
        return message;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not a sightline::Error: " << e.what();
        return {};
    }
    ADD_FAILURE() << file << " loaded";
    return {};
}

TEST(Project, HostileJsonIsOneLineNamingTheFile)
{
    TempFolder folder("sightline_project_hostile");
    const std::string prefix = minimalDocument().dump();
    const std::string head = prefix.substr(0, prefix.size() - 1) + ",\"notes\":";

    // Nested far past any parser's stack under an unknown key (kept on load, so walked on save).
    const std::string deep = loadError(folder.path / "deep.json", head + std::string(100'000, '[') +
                                                                      std::string(100'000, ']') + "}");
    EXPECT_NE(deep.find("nested deeper than 512"), std::string::npos) << deep;
    const std::string array = loadError(folder.path / "array.json", std::string(1'000'000, '[') + std::string(1'000'000, ']'));
    EXPECT_NE(array.find("nested deeper than 512"), std::string::npos) << array;

    // A number beyond double: nlohmann's out_of_range, not a parse_error; no bracketed id.
    const std::string overflow = loadError(folder.path / "overflow.json", head + "1e400}");
    EXPECT_NE(overflow.find("invalid JSON: number overflow parsing '1e400', at byte"), std::string::npos) << overflow;
    EXPECT_EQ(overflow.find("[json.exception"), std::string::npos) << overflow;

    // Unknown keys of a legal depth are still kept.
    std::ofstream(folder.path / "notes.json") << head + "[[[\"[{\\\"\"]]]}";
    EXPECT_EQ(loadProject(folder.path / "notes.json").extra.at("notes").dump(), "[[[\"[{\\\"\"]]]");
}

TEST(Project, BuildSceneAddsOccluders)
{
    TempFolder folder("sightline_project_scene");
    std::ofstream(folder.path / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    json d = minimalDocument();
    d["scene"] = "tri.obj";
    d["occluders"].push_back({{"name", "floor"}, {"mesh", "plane"},
                              {"transform", {10, 0, 0, 0, 0, 1, 0, 0, 0, 0, 10, 0, 0, -1, 0, 1}}});
    d["occluders"].push_back({{"name", "again"}, {"mesh", "tri.obj"}});
    const Project p = parseProject(d, folder.path, "p.json");
    const Scene scene = buildScene(p);
    EXPECT_EQ(scene.triangleCount(), 1u + 12u + 2u + 1u);
    ASSERT_EQ(scene.instances.size(), 4u);
    EXPECT_EQ(scene.instances[1].name, "crate");
    const Bounds box = scene.bounds();
    EXPECT_FLOAT_EQ(box.min.x, -5.0f);   // 10 m plane centred on the origin
    EXPECT_FLOAT_EQ(box.min.y, -1.0f);
    EXPECT_FLOAT_EQ(box.max.z, 5.0f);
    EXPECT_FLOAT_EQ(box.max.x, 5.0f);

    d["occluders"].push_back({{"mesh", "sphere"}});
    EXPECT_THROW(buildScene(parseProject(d, folder.path, "p.json")), Error);
    d["occluders"].erase(d["occluders"].size() - 1);
    d["scene"] = "missing.glb";
    EXPECT_THROW(buildScene(parseProject(d, folder.path, "p.json")), Error);
}

TEST(Project, BuiltinMeshesAreClosedAndOriented)
{
    const Mesh box = builtinMesh("box");
    ASSERT_EQ(box.triangleCount(), 12u);
    EXPECT_TRUE(box.watertight);
    EXPECT_TRUE(closedAndOutward(box));   // the check an imported mesh must pass for the flag
    EXPECT_FALSE(builtinMesh("plane").watertight);
    // Every face normal points away from the centre.
    for (std::size_t t = 0; t < 12; ++t) {
        const glm::vec3 a = box.positions[box.indices[3 * t]], b = box.positions[box.indices[3 * t + 1]],
                        c = box.positions[box.indices[3 * t + 2]];
        EXPECT_GT(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0f), 0.0f) << "triangle " << t;
    }
    const Mesh plane = builtinMesh("plane");
    for (std::size_t t = 0; t < 2; ++t) {
        const glm::vec3 a = plane.positions[plane.indices[3 * t]], b = plane.positions[plane.indices[3 * t + 1]],
                        c = plane.positions[plane.indices[3 * t + 2]];
        EXPECT_GT(glm::cross(b - a, c - a).y, 0.0f);
    }
}
