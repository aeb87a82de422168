// Recorded paths in the project file (project/RecordedPath.h): a path survives a save and load
// exactly and beside the other keys, plays back with held keys (camera and edits), leaves alone an
// occluder renamed since, and a malformed path is refused in one line naming its key.

#include <filesystem>

#include <gtest/gtest.h>
#include <unistd.h>

#include "project/Project.h"
#include "project/ProjectMotion.h"
#include "project/RecordedPath.h"
#include "base/Error.h"
#include "visibility/Patch.h"

using namespace sightline;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

Project twoPatchProject()
{
    Project project;
    project.name = "p.json";
    project.source.corner = {0.0, 1.0, 0.0};
    project.receiver.corner = {0.0, 1.0, 8.0};
    OccluderSpec crate;
    crate.name = "crate";
    crate.mesh = "box";
    project.occluders.push_back(crate);
    return project;
}

RecordedPath samplePath()
{
    RecordedPath path;
    path.fps = 24.0;
    path.frames = 30;
    path.camera.push_back({0, {{1.0, 2.0, 3.0}, 7.5, 0.25, -0.5, 0.9}});
    path.camera.push_back({12, {{1.1, 2.0, 3.0}, 7.0, 0.3, -0.45, 0.9}});
    path.camera.push_back({18, {{1.1, 2.0, 3.0}, 7.0, 0.0, -1.5, 0.9, true}});   // the top view, orthographic
    PathEdit start;
    start.frame = 0;
    start.object = PathEdit::Object::Receiver;
    start.patch.corner = {0.0, 1.0, 8.0};
    PathEdit moved = start;
    moved.frame = 20;
    moved.patch.corner = {0.0, 1.0, 6.125};
    moved.patch.u = {2.0, 0.0, 0.0};
    PathEdit crate;
    crate.frame = 20;
    crate.object = PathEdit::Object::Occluder;
    crate.index = 0;
    crate.name = "crate";
    crate.transform[3] = glm::vec4(2.0f, 0.5f, 4.0f, 1.0f);
    path.edits = {start, moved, crate};
    return path;
}

TEST(RecordedPath, RoundTripsThroughTheProjectFileBesideOtherKeys)
{
    const fs::path folder = fs::temp_directory_path() / ("sightline-path-" + std::to_string(getpid()));
    fs::create_directories(folder);
    Project project = twoPatchProject();
    project.extra["designer_notes"] = "kept";
    const RecordedPath path = samplePath();
    setRecordedPath(project, path);
    saveProject(project, folder / "p.json");

    const Project loaded = loadProject(folder / "p.json");
    EXPECT_EQ(loaded.extra.at("designer_notes"), "kept");
    const RecordedPath back = parseRecordedPath(loaded, "p.json");
    EXPECT_EQ(back.fps, path.fps);
    EXPECT_EQ(back.frames, path.frames);
    ASSERT_EQ(back.camera.size(), path.camera.size());
    for (std::size_t k = 0; k < path.camera.size(); ++k) {
        EXPECT_EQ(back.camera[k].frame, path.camera[k].frame);
        EXPECT_EQ(back.camera[k].camera, path.camera[k].camera);   // exact: doubles written round-trip
    }
    ASSERT_EQ(back.edits.size(), path.edits.size());
    EXPECT_EQ(back.edits[1].patch.corner, path.edits[1].patch.corner);
    EXPECT_EQ(back.edits[1].patch.u, path.edits[1].patch.u);
    EXPECT_EQ(back.edits[2].transform, path.edits[2].transform);
    EXPECT_EQ(toJson(back), toJson(path));
    // The orthographic flag is kept, and written only where it is set.
    EXPECT_TRUE(back.camera[2].camera.orthographic);
    EXPECT_FALSE(back.camera[1].camera.orthographic);
    EXPECT_FALSE(toJson(path).at("camera")[1].contains("orthographic"));

    // A second save of the loaded project keeps it byte for byte (an unknown key to the model).
    saveProject(loaded, folder / "q.json");
    EXPECT_EQ(loadProject(folder / "q.json").extra.at(kRecordedPathKey), loaded.extra.at(kRecordedPathKey));
    // An empty path removes the key.
    Project cleared = loaded;
    setRecordedPath(cleared, RecordedPath{});
    EXPECT_FALSE(cleared.extra.contains(kRecordedPathKey));
    EXPECT_TRUE(parseRecordedPath(cleared, "p.json").empty());
    fs::remove_all(folder);
}

TEST(RecordedPath, KeysHoldUntilTheNextOne)
{
    const Project project = twoPatchProject();
    const RecordedPath path = samplePath();
    EXPECT_EQ(path.cameraAt(0)->distance, 7.5);
    EXPECT_EQ(path.cameraAt(11)->distance, 7.5);
    EXPECT_EQ(path.cameraAt(12)->distance, 7.0);
    EXPECT_EQ(path.cameraAt(29)->distance, 7.0);

    const Project early = projectAtPathFrame(project, path, 19);
    EXPECT_EQ(early.receiver.corner, glm::dvec3(0.0, 1.0, 8.0));
    EXPECT_EQ(early.receiver.na, project.receiver.na);
    // The crate's only key is at frame 20: before it, that key holds (its first).
    EXPECT_EQ(early.occluders[0].transform[3], glm::vec4(2.0f, 0.5f, 4.0f, 1.0f));
    const Project late = projectAtPathFrame(project, path, 20);
    EXPECT_EQ(late.receiver.corner, glm::dvec3(0.0, 1.0, 6.125));
    EXPECT_EQ(late.receiver.u, glm::dvec3(2.0, 0.0, 0.0));
    EXPECT_EQ(late.source.corner, project.source.corner);   // no source edits: the project's

    // Renamed since recording: left alone.
    Project renamed = project;
    renamed.occluders[0].name = "barrel";
    EXPECT_EQ(projectAtPathFrame(renamed, path, 25).occluders[0].transform, glm::mat4(1.0f));

    // Time to frame: k / fps maps back to k, held at the end.
    EXPECT_EQ(path.frameAtTime(12.0 / 24.0), 12);
    EXPECT_EQ(path.frameAtTime(0.0), 0);
    EXPECT_EQ(path.frameAtTime(100.0), 29);
    EXPECT_DOUBLE_EQ(path.seconds(), 30.0 / 24.0);
}

std::string errorOf(const json& recorded)
{
    Project project = twoPatchProject();
    project.extra[kRecordedPathKey] = recorded;
    try {
        parseRecordedPath(project, "p.json");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(RecordedPath, AMalformedPathIsRefusedNamingTheKey)
{
    const json good = toJson(samplePath());
    auto with = [&](const json::json_pointer& at, const json& value) {
        json j = good;
        j[at] = value;
        return j;
    };
    const std::pair<json, std::string> cases[] = {
        {json::array(), "p.json: 'recorded_path' must be an object"},
        {with(json::json_pointer("/fps"), 0), "'recorded_path.fps' must be in (0, 1000]"},
        {with(json::json_pointer("/frames"), 0), "'recorded_path.frames' must be in [1, "},
        {with(json::json_pointer("/frames"), "ten"), "'recorded_path.frames' must be an integer"},
        {with(json::json_pointer("/camera/1/frame"), 0), "'recorded_path.camera[1].frame' must be greater"},
        {with(json::json_pointer("/camera/1/frame"), 30), "'recorded_path.camera[1].frame' must be in [0, frames)"},
        {with(json::json_pointer("/camera/0/distance"), -1), "'recorded_path.camera[0].distance' must be positive"},
        {with(json::json_pointer("/camera/0/target"), json::array({1, 2})), "'recorded_path.camera[0].target' must be an array of 3"},
        {with(json::json_pointer("/camera/2/orthographic"), "yes"), "'recorded_path.camera[2].orthographic' must be true or false"},
        {with(json::json_pointer("/edits/0/object"), "door"), "'recorded_path.edits[0].object' must be \"source\""},
        {with(json::json_pointer("/edits/2/frame"), 5), "'recorded_path.edits[2].frame' must not be less"},
        {with(json::json_pointer("/edits/2/transform"), json::array({1, 2, 3})), "'recorded_path.edits[2].transform' must be an array of 16"},
        {with(json::json_pointer("/edits/2/index"), -1), "'recorded_path.edits[2].index' must be an occluder's index"},
        {with(json::json_pointer("/edits/2/transform/3"), 0.5), "'recorded_path.edits[2].transform' must be affine"},
        {with(json::json_pointer("/edits/2/transform/15"), 2), "'recorded_path.edits[2].transform' must be affine"},
        {with(json::json_pointer("/edits"), json::array_t(kMaxPathKeys + 1)), "'recorded_path.edits' has 100001 keys; at most 100000"},
        {with(json::json_pointer("/camera"), json::array_t(kMaxPathKeys + 1)), "'recorded_path.camera' has 100001 keys"},
    };
    for (const auto& [document, says] : cases) {
        const std::string error = errorOf(document);
        EXPECT_NE(error.find(says), std::string::npos) << error;
        EXPECT_EQ(error.find('\n'), std::string::npos);
    }
    EXPECT_EQ(errorOf(good), "");
}

// Every run over a path checks its patches at each frame the same way (validateMotionFrames), and
// the state it checks at a frame is the one projectAtPathFrame plays.
TEST(RecordedPath, InvalidPatchesAtAnyFrameAreRefusedNamingTheFrame)
{
    const Project base = withoutMotionKeys(twoPatchProject());
    RecordedPath path = samplePath();
    EXPECT_NO_THROW(validateMotionFrames(base, ProjectMotion::of(path), path.frames));
    for (const int f : {0, 5, 21})
        EXPECT_NO_THROW(validatePatchPair(projectAtPathFrame(base, path, f).source, projectAtPathFrame(base, path, f).receiver));

    auto errorAt = [&](const PathEdit& bad) {
        RecordedPath p = samplePath();
        p.edits.push_back(bad);
        try {
            validateMotionFrames(base, ProjectMotion::of(p), p.frames);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    PathEdit flat;
    flat.frame = 25;
    flat.object = PathEdit::Object::Receiver;
    flat.patch.corner = {0.0, 1.0, 8.0};
    flat.patch.u = {0.0, 0.0, 0.0};   // degenerate
    EXPECT_EQ(errorAt(flat).rfind("frame 25: ", 0), 0u) << errorAt(flat);
    PathEdit across = flat;
    across.patch = Patch{};
    across.patch.corner = {0.0, 1.0, 0.0};   // on the source's plane
    EXPECT_EQ(errorAt(across).rfind("frame 25: ", 0), 0u) << errorAt(across);
    PathEdit far = flat;
    far.patch = Patch{};
    far.patch.corner = {1e6, 1.0, 8.0};
    EXPECT_EQ(errorAt(far).rfind("frame 25: ", 0), 0u) << errorAt(far);
    // Beyond the frames asked for, an edit is not checked.
    RecordedPath late = samplePath();
    late.edits.push_back(flat);
    EXPECT_NO_THROW(validateMotionFrames(base, ProjectMotion::of(late), 25));
}

} // namespace
