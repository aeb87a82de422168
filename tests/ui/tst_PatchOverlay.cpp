// The patch overlay (importance and light on a patch, Eisemann & Décoret §8-9) without a window:
// its colours, read-outs and accumulation on hand-made maps, the sample under a cursor ray, the
// animation run on a document, and headless screenshots whose pixels on the patch must be the
// overlay's colours of the expected values.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include <QImage>

#include <glm/gtc/matrix_transform.hpp>

#include "AnimationImportance.h"
#include "EditorDocument.h"
#include "editor/LiveVisibility.h"
#include "OffscreenRender.h"
#include "PatchOverlay.h"
#include "editor/Picking.h"
#include "UiTestScene.h"
#include "project/Project.h"
#include "base/ColourMap.h"
#include "base/Error.h"

namespace sightline::ui {
namespace {

using test::floorPatches;
using test::freshFolder;
using test::writeFloorObj;

/// A project with a 4x2 source (S = 8) and a 2x2 receiver: the grids of the hand-made maps.
Project smallProject()
{
    Project project;
    project.source.na = 4;
    project.source.nb = 2;
    project.receiver.na = project.receiver.nb = 2;
    return project;
}

/// Receiver 0 misses sources {0, 1}, receiver 1 source {0}, receiver 2 nothing, receiver 3 all.
VisibilityResult mapA()
{
    VisibilityResult r;
    r.valid = true;
    r.map = HiddenSampleMap(8, 2, 2);
    r.map.setBlocked(0, 0);
    r.map.setBlocked(0, 1);
    r.map.setBlocked(1, 0);
    for (int i = 0; i < 8; ++i)
        r.map.setBlocked(3, i);
    return r;
}

/// Only receiver 3 is blind.
VisibilityResult mapB()
{
    VisibilityResult r;
    r.valid = true;
    r.map = HiddenSampleMap(8, 2, 2);
    for (int i = 0; i < 8; ++i)
        r.map.setBlocked(3, i);
    return r;
}

std::uint32_t packed(Rgb8 c) { return std::uint32_t(c.r) << 24 | std::uint32_t(c.g) << 16 | std::uint32_t(c.b) << 8 | 0xffu; }

TEST(OverlayTexels, ImportanceIsViridisAndLightIsTheFraction)
{
    ImportanceMap map(2, 2);
    map.values = {0.0f, 0.25f, 0.5f, 1.0f};
    const OverlayTexels texels = importanceTexels(map);
    ASSERT_EQ(texels.rgba.size(), 16u);
    EXPECT_FALSE(texels.smooth);
    EXPECT_EQ(texels.rgbaAt(0, 0), packed(viridis8(0.0f)));
    EXPECT_EQ(texels.rgbaAt(1, 0), packed(viridis8(0.25f)));
    EXPECT_EQ(texels.rgbaAt(0, 1), packed(viridis8(0.5f)));   // index b * na + a
    EXPECT_EQ(texels.rgbaAt(1, 1), packed(viridis8(1.0f)));
    // Matplotlib's viridis ends, within the fit's few 1/255.
    auto near = [](std::uint32_t rgba, int r, int g, int b) {
        return std::abs(int(rgba >> 24) - r) <= 4 && std::abs(int((rgba >> 16) & 255) - g) <= 4 &&
               std::abs(int((rgba >> 8) & 255) - b) <= 4;
    };
    EXPECT_TRUE(near(texels.rgbaAt(0, 0), 68, 1, 84)) << "dark purple at 0";
    EXPECT_TRUE(near(texels.rgbaAt(1, 1), 253, 231, 37)) << "yellow at 1";

    LightImage light{2, 1, {glm::vec3(1.0f, 0.5f, 0.0f), glm::vec3(2.0f, -1.0f, 0.2f)}};
    const OverlayTexels lit = lightTexels(light);
    EXPECT_TRUE(lit.smooth);
    EXPECT_EQ(lit.rgbaAt(0, 0), 0xff8000ffu);
    EXPECT_EQ(lit.rgbaAt(1, 0), 0xff0033ffu) << "clamped to [0, 1]";
}

TEST(PatchOverlay, OffItDoesNothingWithALiveResult)
{
    PatchOverlay overlay;
    const Project project = smallProject();
    const std::uint64_t version = overlay.version();
    overlay.setLive(mapA(), project, true);
    EXPECT_EQ(overlay.version(), version) << "no recomputation while the overlay is off";
    EXPECT_TRUE(overlay.texels().empty());
    EXPECT_FALSE(overlay.needsLive());
    EXPECT_TRUE(overlay.readOut(0, 0).isEmpty());
    // Switched on, it asks for the current result again and then shows it.
    overlay.setKind(OverlayKind::ReceiverImportance);
    EXPECT_TRUE(overlay.needsLive());
    EXPECT_FALSE(overlay.importance());
    overlay.setLive(mapA(), project, false);
    EXPECT_FALSE(overlay.needsLive());
    ASSERT_TRUE(overlay.importance());
    EXPECT_NE(overlay.version(), version);
}

TEST(PatchOverlay, ImportanceOfAKnownMapAndItsReadOut)
{
    PatchOverlay overlay;
    const Project project = smallProject();
    overlay.setKind(OverlayKind::ReceiverImportance);
    overlay.setLive(mapA(), project, true);
    const ImportanceMap* receiver = overlay.importance();
    ASSERT_TRUE(receiver);
    EXPECT_EQ(receiver->values, (std::vector<float>{0.75f, 0.875f, 1.0f, 0.0f}));
    EXPECT_EQ(overlay.frames(), 1);
    EXPECT_EQ(overlay.texels().rgbaAt(1, 0), packed(viridis8(0.875f)));
    EXPECT_EQ(overlay.texels().rgbaAt(1, 1), packed(viridis8(0.0f)));
    EXPECT_EQ(overlay.readOut(1, 0), QString("receiver sample (1, 0): 87.5% of the source seen (this frame)"));
    EXPECT_EQ(overlay.legendCaption(), QString::fromUtf8("fraction of the source seen — this frame"));
    EXPECT_TRUE(overlay.readOut(2, 0).isEmpty()) << "outside the grid";

    overlay.setKind(OverlayKind::SourceImportance);
    overlay.setLive(mapA(), project, false);
    const ImportanceMap* source = overlay.importance();
    ASSERT_TRUE(source);
    ASSERT_EQ(source->na, 4);
    ASSERT_EQ(source->nb, 2);
    // Source 0 is missed by receivers 0, 1, 3; source 1 by 0 and 3; the others by 3 only.
    EXPECT_EQ(source->values, (std::vector<float>{0.25f, 0.5f, 0.75f, 0.75f, 0.75f, 0.75f, 0.75f, 0.75f}));
    EXPECT_EQ(overlay.readOut(1, 0), QString("source sample (1, 0): seen by 50.0% of the receiver (this frame)"));
    EXPECT_EQ(overlay.texels().rgbaAt(3, 1), packed(viridis8(0.75f)));
}

TEST(PatchOverlay, AccumulatingTwoAlternatingMapsGivesTheirMeanMaximumAndEverVisible)
{
    PatchOverlay overlay;
    const Project project = smallProject();
    overlay.setKind(OverlayKind::ReceiverImportance);
    overlay.setLive(mapA(), project, true);
    overlay.setAccumulating(true);
    EXPECT_TRUE(overlay.needsLive()) << "the accumulation starts with the current frame";
    overlay.setLive(mapA(), project, false);
    EXPECT_EQ(overlay.frames(), 1);
    overlay.setLive(mapB(), project, true);
    overlay.setLive(mapA(), project, true);
    overlay.setLive(mapB(), project, true);
    EXPECT_EQ(overlay.frames(), 4);
    EXPECT_EQ(overlay.importance()->values, (std::vector<float>{0.875f, 0.9375f, 1.0f, 0.0f}));
    EXPECT_EQ(overlay.readOut(0, 0), QString("receiver sample (0, 0): 87.5% of the source seen (mean of 4 frames)"));
    EXPECT_EQ(overlay.legendCaption(), QString::fromUtf8("fraction of the source seen — mean of 4 frames"));
    EXPECT_EQ(overlay.texels().rgbaAt(1, 0), packed(viridis8(0.9375f)));

    overlay.setStatistic(ImportanceStatistic::Maximum);
    EXPECT_EQ(overlay.importance()->values, (std::vector<float>{1.0f, 1.0f, 1.0f, 0.0f}));
    overlay.setStatistic(ImportanceStatistic::EverVisible);
    EXPECT_EQ(overlay.importance()->values, (std::vector<float>{1.0f, 1.0f, 1.0f, 0.0f}));
    EXPECT_EQ(overlay.readOut(1, 1), QString("receiver sample (1, 1): never saw the source in 4 frames"));
    EXPECT_EQ(overlay.readOut(0, 1), QString("receiver sample (0, 1): saw the source in at least one of 4 frames"));

    // The source side was accumulated over the same frames: (0.25 + 1) / 2 for source 0.
    overlay.setStatistic(ImportanceStatistic::Mean);
    overlay.setKind(OverlayKind::SourceImportance);
    EXPECT_EQ(overlay.frames(), 4);
    EXPECT_FLOAT_EQ(overlay.importance()->at(0, 0), 0.5f * (0.25f + 0.75f));
    EXPECT_FLOAT_EQ(overlay.importance()->at(3, 1), 0.75f);

    // Paused: the current frame; on again: the same accumulation goes on.
    overlay.setKind(OverlayKind::ReceiverImportance);
    overlay.setAccumulating(false);
    EXPECT_EQ(overlay.frames(), 1);
    EXPECT_EQ(overlay.importance()->values, (std::vector<float>{1.0f, 1.0f, 1.0f, 0.0f})) << "map B, the last frame";
    overlay.setAccumulating(true);
    EXPECT_FALSE(overlay.needsLive());
    EXPECT_EQ(overlay.frames(), 4);
}

TEST(PatchOverlay, AccumulationStartsAgainOnResetAndWhenAGridChanges)
{
    PatchOverlay overlay;
    Project project = smallProject();
    overlay.setKind(OverlayKind::ReceiverImportance);
    overlay.setAccumulating(true);
    for (int f = 0; f < 3; ++f)
        overlay.setLive(f % 2 ? mapB() : mapA(), project, true);
    EXPECT_EQ(overlay.frames(), 3);

    overlay.resetAccumulation();
    EXPECT_TRUE(overlay.needsLive()) << "starts again from the current frame";
    overlay.setLive(mapA(), project, false);
    EXPECT_EQ(overlay.frames(), 1);
    overlay.setLive(mapB(), project, true);
    EXPECT_EQ(overlay.frames(), 2);

    // The same 8 source samples as an 8 x 1 grid: another grid, a new accumulation.
    project.source.na = 8;
    project.source.nb = 1;
    overlay.setLive(mapA(), project, true);
    EXPECT_EQ(overlay.frames(), 1);
    EXPECT_EQ(overlay.importance()->values, (std::vector<float>{0.75f, 0.875f, 1.0f, 0.0f}));

    // A new document forgets everything.
    overlay.setLive(mapB(), project, true);
    EXPECT_EQ(overlay.frames(), 2);
    overlay.clear();
    EXPECT_FALSE(overlay.importance());
    overlay.setLive(mapB(), project, true);
    EXPECT_EQ(overlay.frames(), 1);
}

TEST(PatchOverlay, AnInvalidPairKeepsTheAccumulationButHasNoCurrentFrame)
{
    PatchOverlay overlay;
    const Project project = smallProject();
    overlay.setKind(OverlayKind::ReceiverImportance);
    overlay.setLive(mapA(), project, true);
    VisibilityResult invalid;
    invalid.error = "the receiver crosses the source's plane";
    overlay.setLive(invalid, project, true);
    EXPECT_FALSE(overlay.importance());
    EXPECT_TRUE(overlay.texels().empty());
    EXPECT_FALSE(overlay.needsLive());

    overlay.setAccumulating(true);
    overlay.setLive(mapA(), project, true);
    overlay.setLive(invalid, project, true);
    ASSERT_TRUE(overlay.importance());
    EXPECT_EQ(overlay.frames(), 1);
}

TEST(PatchOverlay, AnAnimationResultIsShownUntilDropped)
{
    PatchOverlay overlay;
    const Project project = smallProject();
    overlay.setKind(OverlayKind::ReceiverImportance);
    overlay.setLive(mapA(), project, true);
    ImportanceAccumulator run;
    for (int f = 0; f < 6; ++f)
        run.add(receiverImportance((f % 2 ? mapB() : mapA()).map));
    overlay.showAnimationResult(ImportanceSide::Receiver, run);
    EXPECT_EQ(overlay.frames(), 6);
    EXPECT_EQ(overlay.readOut(0, 0), QString("receiver sample (0, 0): 87.5% of the source seen (mean of 6 animation frames)"));
    overlay.setStatistic(ImportanceStatistic::Maximum);
    EXPECT_EQ(overlay.legendCaption(), QString::fromUtf8("fraction of the source seen — maximum of 6 animation frames"));
    // The other side shows its own live values; the result comes back with its side.
    overlay.setKind(OverlayKind::SourceImportance);
    overlay.setLive(mapA(), project, false);
    EXPECT_EQ(overlay.frames(), 1);
    overlay.setKind(OverlayKind::ReceiverImportance);
    EXPECT_EQ(overlay.frames(), 6);
    overlay.dropAnimationResult();
    EXPECT_EQ(overlay.frames(), 1);
}

TEST(PatchOverlay, LightOnTheReceiverIsTheSoftShadowAndABrokenLightSaysWhy)
{
    PatchOverlay overlay;
    Project project = smallProject();
    overlay.setKind(OverlayKind::LightOnReceiver);
    overlay.setLive(mapA(), project, true);
    const LightImage* light = overlay.light();
    ASSERT_TRUE(light) << overlay.error();
    EXPECT_FALSE(overlay.importance());
    EXPECT_TRUE(overlay.legendCaption().isEmpty()) << "no importance legend for the light";
    // A white light: the visible fraction on every channel (§8).
    EXPECT_EQ(light->rgb[1], glm::vec3(0.875f));
    EXPECT_EQ(overlay.readOut(1, 0), QString("receiver sample (1, 0): light R 87.5%, G 87.5%, B 87.5% of full"));
    EXPECT_TRUE(overlay.texels().smooth);
    EXPECT_EQ(overlay.texels().rgbaAt(1, 0), 0xdfdfdfffu);   // round(0.875 * 255) = 223

    // A neon sign: the left half of the source red, the right half dark (§8's coloured light).
    overlay.clear();   // a new document: the light is loaded again
    project.folder = freshFolder("overlay-light");
    QImage neon(2, 1, QImage::Format_RGB32);
    neon.setPixel(0, 0, qRgb(255, 0, 0));
    neon.setPixel(1, 0, qRgb(0, 0, 0));
    ASSERT_TRUE(neon.save(QString::fromStdString((project.folder / "neon.png").string())));
    project.extra["light"] = {{"texture", "neon.png"}};
    overlay.setLive(mapA(), project, true);
    ASSERT_TRUE(overlay.light()) << overlay.error();
    // Receiver 0 misses the red samples (0, 0) and (1, 0): it sees the red (0, 1) and (1, 1), 2 of 8.
    EXPECT_EQ(overlay.light()->rgb[0], glm::vec3(0.25f, 0.0f, 0.0f));
    EXPECT_EQ(overlay.light()->rgb[2], glm::vec3(0.5f, 0.0f, 0.0f));
    EXPECT_EQ(overlay.readOut(0, 0), QString("receiver sample (0, 0): light R 25.0%, G 0.0%, B 0.0% of full"));

    overlay.clear();
    project.extra["light"] = {{"texture", "missing.png"}};
    overlay.setLive(mapA(), project, true);
    EXPECT_FALSE(overlay.light());
    EXPECT_TRUE(overlay.texels().empty());
    EXPECT_NE(overlay.error().find("missing.png"), std::string::npos) << overlay.error();
}

TEST(OverlayKinds, NamesRoundTripAndPatches)
{
    for (const OverlayKind kind : {OverlayKind::None, OverlayKind::ReceiverImportance, OverlayKind::SourceImportance,
                                   OverlayKind::LightOnReceiver})
        EXPECT_EQ(parseOverlayKind(toString(kind)), kind);
    EXPECT_THROW(parseOverlayKind("shadow"), Error);
    EXPECT_EQ(overlayPatch(OverlayKind::SourceImportance), ObjectKind::Source);
    EXPECT_EQ(overlayPatch(OverlayKind::LightOnReceiver), ObjectKind::Receiver);
    EXPECT_EQ(overlayPatch(OverlayKind::None), ObjectKind::None);
}

TEST(Picking, PatchSampleUnderARayIsTheCellItCrosses)
{
    const Patch source = floorPatches().first;   // corner (0, 1, 0.5), u = -z, v = +y, 16 x 16
    const glm::dvec3 point = source.corner + (5.25 / 16.0) * source.u + (3.5 / 16.0) * source.v;
    const auto hit = pickPatchSample(source, {point - glm::dvec3(3.0, 0.0, 0.0), {1.0, 0.0, 0.0}});
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->a, 5);
    EXPECT_EQ(hit->b, 3);
    EXPECT_NEAR(hit->s, 5.25 / 16.0, 1e-12);
    EXPECT_NEAR(hit->distance, 3.0, 1e-12);
    // The far edge belongs to the last cell; outside, nothing.
    const auto edge = pickPatchSample(source, {source.corner + source.u + source.v - glm::dvec3(1.0, 0.0, 0.0), {1.0, 0.0, 0.0}});
    ASSERT_TRUE(edge);
    EXPECT_EQ(edge->a, 15);
    EXPECT_EQ(edge->b, 15);
    EXPECT_FALSE(pickPatchSample(source, {source.corner - 0.1 * source.u - glm::dvec3(1.0, 0.0, 0.0), {1.0, 0.0, 0.0}}));
}

// ---- on a level: the floor scene, the wall and the animation ----

/// A wall in the plane x = 5.5, 0.5 m before the receiver, over z in [-2, 0] and y in [0, 1.3]:
/// it hides the source from the receiver's samples with z < 0 and y below about 1.25 (a <= 5 and
/// b <= 3 of 16 are fully in its shadow; a >= 10 or b >= 5 fully lit). Not symmetric in a and b,
/// so a transposed overlay would show.
OccluderSpec cornerWall()
{
    OccluderSpec wall;
    wall.name = "wall";
    wall.mesh = "plane";   // unit square in XZ; turned about z, its x becomes y
    wall.transform = glm::translate(glm::mat4(1.0f), glm::vec3(5.5f, 0.65f, -1.0f)) *
                     glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 0, 1)) *
                     glm::scale(glm::mat4(1.0f), glm::vec3(1.3f, 1.0f, 2.0f));
    return wall;
}

/// The floor level with the two test patches, the wall and, when `animated`, a step animation
/// that moves the wall 20 m aside on every odd frame (4 frames).
std::filesystem::path writeWallProject(const std::filesystem::path& folder, bool animated)
{
    writeFloorObj(folder);
    Project project;
    project.folder = folder;
    project.scene = "floor.obj";
    std::tie(project.source, project.receiver) = floorPatches();
    project.occluders.push_back(cornerWall());
    if (animated)
        project.extra["animation"] = nlohmann::json::parse(R"({"frames": 4, "tracks": [{"target": "occluder", "name": "wall",
            "interpolation": "step", "loop": true,
            "keys": [{"frame": 0, "translate": [0, 0, 0]}, {"frame": 1, "translate": [0, 0, 20]}]}]})");
    const auto file = folder / "wall.json";
    saveProject(project, file);
    return file;
}

TEST(AnimationImportance, AlternatingWallGivesTheMeanOfBothFrames)
{
    EditorDocument document;
    document.open(writeWallProject(freshFolder("overlay-animation"), true));
    const Animation animation = parseAnimation(document.project(), "wall.json");
    ASSERT_EQ(defaultFrameCount(animation), 4);
    int calls = 0;
    const auto progress = [&](int done, int total) {
        EXPECT_EQ(total, 4);
        EXPECT_EQ(done, ++calls);
        return true;
    };
    const ImportanceRunResult run = accumulateDocumentAnimation(document, animation, 4, ImportanceSide::Receiver, progress);
    ASSERT_EQ(run.framesDone, 4);
    const ImportanceMap mean = run.accumulator.result(ImportanceStatistic::Mean);

    // Frame 0 is the document as it is; frame 1 has the shaft open.
    LiveVisibility live;
    live.setScene(document.scene());
    const VisibilityResult frame0 = live.sample(document.project().source, document.project().receiver);
    ASSERT_TRUE(frame0.valid);
    const ImportanceMap shadowed = receiverImportance(frame0.map);
    EXPECT_FLOAT_EQ(shadowed.at(2, 2), 0.0f) << "the wall hides the whole source from this corner";
    EXPECT_FLOAT_EQ(shadowed.at(13, 13), 1.0f);
    ASSERT_TRUE(mean.sameGrid(shadowed));
    for (std::size_t k = 0; k < mean.values.size(); ++k)
        EXPECT_NEAR(mean.values[k], 0.5f * (shadowed.values[k] + 1.0f), 1e-6f) << "sample " << k;
    EXPECT_FLOAT_EQ(run.accumulator.result(ImportanceStatistic::Maximum).at(2, 2), 1.0f);

    // Cancelling after two frames keeps those two.
    const ImportanceRunResult cut = accumulateDocumentAnimation(document, animation, 4, ImportanceSide::Receiver,
                                                                [](int done, int) { return done < 2; });
    EXPECT_TRUE(cut.cancelled);
    EXPECT_EQ(cut.accumulator.frames(), 2);

    // No animation: nothing to run, and an empty Animation says so.
    EditorDocument still;
    still.open(writeWallProject(freshFolder("overlay-still"), false));
    EXPECT_TRUE(parseAnimation(still.project(), "wall.json").empty());
}

/// The camera behind `patch` (on the side its normal does not face), looking at its centre along
/// its normal, from `distance` metres: nothing of the shaft lies between it and the patch.
Camera behind(const Patch& patch, double distance)
{
    Camera camera;
    camera.target = patch.centre();
    camera.distance = distance;
    const glm::dvec3 forward = patch.normal();   // from behind, looking the way the normal points
    camera.yaw = std::atan2(-forward.x, -forward.z);
    camera.pitch = std::asin(forward.y);
    return camera;
}

bool sameColour(QRgb pixel, std::uint32_t rgba, int tolerance = 1)
{
    return std::abs(qRed(pixel) - int(rgba >> 24)) <= tolerance &&
           std::abs(qGreen(pixel) - int((rgba >> 16) & 255)) <= tolerance &&
           std::abs(qBlue(pixel) - int((rgba >> 8) & 255)) <= tolerance;
}

/// The colour smooth texels give at patch coordinates (s, t): bilinear between sample centres,
/// clamped at the borders (what the renderer's shader computes).
std::uint32_t bilinearAt(const OverlayTexels& texels, double s, double t)
{
    const double x = s * texels.na - 0.5, y = t * texels.nb - 0.5;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    auto texel = [&](int a, int b, int shift) {
        return double((texels.rgbaAt(std::clamp(a, 0, texels.na - 1), std::clamp(b, 0, texels.nb - 1)) >> shift) & 255);
    };
    std::uint32_t rgba = 0xff;
    for (const int shift : {24, 16, 8}) {
        const double top = texel(x0, y0, shift) * (1 - fx) + texel(x0 + 1, y0, shift) * fx;
        const double bottom = texel(x0, y0 + 1, shift) * (1 - fx) + texel(x0 + 1, y0 + 1, shift) * fx;
        rgba |= std::uint32_t(std::lround(top * (1 - fy) + bottom * fy)) << shift;
    }
    return rgba;
}

/// Every sample centre of `patch` on the image has the overlay's colour there (nearest texels: the
/// sample's own colour; smooth ones: interpolated at the pixel's centre); returns how many do not.
int wrongSamplePixels(const QImage& image, const Camera& camera, const Patch& patch, const OverlayTexels& texels)
{
    int wrong = 0;
    for (int b = 0; b < patch.nb; ++b) {
        for (int a = 0; a < patch.na; ++a) {
            const glm::dvec3 centre = patch.corner + (a + 0.5) / patch.na * patch.u + (b + 0.5) / patch.nb * patch.v;
            const glm::dvec3 p = toPixels(camera, centre, image.width(), image.height());
            const int x = int(p.x), y = int(p.y);
            std::uint32_t expected = texels.rgbaAt(a, b);
            if (texels.smooth) {
                const auto hit = pickPatchSample(patch, pixelRay(camera, x + 0.5, y + 0.5, image.width(), image.height()));
                if (!hit) {
                    ADD_FAILURE() << "sample (" << a << ", " << b << ") is not on the patch";
                    ++wrong;
                    continue;
                }
                expected = bilinearAt(texels, hit->s, hit->t);
            }
            const QRgb pixel = image.pixel(x, y);
            if (!sameColour(pixel, expected)) {
                ADD_FAILURE() << "sample (" << a << ", " << b << "): pixel " << std::hex << pixel << ", overlay " << expected;
                ++wrong;
            }
        }
    }
    return wrong;
}

TEST(OffscreenRender, ReceiverImportanceOverlayShowsTheValuesOnTheReceiver)
{
    const auto folder = freshFolder("overlay-offscreen");
    EditorDocument document;
    document.open(writeFloorObj(folder));
    const auto [source, receiver] = floorPatches();
    document.setState({ObjectKind::Source, 0}, source, "place");
    document.setState({ObjectKind::Receiver, 0}, receiver, "place");
    const Camera camera = behind(receiver, 1.8);
    ViewStyle style;   // rays on: they lie behind the opaque overlay from here
    style.rayCap = 1 << 16;
    const glm::dvec3 centre = toPixels(camera, receiver.centre(), 400, 400);
    const std::uint32_t yellow = packed(viridis8(1.0f)), purple = packed(viridis8(0.0f));

    // Without an overlay: the translucent blue patch, not the colour map.
    const OffscreenResult plain = renderOffscreen(document, camera, style, 400, 400);
    EXPECT_FALSE(sameColour(plain.image.pixel(int(centre.x), int(centre.y)), yellow, 40));

    // The shaft is open: every receiver sample sees the whole source, 100% = viridis yellow.
    PatchOverlay overlay;
    overlay.setKind(OverlayKind::ReceiverImportance);
    const OffscreenResult open = renderOffscreen(document, camera, style, 400, 400, gl::Backend::OSMesa, &overlay);
    ASSERT_EQ(open.visibility.blocked, 0u);
    ASSERT_TRUE(overlay.importance());
    EXPECT_EQ(wrongSamplePixels(open.image, camera, receiver, overlay.texels()), 0);
    EXPECT_TRUE(sameColour(open.image.pixel(int(centre.x), int(centre.y)), yellow));
    const glm::dvec3 beside = toPixels(camera, receiver.centre() + 0.8 * receiver.u, 400, 400);
    EXPECT_FALSE(sameColour(open.image.pixel(int(beside.x), int(beside.y)), yellow, 40)) << "nothing painted off the patch";

    // A wall before one corner of the receiver: dark there, yellow elsewhere, each sample's own value.
    document.addOccluder(cornerWall());
    const OffscreenResult walled = renderOffscreen(document, camera, style, 400, 400, gl::Backend::OSMesa, &overlay);
    ASSERT_GT(walled.visibility.blocked, 0u);
    EXPECT_EQ(wrongSamplePixels(walled.image, camera, receiver, overlay.texels()), 0);
    auto pixelAt = [&](int a, int b) {
        const glm::dvec3 p = toPixels(camera, receiver.corner + (a + 0.5) / 16 * receiver.u + (b + 0.5) / 16 * receiver.v, 400, 400);
        return walled.image.pixel(int(p.x), int(p.y));
    };
    EXPECT_TRUE(sameColour(pixelAt(2, 2), purple)) << "in the wall's shadow: 0%";
    EXPECT_TRUE(sameColour(pixelAt(13, 2), yellow)) << "beside the wall: 100%";
    EXPECT_TRUE(sameColour(pixelAt(2, 13), yellow)) << "above the wall: 100%";
}

TEST(OffscreenRender, SourceImportanceAndLightOverlays)
{
    const auto folder = freshFolder("overlay-offscreen-source");
    EditorDocument document;
    document.open(writeWallProject(folder, false));
    const Project& project = document.project();

    PatchOverlay overlay;
    overlay.setKind(OverlayKind::SourceImportance);
    const Camera fromBehindSource = behind(project.source, 1.8);
    // Without rays: seen end-on from behind the source, a ray shrinks to a dot whose depth
    // llvmpipe extrapolates, and a few dots would show through the overlay.
    ViewStyle noRays;
    noRays.showRays = false;
    const OffscreenResult source = renderOffscreen(document, fromBehindSource, noRays, 400, 400, gl::Backend::OSMesa, &overlay);
    ASSERT_TRUE(overlay.importance());
    EXPECT_EQ(overlay.importance()->na, project.source.na);
    // The wall hides part of the receiver from every source sample: none sees all of it.
    EXPECT_LT(*std::max_element(overlay.importance()->values.begin(), overlay.importance()->values.end()), 1.0f);
    EXPECT_EQ(wrongSamplePixels(source.image, fromBehindSource, project.source, overlay.texels()), 0);

    // The light: interpolated between sample centres, so at the centres it is the sample's value.
    overlay.setKind(OverlayKind::LightOnReceiver);
    const Camera fromBehindReceiver = behind(project.receiver, 1.8);
    const OffscreenResult light = renderOffscreen(document, fromBehindReceiver, ViewStyle{}, 400, 400, gl::Backend::OSMesa, &overlay);
    ASSERT_TRUE(overlay.light()) << overlay.error();
    EXPECT_EQ(wrongSamplePixels(light.image, fromBehindReceiver, project.receiver, overlay.texels()), 0);
}

} // namespace
} // namespace sightline::ui
