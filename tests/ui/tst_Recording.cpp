// Video recordings of a project (ui/VideoRecording.h and `sightline --record`), decoded again with
// libavformat: the frame count, size and rate asked for; the rays follow the receiver as the
// animation moves it (the pixels that rays cover, found as the difference from the same video
// without rays, lie along the receiver's new place and leave its old one); a recorded path drives
// the camera and the edits with held keys; bad arguments give one-line errors and no file.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <glm/gtc/matrix_transform.hpp>

#include "CliRunner.h"
#include "EditorDocument.h"
#include "UiTestScene.h"
#include "VideoDecoder.h"
#include "VideoRecording.h"
#include "editor/ViewSettings.h"
#include "project/Animation.h"
#include "project/RecordedPath.h"

namespace sightline::ui {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::decodeVideo;
using test::DecodedVideo;

constexpr int kWidth = 192, kHeight = 144;

/// The floor level with its two patches and `extra` keys (an animation, a recorded path), saved as
/// a project in `folder` and opened.
void openFloorProject(EditorDocument& document, const fs::path& folder, const json& extra)
{
    Project project;
    project.scene = test::writeFloorObj(folder).filename().string();
    std::tie(project.source, project.receiver) = test::floorPatches();
    project.extra = extra;
    saveProject(project, folder / "floor.json");
    document.open(folder / "floor.json");
}

/// The receiver rises 2 m over 10 frames.
json risingReceiver()
{
    return {{"animation",
             {{"frames", 10},
              {"tracks", json::array({{{"target", "receiver"},
                                       {"keys", json::array({{{"frame", 0}, {"translate", {0, 0, 0}}},
                                                             {{"frame", 9}, {"translate", {0, 2, 0}}}})}}})}}}};
}

ViewStyle opaqueRays(bool show)
{
    ViewStyle style;
    style.showRays = show;
    style.rayCap = 1 << 16;
    style.freeColour = {1.0f, 0.85f, 0.15f, 1.0f};   // opaque: a crisp difference after encoding
    return style;
}

/// Whether the rays cover pixel (x, y) of frame f: most of its 3x3 neighbourhood differs clearly
/// from the video without rays.
bool rayAt(const DecodedVideo& with, const DecodedVideo& without, std::size_t f, glm::dvec3 pixel)
{
    int covered = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int x = int(pixel.x) + dx, y = int(pixel.y) + dy;
            int diff = 0;
            for (int c = 0; c < 3; ++c)
                diff += std::abs(with.at(f, x, y, c) - without.at(f, x, y, c));
            covered += diff > 90;
        }
    return covered >= 6;
}

int rayPixels(const DecodedVideo& with, const DecodedVideo& without, std::size_t f)
{
    int n = 0;
    for (int y = 0; y < with.height; ++y)
        for (int x = 0; x < with.width; ++x) {
            int diff = 0;
            for (int c = 0; c < 3; ++c)
                diff += std::abs(with.at(f, x, y, c) - without.at(f, x, y, c));
            n += diff > 90;
        }
    return n;
}

TEST(VideoRecording, TheRaysFollowTheReceiverAsTheAnimationMovesIt)
{
    const fs::path folder = test::freshFolder("record-animation");
    EditorDocument document;
    openFloorProject(document, folder, risingReceiver());
    const auto [source, receiver] = test::floorPatches();
    // From the side, with room above for the receiver's rise.
    Camera camera = shaftView(source, receiver);
    camera.distance *= 1.6;
    camera.target.y += 1.0;
    camera.pitch = -0.2;

    RecordingOptions options;
    options.width = kWidth;
    options.height = kHeight;
    options.fps = 30.0;
    RecordingScene scene = recordingScene(document, camera, opaqueRays(true));
    EXPECT_EQ(defaultRecordingFrames(scene, 30.0), 10);   // the animation's "frames"
    options.frames = defaultRecordingFrames(scene, 30.0);
    options.output = folder / "rays.mp4";
    const RecordingFigures figures = recordVideo(scene, options);
    EXPECT_EQ(figures.frames, 10);
    EXPECT_EQ(figures.source, "animation");
    EXPECT_EQ(figures.encoder, "libx264");
    scene.style = opaqueRays(false);
    options.output = folder / "no-rays.mp4";
    recordVideo(scene, options);

    const DecodedVideo with = decodeVideo((folder / "rays.mp4").string());
    const DecodedVideo without = decodeVideo((folder / "no-rays.mp4").string());
    EXPECT_EQ(with.codec, "h264");
    EXPECT_EQ(with.width, kWidth);
    EXPECT_EQ(with.height, kHeight);
    EXPECT_NEAR(with.fps, 30.0, 1e-9);
    ASSERT_EQ(with.frames.size(), 10u);
    ASSERT_EQ(without.frames.size(), 10u);

    // Near the receiver (a tenth of the way back to the source), where it is in frames 0 and 9.
    auto nearReceiver = [&](int frame) {
        const glm::dvec3 r = receiver.centre() + glm::dvec3(0.0, 2.0 * frame / 9.0, 0.0);
        return toPixels(camera, r + 0.1 * (source.centre() - r), kWidth, kHeight);
    };
    const glm::dvec3 first = nearReceiver(0), last = nearReceiver(9);
    ASSERT_GT(first.y - last.y, 10.0) << "the rise must show on screen for the test to mean anything";
    EXPECT_TRUE(rayAt(with, without, 0, first));
    EXPECT_FALSE(rayAt(with, without, 0, last));
    EXPECT_TRUE(rayAt(with, without, 9, last));
    EXPECT_FALSE(rayAt(with, without, 9, first));
    // Every frame shows rays (no frame dropped or blank).
    for (std::size_t f = 0; f < 10; ++f)
        EXPECT_GT(rayPixels(with, without, f), 200) << "frame " << f;
}

TEST(VideoRecording, ARecordedPathDrivesTheCameraAndTheEditsWithHeldKeys)
{
    const fs::path folder = test::freshFolder("record-path");
    const auto [source, receiver] = test::floorPatches();
    const Camera a = shaftView(source, receiver);
    Camera b = a;
    b.yaw += 0.6;
    RecordedPath path;
    path.fps = 10.0;
    path.frames = 12;
    path.camera = {{0, toPathCamera(a)}, {6, toPathCamera(b)}};
    PathEdit start;
    start.object = PathEdit::Object::Receiver;
    start.patch = receiver;
    PathEdit raised = start;
    raised.frame = 6;
    raised.patch.corner.y += 1.5;
    path.edits = {start, raised};
    Project holder;
    setRecordedPath(holder, path);

    EditorDocument document;
    openFloorProject(document, folder, holder.extra);
    const RecordingScene scene = recordingScene(document, Camera{}, opaqueRays(true));
    ASSERT_EQ(scene.path.frames, 12);
    EXPECT_EQ(defaultRecordingFps(scene), 10.0);
    EXPECT_EQ(defaultRecordingFrames(scene, 10.0), 12);
    EXPECT_EQ(defaultRecordingFrames(scene, 20.0), 24);   // the same 1.2 s at twice the rate
    // Video frame 13 at 20 fps is 0.65 s: path frame 6, the second keys.
    const RecordingFrame at = recordingFrame(scene, 13, 20.0);
    EXPECT_EQ(at.project.receiver.corner, raised.patch.corner);
    EXPECT_EQ(at.camera.yaw, b.yaw);
    EXPECT_EQ(recordingFrame(scene, 11, 20.0).camera.yaw, a.yaw);

    RecordingOptions options;
    options.output = folder / "path.webm";
    options.width = kWidth;
    options.height = kHeight;
    options.fps = 10.0;
    options.frames = 12;
    const RecordingFigures figures = recordVideo(scene, options);
    EXPECT_EQ(figures.source, "recorded path");
    const DecodedVideo video = decodeVideo(options.output.string());
    EXPECT_EQ(video.codec, "vp9");
    ASSERT_EQ(video.frames.size(), 12u);
    auto meanDifference = [&](std::size_t f, std::size_t g) {
        double sum = 0;
        for (std::size_t i = 0; i < video.frames[f].size(); ++i)
            sum += std::abs(int(video.frames[f][i]) - int(video.frames[g][i]));
        return sum / double(video.frames[f].size());
    };
    // Held keys: frames within a key's span look alike; the cut between spans is large.
    EXPECT_LT(meanDifference(0, 5), 2.0);
    EXPECT_LT(meanDifference(6, 11), 2.0);
    EXPECT_GT(meanDifference(5, 6), 10.0);
}

TEST(VideoRecording, CancellingWritesNoFile)
{
    const fs::path folder = test::freshFolder("record-cancel");
    EditorDocument document;
    openFloorProject(document, folder, risingReceiver());
    RecordingOptions options;
    options.output = folder / "cancelled.mp4";
    options.width = 64;
    options.height = 48;
    options.frames = 10;
    const RecordingFigures figures =
        recordVideo(recordingScene(document, Camera{}, ViewStyle{}), options, [](int done, int) { return done < 3; });
    EXPECT_EQ(figures.frames, 3);
    EXPECT_FALSE(fs::exists(options.output));
    EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 2);   // floor.obj, floor.json
}

TEST(RecordCommand, RecordsTheDemoAnimationHeadless)
{
    fs::create_directories(test::uniqueFolder());
    const fs::path folder = test::freshFolder("record-cli");
    const fs::path project = test::copyDemoProject(folder);
    const fs::path out = folder / "demo.mp4";
    const test::CliRun run = test::runProgram(SIGHTLINE_EDITOR, "--record " + out.string() + " " + project.string() + " --size 128x72", 300);
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_NE(run.out.find("40 frames at 128x72, 30 fps (libx264, animation)"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("frames per second"), std::string::npos) << run.out;
    const DecodedVideo video = decodeVideo(out.string());
    EXPECT_EQ(video.frames.size(), 40u);   // the demo's animation
    EXPECT_EQ(video.width, 128);
    EXPECT_EQ(video.height, 72);

    const test::CliRun short_ = test::runProgram(SIGHTLINE_EDITOR, "--record " + (folder / "short.webm").string() + " " +
                                                                        project.string() + " --size 64x48 --frames 5 --fps 12", 300);
    ASSERT_EQ(short_.code, 0) << short_.err;
    const DecodedVideo webm = decodeVideo((folder / "short.webm").string());
    EXPECT_EQ(webm.frames.size(), 5u);
    EXPECT_NEAR(webm.fps, 12.0, 1e-9);
}

TEST(RecordCommand, BadArgumentsGiveOneLineErrorsAndNoFile)
{
    fs::create_directories(test::uniqueFolder());
    const fs::path folder = test::freshFolder("record-bad");
    const fs::path project = test::copyDemoProject(folder);
    const std::string p = project.string();
    const std::pair<std::string, std::string> cases[] = {
        {"--record " + (folder / "a.avi").string() + " " + p, "unknown extension '.avi'"},
        {"--record " + (folder / "a.mp4").string() + " " + p + " --size 321x240", "odd side"},
        {"--record " + (folder / "a.mp4").string() + " " + p + " --size 9000x720", "8192 pixels a side"},
        {"--record " + (folder / "a.mp4").string() + " " + p + " --size 8x8", "too small"},
        {"--record " + (folder / "a.mp4").string() + " " + p + " --fps 0", "--fps"},
        {"--record " + (folder / "a.mp4").string() + " " + p + " --frames 0", "--frames"},
        {"--record " + (folder / "no" / "a.mp4").string() + " " + p, "does not exist"},
        {"--record /proc/a.mp4 " + p, "cannot write in '/proc'"},
        {"--record " + (folder / "a.mp4").string() + " " + (folder / "missing.json").string(), "missing.json"},
        {"--record " + (folder / "a.mp4").string(), "need a project file"},
    };
    for (const auto& [arguments, says] : cases) {
        const test::CliRun run = test::runProgram(SIGHTLINE_EDITOR, arguments, 120);
        EXPECT_NE(run.code, 0) << arguments;
        EXPECT_NE(run.err.find(says), std::string::npos) << arguments << ": " << run.err;
        EXPECT_TRUE(test::oneLine(run.err)) << arguments << ": " << run.err;
    }
    // A malformed recorded path in the project: named, in one line.
    json document = json::parse(std::ifstream(project));
    document[kRecordedPathKey] = {{"fps", 30}, {"frames", 10}, {"camera", json::array({{{"frame", 12}}})}};
    std::ofstream(folder / "bad-path.json") << document.dump();
    const test::CliRun bad = test::runProgram(SIGHTLINE_EDITOR, "--record " + (folder / "a.mp4").string() + " " +
                                                                    (folder / "bad-path.json").string(), 120);
    EXPECT_NE(bad.code, 0);
    EXPECT_NE(bad.err.find("'recorded_path.camera[0].frame' must be in [0, frames)"), std::string::npos) << bad.err;
    EXPECT_TRUE(test::oneLine(bad.err)) << bad.err;
    fs::remove(folder / "bad-path.json");

    EXPECT_FALSE(fs::exists(folder / "a.mp4"));
    EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 2);   // demo.json, demo_level.glb
}

TEST(RecordCommand, BadNamesSizesAndPathsAreRefusedBeforeAnyWindow)
{
    fs::create_directories(test::uniqueFolder());
    const fs::path folder = test::freshFolder("record-bad-path");
    const fs::path project = test::copyDemoProject(folder);
    const std::string p = project.string(), out = (folder / "a.mp4").string();
    // The offscreen platform: a window, were one created, would not crash the test's run.
    const std::string editor = std::string("env QT_QPA_PLATFORM=offscreen ") + SIGHTLINE_EDITOR;
    const json original = json::parse(std::ifstream(project));
    auto withPath = [&](const std::string& name, const json& path) {
        json document = original;
        document[kRecordedPathKey] = path;
        std::ofstream(folder / name) << document.dump();
        return (folder / name).string();
    };
    const json receiver = original.at("receiver");
    json crossing = receiver;
    crossing["corner"] = original.at("source").at("corner");   // on the source's plane
    json far = receiver;
    far["corner"] = {2e6, 0, 0};   // beyond kMaxCoordinateMetres
    json flat = receiver;
    flat["u"] = {0, 0, 0};
    json projective = json::array();
    for (int i = 0; i < 16; ++i)
        projective.push_back(i % 5 == 0 ? 1.0 : i == 3 ? 0.5 : 0.0);
    auto edit = [&](const json& patch) {
        return json{{"fps", 30}, {"frames", 10},
                    {"edits", {{{"frame", 0}, {"object", "receiver"}, {"corner", receiver.at("corner")}, {"u", receiver.at("u")},
                                {"v", receiver.at("v")}},
                               {{"frame", 4}, {"object", "receiver"}, {"corner", patch.at("corner")}, {"u", patch.at("u")},
                                {"v", patch.at("v")}}}}};
    };
    const std::string crossingFile = withPath("crossing.json", edit(crossing));
    const std::string farFile = withPath("far.json", edit(far));
    const std::string flatFile = withPath("flat.json", edit(flat));
    const std::string projectiveFile = withPath(
        "projective.json", {{"fps", 30}, {"frames", 10},
                            {"edits", {{{"frame", 2}, {"object", "occluder"}, {"index", 0}, {"name", "x"}, {"transform", projective}}}}});
    const std::string slowFile = withPath("slow.json", {{"fps", 0.001}, {"frames", 1000000}});
    const std::pair<std::string, std::string> cases[] = {
        {"--record \"\" " + p, "--record needs an output file name"},
        {"--screenshot \"\" " + p, "--screenshot needs an output file name"},
        {"--record " + p + " " + p, "the opened file"},
        {"--record " + out + " " + p + " --size 4294967312x16", "--size must be WxH"},
        {"--record " + out + " " + p + " --size 16x99999999999999999999", "--size must be WxH"},
        {"--record " + out + " " + crossingFile, "frame 4: "},
        {"--record " + out + " " + farFile, "frame 4: "},
        {"--record " + out + " " + flatFile, "frame 4: "},
        {"--record " + out + " " + projectiveFile, "'recorded_path.edits[0].transform' must be affine"},
        {"--record " + out + " " + slowFile + " --fps 240", "at most 1000000 are recorded"},
        {"--background-load 2 " + p, "--background-load applies to --benchmark-interaction and --benchmark-stalls"},
        {"--benchmark-stalls --background-load 999 " + p, "--background-load"},
    };
    for (const auto& [arguments, says] : cases) {
        const test::CliRun run = test::runProgram(editor, arguments, 120);
        EXPECT_TRUE(run.code == 1 || run.code == 2) << arguments << ": " << run.code << " " << run.err;
        EXPECT_NE(run.err.find(says), std::string::npos) << arguments << ": " << run.err;
        EXPECT_TRUE(test::oneLine(run.err)) << arguments << ": " << run.err;
    }
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(json::parse(std::ifstream(project)), original);   // the opened file is untouched
}

} // namespace
} // namespace sightline::ui

// A path recorded in an orthographic view (7 / 1 / 3, or 5) plays back orthographic: the flag goes
// into the path's camera keys and back out, and a key differing only in it is a new key.
namespace sightline::ui {
TEST(VideoRecording, TheOrthographicFlagRoundTripsThroughAPathCamera)
{
    Camera camera;
    camera.target = {1.0, 2.0, 3.0};
    camera.orthographic = true;
    const PathCamera key = toPathCamera(camera);
    EXPECT_TRUE(key.orthographic);
    EXPECT_TRUE(toCamera(key).orthographic);
    Camera perspective = camera;
    perspective.orthographic = false;
    EXPECT_FALSE(toCamera(toPathCamera(perspective)).orthographic);
    EXPECT_NE(toPathCamera(perspective), key);
}
} // namespace sightline::ui
