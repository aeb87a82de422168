// Importance maps over time and soft shadows as the project and the CLI see them: animation
// tracks, accumulation of alternating configurations, light textures and height maps from files,
// and the `importance` / `shadow` subcommands' images and .npy files.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <QImage>

#include "CliRunner.h"
#include "project/Animation.h"
#include "project/ImportanceRun.h"
#include "project/LightingSetup.h"
#include "project/ProjectMotion.h"
#include "project/ProjectSampler.h"
#include "project/RecordedPath.h"
#include "report/MapImage.h"
#include "base/ColourMap.h"
#include "base/Error.h"
#include "base/NpyFile.h"
#include "visibility/RayCastSampler.h"

using namespace sightline;
using namespace sightline::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

/// A 2 m wall with a 1 m hole between the patches, and a "door" box that an animation moves into
/// the hole on odd frames and out of the way on even ones (step keys, looping every 2 frames).
class ImportanceProject : public ::testing::Test {
protected:
    fs::path folder;
    json document;

    void SetUp() override
    {
        folder = uniqueFolder();
        fs::remove_all(folder);
        fs::create_directories(folder);
        test::writeWallWithHoleObj(folder / "wall.obj");
        document = {
            {"version", 1},
            {"scene", "wall.obj"},
            {"source", {{"corner", {0, 0, 0}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}, {"samples", {16, 8}}}},
            {"receiver", {{"corner", {-0.5, -0.2, 4}}, {"u", {2, 0, 0}}, {"v", {0, 1.4, 0}}, {"samples", {24, 20}}}},
            {"occluders", {{{"name", "door"}, {"mesh", "box"},
                            {"transform", {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.2, 0, 0.25, 0.25, 2.2, 1}}}}},
            {"animation",
             {{"frames", 4},
              {"tracks", {{{"target", "occluder"}, {"name", "door"}, {"interpolation", "step"}, {"loop", true},
                           {"keys", {{{"frame", 0}, {"translate", {0, 5, 0}}}, {{"frame", 1}, {"translate", {0, 0, 0}}}}}}}}}},
        };
        save();
    }
    void TearDown() override { fs::remove_all(folder); }

    void save() const { std::ofstream(folder / "p.json") << document.dump(2); }
    fs::path projectFile() const { return folder / "p.json"; }

    /// A recorded path over 7 frames at 10 fps: the door out of the way (frames 0-2), in the hole
    /// (3-4), then the receiver slid 0.3 m sideways (5-6), with camera keys that sampling ignores.
    /// Edits in frame order: door and receiver at 0, door at 3, receiver at 5.
    static RecordedPath doorPath(const Project& project)
    {
        RecordedPath path;
        path.fps = 10.0;
        path.frames = 7;
        path.camera = {{0, PathCamera{}}, {2, PathCamera{.distance = 7.0}}, {6, PathCamera{.yaw = 0.5}}};
        glm::mat4 open = project.occluders[0].transform, shut = open;
        open[3][1] += 5.0f;
        PathEdit door;
        door.object = PathEdit::Object::Occluder;
        door.name = "door";
        door.transform = open;
        path.edits.push_back(door);
        door.frame = 3;
        door.transform = shut;
        path.edits.push_back(door);
        PathEdit slide;   // as the recorder writes it: the starting state at frame 0, then the move
        slide.object = PathEdit::Object::Receiver;
        slide.patch = project.receiver;
        path.edits.insert(path.edits.begin() + 1, slide);
        slide.frame = 5;
        slide.patch.corner.x += 0.3;
        path.edits.push_back(slide);
        return path;
    }

    /// The reference importance of one animation frame (Embree).
    ImportanceMap referenceAt(int frame, ImportanceSide side = ImportanceSide::Receiver) const
    {
        const Project project = loadProject(projectFile());
        const Project moved = projectAtFrame(project, parseAnimation(project, "p.json"), frame);
        return importanceOf(RayCastScene(buildScene(moved)).sample(moved.source, moved.receiver), moved, side);
    }
};

QRgb viridisQRgb(float t)
{
    const Rgb8 c = viridis8(t);
    return qRgb(c.r, c.g, c.b);
}

} // namespace

TEST(Animation, TracksInterpolateStepAndLoop)
{
    AnimationTrack track;
    track.keys = {{0, {0, 0, 0}}, {10, {1, 0, 0}}, {20, {1, 2, 0}}};
    EXPECT_EQ(track.offsetAt(0), glm::dvec3(0, 0, 0));
    EXPECT_EQ(track.offsetAt(5), glm::dvec3(0.5, 0, 0));
    EXPECT_EQ(track.offsetAt(15), glm::dvec3(1, 1, 0));
    EXPECT_EQ(track.offsetAt(40), glm::dvec3(1, 2, 0));   // holds the last key
    track.step = true;
    EXPECT_EQ(track.offsetAt(15), glm::dvec3(1, 0, 0));
    track.loop = true;                                      // period 21
    EXPECT_EQ(track.offsetAt(21 + 15), glm::dvec3(1, 0, 0));
    EXPECT_EQ(track.offsetAt(21), glm::dvec3(0, 0, 0));
}

TEST(Animation, DefaultFrameCountIsFramesElseTheLastKeyElseOne)
{
    Animation animation;
    EXPECT_EQ(defaultFrameCount(animation), 1);   // nothing moves
    AnimationTrack walk, door;
    walk.target = AnimationTrack::Target::Receiver;
    walk.keys = {{0, {0, 0, 0}}, {20, {0, 0, -1.5}}, {39, {0, 0, 0}}};
    door.loop = true;
    door.keys = {{0, {0, 0, 0}}, {5, {0, 1, 0}}};
    animation.tracks = {door, walk};
    EXPECT_EQ(defaultFrameCount(animation), 40);   // the longest track, frames 0 .. 39
    animation.tracks = {door};
    EXPECT_EQ(defaultFrameCount(animation), 6);
    animation.frames = 3;                            // given: wins over the keys
    EXPECT_EQ(defaultFrameCount(animation), 3);
}

TEST_F(ImportanceProject, AnimationIsReadAndMovesTheNamedOccluder)
{
    const Project project = loadProject(projectFile());
    const Animation animation = parseAnimation(project, "p.json");
    ASSERT_EQ(animation.tracks.size(), 1u);
    EXPECT_EQ(animation.frames, 4);
    EXPECT_TRUE(animation.movesOccluders());
    EXPECT_FLOAT_EQ(projectAtFrame(project, animation, 0).occluders[0].transform[3][1], 5.25f);
    EXPECT_FLOAT_EQ(projectAtFrame(project, animation, 1).occluders[0].transform[3][1], 0.25f);
    EXPECT_FLOAT_EQ(projectAtFrame(project, animation, 2).occluders[0].transform[3][1], 5.25f);
    // The key survives a save (an extra key of the document).
    EXPECT_EQ(toJson(project)["animation"], document["animation"]);

    const auto failsWith = [&](json tracks, const std::string& needle) {
        Project broken = project;
        broken.extra["animation"]["tracks"] = std::move(tracks);
        try {
            parseAnimation(broken, "p.json");
            ADD_FAILURE() << "no error for " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    failsWith({{{"target", "lamp"}, {"keys", {{{"frame", 0}, {"translate", {0, 0, 0}}}}}}}, "target");
    failsWith({{{"target", "occluder"}, {"name", "gate"}, {"keys", {{{"frame", 0}, {"translate", {0, 0, 0}}}}}}}, "'gate'");
    failsWith({{{"target", "source"}, {"keys", {{{"frame", 3}, {"translate", {0, 0, 0}}}, {{"frame", 3}, {"translate", {1, 0, 0}}}}}}},
              "keys[1].frame");
    failsWith({{{"target", "source"}, {"keys", json::array()}}}, "keys");
    failsWith({{{"target", "receiver"}, {"keys", {{{"frame", 0}, {"translate", {0, "up", 0}}}}}}}, "translate");
}

TEST_F(ImportanceProject, AccumulatingTwoAlternatingConfigurationsGivesTheirAverage)
{
    const Project project = loadProject(projectFile());
    const Animation animation = parseAnimation(project, "p.json");
    const ImportanceMap open = referenceAt(0), closed = referenceAt(1);
    ASSERT_GT(open.mean(), closed.mean() + 0.05);   // the door really changes what is seen

    for (const ImportanceSide side : {ImportanceSide::Receiver, ImportanceSide::Source}) {
        const ImportanceMap a = referenceAt(0, side), b = referenceAt(1, side);
        ProjectSampler sampler(project, loadProjectMeshes(project), SamplerSettings{});
        int calls = 0;
        const ImportanceRunResult run =
            accumulateImportance(sampler, project, animation, 4, side, [&](int done, int total) {
                EXPECT_EQ(done, ++calls);
                EXPECT_EQ(total, 4);
                return true;
            });
        ASSERT_EQ(run.framesDone, 4);
        const ImportanceMap mean = run.accumulator.result(ImportanceStatistic::Mean);
        const ImportanceMap maximum = run.accumulator.result(ImportanceStatistic::Maximum);
        const ImportanceMap ever = run.accumulator.result(ImportanceStatistic::EverVisible);
        ASSERT_TRUE(mean.sameGrid(a));
        for (std::size_t k = 0; k < a.values.size(); ++k) {
            ASSERT_NEAR(mean.values[k], 0.5f * (a.values[k] + b.values[k]), 1e-6f) << k;
            ASSERT_EQ(maximum.values[k], std::max(a.values[k], b.values[k])) << k;
            ASSERT_EQ(ever.values[k], std::max(a.values[k], b.values[k]) > 0.0f ? 1.0f : 0.0f) << k;
        }
    }
    // Cancelling after the first frame keeps what was done.
    ProjectSampler sampler(project, loadProjectMeshes(project), SamplerSettings{});
    const ImportanceRunResult stopped =
        accumulateImportance(sampler, project, animation, 4, ImportanceSide::Receiver, [](int, int) { return false; });
    EXPECT_EQ(stopped.framesDone, 1);
    EXPECT_TRUE(stopped.cancelled);
}

TEST_F(ImportanceProject, TheGlSamplerWithoutAContextFactoryIsRefusedInOneLine)
{
    const Project project = loadProject(projectFile());
    SamplerSettings settings;
    settings.method = "gl";
    try {
        ProjectSampler sampler(project, loadProjectMeshes(project), settings);
        FAIL() << "a GL sampler without a context was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("OpenGL context"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
}

TEST_F(ImportanceProject, ImportanceOverARecordedPathEqualsTheSameFramesAccumulatedByHand)
{
    Project project = loadProject(projectFile());
    setRecordedPath(project, doorPath(project));
    const ProjectMotion motion = parseProjectMotion(project, ProjectMotion::Kind::RecordedPath, "p.json");
    ASSERT_EQ(motion.defaultFrames(), 7);
    // Only frames with an edit key can differ from the frame before.
    for (int f = 0; f < 9; ++f)
        EXPECT_EQ(motion.mayChangeAt(f), f == 0 || f == 3 || f == 5) << f;

    for (const ImportanceSide side : {ImportanceSide::Receiver, ImportanceSide::Source}) {
        // By hand: every frame of the path sampled and added.
        ProjectSampler handSampler(project, loadProjectMeshes(project), SamplerSettings{});
        const RecordedPath path = parseRecordedPath(project, "p.json");
        ImportanceAccumulator byHand;
        for (int f = 0; f < 9; ++f) {   // two frames past the end hold the last one
            const Project frame = projectAtPathFrame(project, path, f);
            byHand.add(importanceOf(handSampler.sample(frame), frame, side));
        }
        ProjectSampler sampler(project, loadProjectMeshes(project), SamplerSettings{});
        const ImportanceRunResult run = accumulateImportance(sampler, project, motion, 9, side);
        ASSERT_EQ(run.framesDone, 9);
        EXPECT_EQ(run.framesSampled, 3);   // frames 0, 3 and 5; the others repeat the frame before
        for (const ImportanceStatistic statistic :
             {ImportanceStatistic::Mean, ImportanceStatistic::Maximum, ImportanceStatistic::EverVisible}) {
            const ImportanceMap expected = byHand.result(statistic), got = run.accumulator.result(statistic);
            ASSERT_TRUE(got.sameGrid(expected));
            for (std::size_t k = 0; k < expected.values.size(); ++k)
                ASSERT_EQ(got.values[k], expected.values[k]) << k;
        }
    }
    // The path's frames really differ: the door shuts the hole, the receiver slides.
    const RecordedPath path = doorPath(project);
    ProjectSampler sampler(project, loadProjectMeshes(project), SamplerSettings{});
    const auto at = [&](int f) { return receiverImportance(sampler.sample(projectAtPathFrame(project, path, f))); };
    const ImportanceMap open = at(0), shut = at(3), slid = at(5);
    EXPECT_GT(open.mean(), shut.mean() + 0.05);
    std::size_t moved = 0;
    for (std::size_t k = 0; k < shut.values.size(); ++k)
        moved += slid.values[k] != shut.values[k];
    EXPECT_GT(moved, shut.values.size() / 10);
}

TEST_F(ImportanceProject, CliImportanceOverTheRecordedPath)
{
    const fs::path png = folder / "map.png", npy = folder / "map.npy";
    // No path yet: refused in one line, naming the key.
    const CliRun none = runCli("importance " + projectFile().string() + " --path --out " + png.string());
    EXPECT_NE(none.code, 0);
    EXPECT_NE(none.err.find("recorded_path"), std::string::npos) << none.err;

    Project project = loadProject(projectFile());
    const RecordedPath path = doorPath(project);
    document["recorded_path"] = toJson(path);
    save();
    const CliRun run = runCli("importance " + projectFile().string() + " --path --json --out " + png.string() +
                              " --npy " + npy.string());
    ASSERT_EQ(run.code, 0) << run.err;
    const json out = json::parse(run.out);
    EXPECT_EQ(out["frames"], 7);   // the path's length
    EXPECT_EQ(out["frames_sampled"], 3);
    EXPECT_EQ(out["motion"], "recorded path");
    // The mean over the path's 7 frames, each sampled by hand with the CLI's sampler.
    ProjectSampler sampler(project, loadProjectMeshes(project), SamplerSettings{});
    ImportanceAccumulator byHand;
    for (int f = 0; f < 7; ++f)
        byHand.add(receiverImportance(sampler.sample(projectAtPathFrame(project, path, f))));
    const ImportanceMap expected = byHand.result(ImportanceStatistic::Mean);
    const FloatArray values = readFloatNpy(npy);
    ASSERT_EQ(values.values.size(), expected.values.size());
    for (std::size_t k = 0; k < expected.values.size(); ++k)
        ASSERT_EQ(values.values[k], expected.values[k]) << k;
    // Without --path the same project accumulates its animation (4 frames).
    const CliRun animated = runCli("importance " + projectFile().string() + " --json --out " + png.string());
    ASSERT_EQ(animated.code, 0) << animated.err;
    EXPECT_EQ(json::parse(animated.out)["frames"], 4);
    EXPECT_EQ(json::parse(animated.out)["motion"], "animation");
}

TEST_F(ImportanceProject, LightTextureAndHeightMapsComeFromFiles)
{
    // A light texture: left half red, right half blue (16 x 8 source samples).
    QImage texture(4, 2, QImage::Format_RGB32);
    for (int x = 0; x < 4; ++x)
        for (int y = 0; y < 2; ++y)
            texture.setPixel(x, y, x < 2 ? qRgb(255, 0, 0) : qRgb(0, 0, 255));
    ASSERT_TRUE(texture.save(QString::fromStdString((folder / "neon.png").string())));
    document["light"] = {{"texture", "neon.png"}};
    // Heights as float32 (nb, na) = (20, 24): column a raised a millimetres.
    std::vector<float> metres(24 * 20);
    for (std::size_t j = 0; j < metres.size(); ++j)
        metres[j] = float(j % 24) * 0.001f;
    writeFloatNpy(metres, 20, 24, folder / "h.npy");
    document["receiver_heights"] = {{"npy", "h.npy"}};
    save();
    Project project = loadProject(projectFile());
    const AreaLight light = projectLight(project, project.source, "p.json");
    ASSERT_EQ(light.groups.size(), 2u);
    EXPECT_EQ(light.groups[0].count, 64);
    EXPECT_EQ(light.unoccluded(), glm::vec3(0.5f, 0.0f, 0.5f));
    const ReceiverHeights heights = projectReceiverHeights(project, project.receiver, "p.json");
    ASSERT_EQ(heights.metres.size(), 480u);
    EXPECT_NEAR(heights.metres[23], 0.023, 1e-7);

    // A grey image as heights: white is `metres`.
    QImage grey(2, 2, QImage::Format_RGB32);
    grey.fill(qRgb(255, 255, 255));
    ASSERT_TRUE(grey.save(QString::fromStdString((folder / "bumps.png").string())));
    project.extra["receiver_heights"] = {{"image", "bumps.png"}, {"metres", 0.25}};
    for (double h : projectReceiverHeights(project, project.receiver, "p.json").metres)
        ASSERT_DOUBLE_EQ(h, 0.25);

    // Errors name the key or the file.
    project.receiver.na = 12;
    project.extra["receiver_heights"] = {{"npy", "h.npy"}};
    EXPECT_THROW(projectReceiverHeights(project, project.receiver, "p.json"), Error);
    project.extra["receiver_heights"] = {{"image", "missing.png"}, {"metres", 1}};
    EXPECT_THROW(projectReceiverHeights(project, project.receiver, "p.json"), Error);
    project.extra["light"] = {{"texture", "wall.obj"}};   // not an image
    EXPECT_THROW(projectLight(project, project.source, "p.json"), Error);
}

TEST_F(ImportanceProject, CliImportanceWritesTheMapWithItsLegendAndTheRawValues)
{
    const fs::path png = folder / "map.png", npy = folder / "map.npy";
    const CliRun run = runCli("importance " + projectFile().string() + " --out " + png.string() + " --npy " + npy.string() +
                              " --json --method raycast");
    ASSERT_EQ(run.code, 0) << run.err;
    const json out = json::parse(run.out);
    EXPECT_EQ(out["frames"], 4);   // the animation's frame count
    EXPECT_EQ(out["samples"], json::array({24, 20}));

    const FloatArray values = readFloatNpy(npy);
    ASSERT_EQ(values.rows, 20);
    ASSERT_EQ(values.columns, 24);
    const ImportanceMap a = referenceAt(0), b = referenceAt(1);
    for (std::size_t k = 0; k < values.values.size(); ++k) {
        ASSERT_GE(values.values[k], 0.0f);
        ASSERT_LE(values.values[k], 1.0f);
        ASSERT_NEAR(values.values[k], 0.5f * (a.values[k] + b.values[k]), 1e-6f) << k;
    }

    const QImage image(QString::fromStdString(png.string()));
    const MapImageLayout layout = mapImageLayout(24, 20);
    ASSERT_EQ(image.size(), layout.size);
    // The legend: yellow (1) at the top of the bar, dark violet (0) at its bottom.
    const QPoint top(layout.legendBar.center().x(), layout.legendBar.top());
    const QPoint bottom(layout.legendBar.center().x(), layout.legendBar.bottom());
    EXPECT_EQ(image.pixel(top), viridisQRgb(1.0f));
    EXPECT_EQ(image.pixel(bottom), viridisQRgb(0.0f));
    // Tick labels are drawn right of the bar (dark text on white).
    int ink = 0;
    for (int x = layout.legendBar.right() + 8; x < layout.legendBar.right() + 40; ++x)
        for (int y = layout.legendBar.top(); y < layout.legendBar.top() + 8; ++y)
            ink += qGray(image.pixel(x, y)) < 128;
    EXPECT_GT(ink, 3);
    // Each sample's square has its value's colour; b = 0 is the bottom row.
    for (int b2 = 0; b2 < 20; b2 += 3) {
        for (int a2 = 0; a2 < 24; a2 += 5) {
            const QPoint centre(layout.map.left() + a2 * layout.scale + layout.scale / 2,
                                layout.map.top() + (19 - b2) * layout.scale + layout.scale / 2);
            ASSERT_EQ(image.pixel(centre), viridisQRgb(values.values[std::size_t(b2 * 24 + a2)])) << a2 << "," << b2;
        }
    }

    // Over the source: shape (nb, na) of the source grid; maximum over one frame.
    const CliRun source = runCli("importance " + projectFile().string() + " --of source --stat max --frames 1 --out " +
                                 png.string() + " --npy " + npy.string() + " --source-samples 8x4");
    ASSERT_EQ(source.code, 0) << source.err;
    const FloatArray sourceValues = readFloatNpy(npy);
    EXPECT_EQ(sourceValues.rows, 4);
    EXPECT_EQ(sourceValues.columns, 8);
}

TEST_F(ImportanceProject, CliImportanceWithoutFramesRunsToTheLastKey)
{
    // No "frames": the door stays out of the way for frames 0..38 and steps into the hole at 39.
    document["animation"] = {{"tracks", {{{"target", "occluder"}, {"name", "door"}, {"interpolation", "step"},
                                          {"keys", {{{"frame", 0}, {"translate", {0, 5, 0}}},
                                                    {{"frame", 39}, {"translate", {0, 0, 0}}}}}}}}};
    save();
    const fs::path png = folder / "map.png", npy = folder / "map.npy";
    const CliRun run = runCli("importance " + projectFile().string() + " --method raycast --json --out " + png.string() +
                              " --npy " + npy.string());
    ASSERT_EQ(run.code, 0) << run.err;
    EXPECT_EQ(json::parse(run.out)["frames"], 40);
    const FloatArray values = readFloatNpy(npy);
    const ImportanceMap open = referenceAt(0), shut = referenceAt(39);
    ASSERT_EQ(values.values.size(), open.values.size());
    double differs = 0.0;
    for (std::size_t k = 0; k < values.values.size(); ++k) {
        ASSERT_NEAR(values.values[k], (39.0f * open.values[k] + shut.values[k]) / 40.0f, 1e-6f) << k;
        differs += std::abs(open.values[k] - shut.values[k]);
    }
    EXPECT_GT(differs, 1.0);   // the door's one frame shows in the mean
}

TEST_F(ImportanceProject, CliShadowWritesTheLightOnTheReceiver)
{
    const fs::path png = folder / "shadow.png", npy = folder / "light.npy";
    const CliRun run = runCli("shadow " + projectFile().string() + " --out " + png.string() + " --npy " + npy.string() +
                              " --scale 3 --json");
    ASSERT_EQ(run.code, 0) << run.err;
    const json out = json::parse(run.out);
    const FloatArray light = readFloatNpy(npy);
    ASSERT_EQ(light.rows, 20);
    ASSERT_EQ(light.columns, 24);
    // Frame 0's configuration is the project as saved (no animation applied by `shadow`).
    Project project = loadProject(projectFile());
    const ImportanceMap expected = receiverImportance(RayCastScene(buildScene(project)).sample(project.source, project.receiver));
    for (std::size_t k = 0; k < light.values.size(); ++k)
        ASSERT_NEAR(light.values[k], expected.values[k], 1e-6f) << k;
    EXPECT_NEAR(out["mean_light"].get<double>(), expected.mean(), 1e-6);

    const QImage image(QString::fromStdString(png.string()));
    ASSERT_EQ(image.size(), QSize(72, 60));
    // Pixel (x, y) shows sample (x / 3, 19 - y / 3) as grey light.
    for (int y = 1; y < 60; y += 7) {
        for (int x = 1; x < 72; x += 5) {
            const float value = light.values[std::size_t((19 - y / 3) * 24 + x / 3)];
            ASSERT_NEAR(qGray(image.pixel(x, y)), value * 255.0f, 1.0f) << x << "," << y;
        }
    }

    // Bad input: one line on stderr, non-zero exit.
    for (const std::string& arguments :
         {"shadow " + projectFile().string() + " --out " + png.string() + " --receiver-samples 0x3",
          "shadow " + projectFile().string() + " --out " + png.string() + " --method hh --jitter 3",
          "importance " + projectFile().string() + " --out " + png.string() + " --source-samples 64x32",
          "importance " + (folder / "none.json").string() + " --out " + png.string()}) {
        const CliRun bad = runCli(arguments);
        EXPECT_NE(bad.code, 0) << arguments;
        EXPECT_TRUE(oneLine(bad.err)) << arguments << ": " << bad.err;
    }
}

TEST_F(ImportanceProject, CliImportanceAndShadowThroughTheGlSampler)
{
    // The animation moves an occluder, so the GL sampler is rebuilt per frame; its accumulated
    // map must match the reference's (grazing rays aside: within two source samples of 128).
    const fs::path png = folder / "gl.png", npy = folder / "gl.npy";
    const CliRun run = runCli("importance " + projectFile().string() + " --method gl --out " + png.string() +
                              " --npy " + npy.string());
    if (run.code != 0 && run.err.find("OSMesa") != std::string::npos)
        GTEST_SKIP() << "no OpenGL context: " << run.err;
    ASSERT_EQ(run.code, 0) << run.err;
    const FloatArray values = readFloatNpy(npy);
    const ImportanceMap a = referenceAt(0), b = referenceAt(1);
    ASSERT_EQ(values.values.size(), a.values.size());
    double sum = 0.0;
    for (std::size_t k = 0; k < values.values.size(); ++k) {
        const double expected = 0.5 * (a.values[k] + b.values[k]);
        EXPECT_NEAR(values.values[k], expected, 2.0 / 128.0) << k;
        sum += std::abs(values.values[k] - expected);
    }
    EXPECT_LE(sum / double(values.values.size()), 1.0 / 1024.0);

    const CliRun shadow = runCli("shadow " + projectFile().string() + " --method gl --out " + png.string() + " --json");
    ASSERT_EQ(shadow.code, 0) << shadow.err;
    // `shadow` samples the project as saved: the door in the hole, which is frame 1's place.
    EXPECT_NEAR(json::parse(shadow.out)["mean_light"].get<double>(), b.mean(), 1.0 / 1024.0);

    // Heights need cpu or raycast: one clear line.
    std::vector<float> metres(24 * 20, 0.01f);
    writeFloatNpy(metres, 20, 24, folder / "h.npy");
    document["receiver_heights"] = {{"npy", "h.npy"}};
    save();
    const CliRun bumpy = runCli("importance " + projectFile().string() + " --method gl --out " + png.string());
    EXPECT_NE(bumpy.code, 0);
    EXPECT_TRUE(oneLine(bumpy.err)) << bumpy.err;
    EXPECT_NE(bumpy.err.find("heights"), std::string::npos) << bumpy.err;
}
