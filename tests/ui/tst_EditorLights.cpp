// Lights in the editor: placed, moved, edited, undone and saved as the "lights" key
// (editor/LightObjects.h, EditorDocument), and the lit view (editor/LitPreview.h) whose exact frame is
// the reference's irradiance, tone-mapped, also after amortised updates.
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <optional>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "EditorDocument.h"
#include "LightCostPanel.h"
#include "editor/LightObjects.h"
#include "editor/LitIndirect.h"
#include "editor/LitPreview.h"
#include "editor/LitReference.h"
#include "TestScenes.h"
#include "UiTestScene.h"
#include "lighting/DirectLight.h"
#include "lighting/Indirect.h"
#include "lighting/LightEmission.h"
#include "lighting/LightSets.h"
#include "project/ProjectLights.h"
#include "base/Error.h"

using namespace sightline;
using namespace sightline::ui;

namespace {

std::filesystem::path freshFolder(const std::string& name)
{
    const auto folder = std::filesystem::temp_directory_path() / ("sightline_editor_lights_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder;
}

Light parsedOne(const nlohmann::json& entry)
{
    return parseLights(nlohmann::json::array({entry}), "test").front();
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-5)
{
    EXPECT_LE(glm::length(a - b), tolerance) << "(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y << ", "
                                            << b.z << ")";
}

TEST(LightObjects, TheGizmosTransformRoundTripsEveryTypeAndKeepsOtherKeys)
{
    const Bounds level{{-5.0f, 0.0f, -5.0f}, {5.0f, 3.0f, 5.0f}};
    for (LightType type : {LightType::Point, LightType::Spot, LightType::Directional, LightType::Area}) {
        nlohmann::json entry = newLightJson(type, {1.0, 2.0, -1.0}, "lamp");
        entry["note"] = "kept";   // a key another tool wrote
        const Light light = parsedOne(entry);
        const nlohmann::json back = placedLightJson(entry, type, lightTransform(light, level));
        EXPECT_EQ(back["note"], "kept");
        const Light again = parsedOne(back);
        expectNear(again.position, light.position);
        expectNear(again.direction, light.direction);
        expectNear(again.area.corner, light.area.corner);
        expectNear(again.area.u, light.area.u);
        expectNear(again.area.v, light.area.v);
        // Moved 1 m along x: a point or spot light's position, an area light's corner; a sun has no place.
        const Light moved = parsedOne(placedLightJson(entry, type, std::get<glm::mat4>(translated(lightTransform(light, level), {1.0, 0.0, 0.0}))));
        if (type == LightType::Area)
            expectNear(moved.area.corner, light.area.corner + glm::dvec3(1.0, 0.0, 0.0));
        else if (type != LightType::Directional)
            expectNear(moved.position, light.position + glm::dvec3(1.0, 0.0, 0.0));
        else
            expectNear(moved.direction, light.direction);
    }
    // A spot turned a quarter about x shines along the turned direction.
    const nlohmann::json spot = newLightJson(LightType::Spot, {0.0, 2.0, 0.0}, "spot");
    const Light turned = parsedOne(placedLightJson(
        spot, LightType::Spot, std::get<glm::mat4>(rotated(lightTransform(parsedOne(spot), level), {1.0, 0.0, 0.0}, 0.5 * std::acos(-1.0)))));
    expectNear(turned.direction, {0.0, 0.0, -1.0});
    // An area light's first scale handle stretches its u edge.
    const nlohmann::json area = newLightJson(LightType::Area, {0.0, 2.0, 0.0}, "panel");
    const Light stretched = parsedOne(placedLightJson(area, LightType::Area, std::get<glm::mat4>(scaled(lightTransform(parsedOne(area), level), 0, 2.0))));
    expectNear(stretched.area.u, 2.0 * parsedOne(area).area.u);
    expectNear(stretched.area.centre(), parsedOne(area).area.centre());
}

// A click on a surface: a ceiling's normal faces down into the room, a wall's into it, a floor's up.
TEST(LightObjects, ALightPlacedOnASurfaceStandsOffItAndShinesAwayFromIt)
{
    const glm::dvec3 ceiling(1.0, 3.0, -2.0), down(0.0, -1.0, 0.0);
    const Light lamp = parsedOne(lightOnSurfaceJson(LightType::Point, ceiling, down, "lamp"));
    expectNear(lamp.position, ceiling + 0.3 * down, 1e-12);
    EXPECT_EQ(lamp.name, "lamp");
    const glm::dvec3 wall(4.0, 1.5, 0.0), west(-1.0, 0.0, 0.0);
    const Light spot = parsedOne(lightOnSurfaceJson(LightType::Spot, wall, west, "spot"));
    expectNear(spot.position, wall + 0.1 * west, 1e-12);
    expectNear(spot.direction, west, 1e-12);
    EXPECT_LT(spot.innerAngle, spot.outerAngle);
    for (const auto& [point, normal] : {std::pair(ceiling, down), std::pair(wall, west), std::pair(glm::dvec3(0.0, 0.0, 0.0), glm::dvec3(0.0, 1.0, 0.0)),
                                        std::pair(glm::dvec3(2.0, 1.0, 2.0), glm::normalize(glm::dvec3(1.0, 1.0, 0.0)))}) {
        const Light panel = parsedOne(lightOnSurfaceJson(LightType::Area, point, normal, "panel"));
        expectNear(panel.area.centre(), point + 0.01 * normal, 1e-12);
        expectNear(panel.area.normal(), normal, 1e-12);   // emits away from the surface
        EXPECT_NEAR(glm::length(panel.area.u), 0.5, 1e-12);
        EXPECT_NEAR(glm::length(panel.area.v), 0.5, 1e-12);
        EXPECT_NEAR(glm::dot(panel.area.u, normal), 0.0, 1e-12);
        EXPECT_NEAR(glm::dot(panel.area.v, normal), 0.0, 1e-12);
    }
    // A sun has no place: the new sun's own direction.
    EXPECT_EQ(lightOnSurfaceJson(LightType::Directional, ceiling, down, "sun"), newLightJson(LightType::Directional, ceiling, "sun"));
}

TEST(LightObjects, AClickNearAMarkerPicksItsLight)
{
    const Light lamp = parsedOne(newLightJson(LightType::Point, {0.0, 2.0, 0.0}, "lamp"));
    const Bounds level{{-5.0f, 0.0f, -5.0f}, {5.0f, 3.0f, 5.0f}};
    const auto hit = pickLight(lamp, level, Ray{{0.0, 2.0, 5.0}, {0.0, 0.0, -1.0}}, 0.1);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(*hit, 5.0, 1e-9);
    EXPECT_FALSE(pickLight(lamp, level, Ray{{0.0, 2.5, 5.0}, {0.0, 0.0, -1.0}}, 0.1));
    EXPECT_FALSE(pickLight(lamp, level, Ray{{0.0, 2.0, 5.0}, {0.0, 0.0, 1.0}}, 0.1)) << "behind the eye";
}

TEST(EditorDocumentLights, LightsArePlacedMovedEditedUndoneAndSaved)
{
    const auto folder = freshFolder("document");
    EditorDocument document;
    document.open(test::writeFloorObj(folder));
    ASSERT_TRUE(document.lights().empty());
    QUndoStack& undo = *document.undoStack();

    document.addLight(newLightJson(LightType::Point, {0.0, 2.0, 0.0}, "Point light 1"));
    ASSERT_EQ(document.lights().size(), 1u);
    EXPECT_EQ(document.selection(), (ObjectRef{ObjectKind::Light, 0}));
    EXPECT_EQ(document.objectName(document.selection()).toStdString(), "Point light 1");
    // Moved as the gizmo moves it: one undoable step.
    const ObjectRef light{ObjectKind::Light, 0};
    document.setState(light, translated(document.state(light), {1.0, 0.5, 0.0}), "move");
    expectNear(document.lights()[0].position, {1.0, 2.5, 0.0});
    undo.undo();
    expectNear(document.lights()[0].position, {0.0, 2.0, 0.0});
    undo.redo();
    expectNear(document.lights()[0].position, {1.0, 2.5, 0.0});
    // An edit that would break the light is refused with the key, and changes nothing.
    nlohmann::json bad = document.lightsJson()[0];
    bad["intensity"] = -1.0;
    EXPECT_THROW(document.editLight(0, bad, "bad"), Error);
    EXPECT_EQ(document.lights()[0].intensity, parsedOne(document.lightsJson()[0]).intensity);
    nlohmann::json brighter = document.lightsJson()[0];
    brighter["intensity"] = 50.0;
    document.editLight(0, brighter, "brighter");
    EXPECT_EQ(document.lights()[0].intensity, 50.0);
    // Duplicated beside the original, then a spot added and deleted.
    document.duplicateSelected();
    ASSERT_EQ(document.lights().size(), 2u);
    EXPECT_EQ(document.lights()[1].name, "Point light 1 copy");
    EXPECT_GT(glm::length(document.lights()[1].position - document.lights()[0].position), 0.1);
    document.addLight(newLightJson(LightType::Spot, {0.0, 2.0, 1.0}, "spot"));
    document.removeSelected();
    ASSERT_EQ(document.lights().size(), 2u);
    undo.undo();
    ASSERT_EQ(document.lights().size(), 3u);
    undo.redo();

    document.save(folder / "lit.json");
    EditorDocument again;
    again.open(folder / "lit.json");
    ASSERT_EQ(again.lights().size(), 2u);
    EXPECT_EQ(again.lightsJson(), document.lightsJson());
    EXPECT_EQ(projectLights(loadProject(folder / "lit.json")).size(), 2u) << "the CLI reads what the editor wrote";
    // Back to the start: no light, no key written.
    while (undo.canUndo())
        undo.undo();
    EXPECT_TRUE(document.lights().empty());
    EXPECT_FALSE(document.project().extra.contains("lights"));
}

TEST(EditorDocumentLights, AProjectWithABadLightIsRefusedNamingTheKey)
{
    const auto folder = freshFolder("bad");
    EditorDocument document;
    document.open(test::writeFloorObj(folder));
    Project project = document.project();
    project.extra["lights"] = nlohmann::json::array({{{"type", "spot"}, {"position", {0, 2, 0}}, {"intensity", 1.0},
                                                      {"inner_angle", 0.8}, {"outer_angle", 0.4}}});
    saveProject(project, folder / "bad.json");
    try {
        EditorDocument other;
        other.open(folder / "bad.json");
        ADD_FAILURE() << "opened";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("lights[0]"), std::string::npos) << e.what();
    }
}

/// A 10 x 10 m floor with a unit box on it: shadows on the floor, light on the box.
std::shared_ptr<const Scene> boxOnAFloor()
{
    Scene scene = test::sceneOf({test::quad({-5.0f, 0.0f, -5.0f}, {0.0f, 0.0f, 10.0f}, {10.0f, 0.0f, 0.0f}, "floor")});
    scene.addMeshInstance(test::closedBox(), glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.5f, 0.0f)));
    return std::make_shared<const Scene>(std::move(scene));
}

std::vector<Light> someLights()
{
    return parseLights(nlohmann::json::array({newLightJson(LightType::Point, {1.5, 2.0, 0.5}, "a"),
                                              newLightJson(LightType::Spot, {-2.0, 3.0, -1.0}, "b"),
                                              newLightJson(LightType::Area, {0.5, 2.5, -2.0}, "c")}),
                       "test");
}

/// The colour the map holds for texel point k of the layout.
glm::vec3 mapAt(const LitPreviewFrame& frame, const LitTexels& texels, std::size_t k)
{
    for (const AoTexelTile& tile : texels.layout.tiles)
        if (k >= tile.firstPoint && k < tile.firstPoint + std::size_t(tile.width) * std::size_t(tile.height)) {
            const std::size_t local = k - tile.firstPoint;
            const int s = int(local % std::size_t(tile.width)), t = int(local / std::size_t(tile.width));
            return frame.map[std::size_t(tile.y + t) * std::size_t(frame.width) + std::size_t(tile.x + s)];
        }
    ADD_FAILURE() << "texel " << k << " in no tile";
    return glm::vec3(0.0f);
}

TEST(LitPreview, TheExactFrameIsTheReferencesIrradianceToneMapped)
{
    const auto scene = boxOnAFloor();
    const std::vector<Light> lights = someLights();
    const LitPreviewFrame frame = exactLitFrame(scene, lights);
    ASSERT_TRUE(frame.error.empty()) << frame.error;
    ASSERT_TRUE(frame.exact);
    const LitTexels texels = litTexels(*scene);
    EXPECT_EQ(frame.texels, texels.points.size());
    const LightingScene lighting(*scene);
    const std::vector<glm::dvec3> reference =
        directIrradiance(lighting, lights, texels.points, DirectLightOptions{.path = LightingPath::Reference});
    std::size_t shadowed = 0, lit = 0;
    for (std::size_t k = 0; k < texels.pointOfTexel.size(); ++k) {
        if (texels.pointOfTexel[k] == SIZE_MAX)
            continue;
        const glm::dvec3 e = reference[texels.pointOfTexel[k]];
        const glm::vec3 expected = toneMapped(e, frame.exposure), shown = mapAt(frame, texels, k);
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(shown[c], expected[c], 1e-5) << "texel " << k;
        (e.r > 0.0 ? lit : shadowed) += 1;
    }
    EXPECT_GT(lit, 1000u);
    EXPECT_GT(shadowed, 100u) << "the box's shadow and its undersides";
}

TEST(LitIndirect, TheBounceShownIsTheVplsIrradianceOnceExactAndThePreviousOneUntilThen)
{
    const auto scene = boxOnAFloor();
    std::vector<Light> lights = someLights();
    const LitTexels texels = litTexels(*scene);
    const LightingScene lighting(*scene);
    const IndirectOptions options = litIndirectOptions();
    const auto expected = [&] {
        return vplIrradiance(lighting, traceVpls(lighting, lights, options), texels.points, options).irradiance;
    };
    const auto settle = [&](LitIndirect& bounce) {
        for (int frame = 0; frame < 10000 && !bounce.exact(); ++frame)
            bounce.update(lighting, 1);   // a VPL or so a frame
    };
    const auto expectShown = [&](const LitIndirect& bounce, const std::vector<glm::dvec3>& want, std::size_t litAtLeast = 0) {
        ASSERT_EQ(bounce.irradiance().size(), want.size());
        std::size_t lit = 0;
        for (std::size_t j = 0; j < want.size(); ++j) {
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(bounce.irradiance()[j][c], want[j][c], 1e-6 * want[j][c] + 1e-12) << "point " << j;
            lit += want[j].r > 0.0;
        }
        EXPECT_GE(lit, litAtLeast) << "the bounce reaches most of the level";
    };
    LitIndirect bounce(texels.points);
    EXPECT_FALSE(bounce.exact());
    bounce.setLights(lighting, lights);
    EXPECT_GT(bounce.vpls(), 100u);
    for (const glm::dvec3& e : bounce.irradiance())
        ASSERT_EQ(e, glm::dvec3(0.0));   // nothing shown before the first bounce is complete
    settle(bounce);
    ASSERT_TRUE(bounce.exact());
    const std::vector<glm::dvec3> first = expected();
    expectShown(bounce, first, first.size() / 2);

    // A light moved: its bounce is traced again; the old one stays until the new one is whole.
    lights[0].position += glm::dvec3(-2.0, 0.5, 1.0);
    bounce.setLights(lighting, lights);
    EXPECT_FALSE(bounce.exact());
    bounce.update(lighting, 1);
    if (!bounce.exact())
        expectShown(bounce, first);
    settle(bounce);
    ASSERT_TRUE(bounce.exact());
    expectShown(bounce, expected());
    // The area light moved, which sends few of the photons: the other lights' VPLs come back the
    // same, so only its own are lit again, its old ones taken away and its new ones added.
    lights[2].area.corner += glm::dvec3(1.0, 0.0, 0.5);
    bounce.setLights(lighting, lights);
    EXPECT_GT(bounce.pending(), 0u);
    EXPECT_LT(bounce.pending(), bounce.vpls());   // not lit anew
    bounce.update(lighting, 1);
    settle(bounce);
    ASSERT_TRUE(bounce.exact());
    expectShown(bounce, expected());
    // The light's power changed: every light's photon count may change, and the bounce is lit anew.
    lights[1].intensity *= 3.0;
    bounce.setLights(lighting, lights);
    settle(bounce);
    ASSERT_TRUE(bounce.exact());
    expectShown(bounce, expected());
    // Unchanged lights: nothing to light, exact at once.
    bounce.setLights(lighting, lights);
    EXPECT_TRUE(bounce.exact());
    EXPECT_EQ(bounce.pending(), 0u);
    expectShown(bounce, expected());
}

TEST(LitPreview, WithTheBounceTheExactFrameIsTheDirectAndTheBounceToneMapped)
{
    const auto scene = boxOnAFloor();
    const std::vector<Light> lights = someLights();
    // As the headless screenshot's `--lit --lit-indirect` asks for it.
    const std::optional<LitPreviewFrame> exact = exactLitFrame(scene, lights, LitShading::Light, 4, true);
    ASSERT_TRUE(exact->error.empty()) << exact->error;
    EXPECT_TRUE(exact->indirect);
    EXPECT_GT(exact->vpls, 100u);
    const LitTexels texels = litTexels(*scene);
    const LightingScene lighting(*scene);
    const std::vector<glm::dvec3> direct = directIrradiance(lighting, lights, texels.points, DirectLightOptions{.path = LightingPath::Reference});
    const IndirectOptions options = litIndirectOptions();
    const std::vector<glm::dvec3> bounce = vplIrradiance(lighting, traceVpls(lighting, lights, options), texels.points, options).irradiance;
    std::size_t brighter = 0;
    for (std::size_t k = 0; k < texels.pointOfTexel.size(); ++k) {
        if (texels.pointOfTexel[k] == SIZE_MAX)
            continue;
        const std::size_t j = texels.pointOfTexel[k];
        const glm::vec3 want = toneMapped(direct[j] + bounce[j], exact->exposure), shown = mapAt(*exact, texels, k);
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(shown[c], want[c], 1e-5) << "texel " << k;
        brighter += toneMapped(direct[j], exact->exposure).g < shown.g;
    }
    EXPECT_GT(brighter, texels.points.size() / 2) << "the bounce lights the shadows too";
}

/// The frames a LitPreview delivers, kept in order, and a wait for the next exact (or failed) one.
struct FrameLog {
    std::mutex mutex;
    std::condition_variable arrived;
    std::vector<LitPreviewFrame> frames;

    LitPreview::Deliver deliver()
    {
        return [this](LitPreviewFrame frame) {
            std::lock_guard lock(mutex);
            frames.push_back(std::move(frame));
            arrived.notify_all();
        };
    }
    /// Whether a frame after the first `count` was exact or failed within two minutes.
    bool waitExact(std::size_t count)
    {
        std::unique_lock lock(mutex);
        return arrived.wait_for(lock, std::chrono::seconds(120), [&] {
            return frames.size() > count && (frames.back().exact || !frames.back().error.empty());
        });
    }
};

/// Two frames show the same irradiance texel for texel, each decoded by its own exposure.
void expectSameIrradiance(const LitPreviewFrame& shown, const LitPreviewFrame& fresh)
{
    ASSERT_EQ(fresh.map.size(), shown.map.size());
    std::size_t compared = 0;
    for (std::size_t i = 0; i < fresh.map.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double a = shown.map[i][c], b = fresh.map[i][c];
            if (a > 0.95 || b > 0.95)
                continue;   // the tone map's flat end: no digits left to compare
            const double ea = -std::log1p(-a) / shown.exposure, eb = -std::log1p(-b) / fresh.exposure;
            ASSERT_NEAR(ea, eb, 1e-4 * std::max(eb, 1e-3)) << "pixel " << i;
            ++compared;
        }
    EXPECT_GT(compared, 1000u);
}

TEST(LitPreview, AMovedLightIsRefreshedByPriorityAndTheViewBecomesExactAgain)
{
    const auto scene = boxOnAFloor();
    std::vector<Light> lights = someLights();
    FrameLog log;
    std::vector<LitPreviewFrame>& frames = log.frames;
    std::mutex& mutex = log.mutex;
    LitPreview preview(log.deliver());
    // A small budget: one light a frame, so the updates are amortised.
    preview.start(7, {.scene = scene, .lights = lights, .segmentsPerFrame = 1});
    ASSERT_TRUE(log.waitExact(0));
    std::size_t seen = 0;
    {
        std::lock_guard lock(mutex);
        ASSERT_TRUE(frames.back().error.empty()) << frames.back().error;
        EXPECT_GE(frames.size(), 3u) << "three lights, one refreshed a frame";
        EXPECT_FALSE(frames.front().exact);
        seen = frames.size();
    }
    lights[0].position += glm::dvec3(-1.0, 0.2, 0.0);
    const std::uint64_t moved = preview.setLights(lights);
    ASSERT_TRUE(log.waitExact(seen));
    LitPreviewFrame last;
    {
        std::lock_guard lock(mutex);
        // The moved light alone: first its low-resolution pass, then exactly.
        ASSERT_EQ(frames.size(), seen + 2);
        EXPECT_EQ(frames[seen].refreshed, 1u);
        EXPECT_EQ(frames[seen].rough, 1u);
        EXPECT_EQ(frames[seen].stale, 1u);
        EXPECT_FALSE(frames[seen].exact);
        EXPECT_EQ(frames[seen + 1].refreshed, 1u);
        EXPECT_EQ(frames[seen + 1].rough, 0u);
        EXPECT_EQ(frames[seen + 1].stale, 0u);
        EXPECT_EQ(frames[seen + 1].lightsVersion, moved);
        EXPECT_LT(frames[seen - 1].lightsVersion, moved);
        last = frames.back();
    }
    preview.stop();
    // The same irradiance as a fresh exact frame of the moved lights (each with its own exposure).
    expectSameIrradiance(last, exactLitFrame(scene, lights));
}

std::shared_ptr<const Scene> boxOnAFloorAt(const glm::vec3& at)
{
    Scene scene = test::sceneOf({test::quad({-5.0f, 0.0f, -5.0f}, {0.0f, 0.0f, 10.0f}, {10.0f, 0.0f, 0.0f}, "floor")});
    scene.addMeshInstance(test::closedBox(), glm::translate(glm::mat4(1.0f), at));
    return std::make_shared<const Scene>(std::move(scene));
}

TEST(LitPreview, AMovedOccluderRefreshesTheTexelsItsShadowsCouldReachAndTheViewBecomesExactAgain)
{
    const auto before = boxOnAFloorAt({0.0f, 0.5f, 0.0f}), after = boxOnAFloorAt({2.5f, 0.5f, 1.5f});
    const std::vector<Light> lights = someLights();
    FrameLog log;
    std::vector<LitPreviewFrame>& frames = log.frames;
    std::mutex& mutex = log.mutex;
    LitPreview preview(log.deliver());
    preview.start(3, {.scene = before, .lights = lights});
    ASSERT_TRUE(log.waitExact(0));
    std::size_t seen = 0;
    std::vector<LightingCache::LightCost> whole;
    {
        std::lock_guard lock(mutex);
        ASSERT_TRUE(frames.back().error.empty()) << frames.back().error;
        seen = frames.size();
        whole = frames.back().costs;
    }
    const std::uint64_t moved = preview.setScene(after);
    ASSERT_TRUE(log.waitExact(seen));
    LitPreviewFrame last;
    {
        std::lock_guard lock(mutex);
        ASSERT_TRUE(frames.back().error.empty()) << frames.back().error;
        // One frame at the default budget; each light lit again where the box's shadows were or
        // are and on the box's new texels, at a fraction of lighting every texel.
        ASSERT_EQ(frames.size(), seen + 1);
        last = frames.back();
        EXPECT_EQ(last.lightsVersion, moved);
        EXPECT_EQ(last.refreshed, lights.size());
        EXPECT_EQ(last.texels, litTexels(*after).points.size());
        ASSERT_EQ(last.costs.size(), whole.size());
        for (std::size_t l = 0; l < lights.size(); ++l)
            EXPECT_LT(last.costs[l].terms, whole[l].terms / 2) << "light " << l;
    }
    preview.stop();
    expectSameIrradiance(last, exactLitFrame(after, lights));
}

TEST(LitPreview, ASceneSetAsTheWorkerStartsIsTheOneItLights)
{
    const auto before = boxOnAFloorAt({0.0f, 0.5f, 0.0f}), after = boxOnAFloorAt({2.5f, 0.5f, 1.5f});
    const std::vector<Light> lights = someLights();
    FrameLog log;
    LitPreview preview(log.deliver());
    preview.start(4, {.scene = before, .lights = lights});
    const std::uint64_t moved = preview.setScene(after);   // the worker may not have read the first yet
    std::optional<LitPreviewFrame> last;
    for (std::size_t seen = 0; !last;) {
        ASSERT_TRUE(log.waitExact(seen));
        std::lock_guard lock(log.mutex);
        ASSERT_TRUE(log.frames.back().error.empty()) << log.frames.back().error;
        if (log.frames.back().lightsVersion == moved)
            last = log.frames.back();
        seen = log.frames.size();
    }
    preview.stop();
    expectSameIrradiance(*last, exactLitFrame(after, lights));
}

/// The first frame of `shading` once exact.
LitPreviewFrame exactFrameShowing(std::shared_ptr<const Scene> scene, const std::vector<Light>& lights, LitShading shading, int budget)
{
    std::mutex mutex;
    std::condition_variable arrived;
    std::optional<LitPreviewFrame> last;
    LitPreview preview([&](LitPreviewFrame frame) {
        std::lock_guard lock(mutex);
        if ((frame.exact && frame.shading == shading) || !frame.error.empty())
            last = std::move(frame);
        arrived.notify_all();
    });
    preview.start(3, {.scene = std::move(scene), .lights = lights, .segmentsPerFrame = std::uint64_t(1) << 40});
    preview.setShading(shading, budget);   // switched after the start, as the menu does
    std::unique_lock lock(mutex);
    EXPECT_TRUE(arrived.wait_for(lock, std::chrono::seconds(120), [&] { return last.has_value(); }));
    LitPreviewFrame out = last ? *last : LitPreviewFrame{};
    lock.unlock();
    preview.stop();
    return out;
}

/// The sets the preview computes for `request` (between frames, on its worker).
std::optional<LightSets> previewSets(std::shared_ptr<const Scene> scene, const std::vector<Light>& lights,
                                     LitPreview::SetsRequest request)
{
    std::mutex mutex;
    std::condition_variable arrived;
    std::optional<LightSets> sets;
    LitPreview preview([&](LitPreviewFrame frame) {
        std::lock_guard lock(mutex);
        if (frame.sets)
            sets = frame.sets;
        arrived.notify_all();
    });
    preview.start(5, {.scene = std::move(scene), .lights = lights, .segmentsPerFrame = std::uint64_t(1) << 40});
    preview.requestSets(std::move(request));
    std::unique_lock lock(mutex);
    EXPECT_TRUE(arrived.wait_for(lock, std::chrono::seconds(120), [&] { return sets.has_value(); }));
    const std::optional<LightSets> out = sets;
    lock.unlock();
    preview.stop();
    return out;
}

// A baked PVS serves the sets: V is the row given (the camera cell's), and L is the light's reach
// within the row it is bounded by, no more.
TEST(LitPreview, SetsServedByAPvsTakeItsRowAsVAndBoundL)
{
    const auto scene = boxOnAFloor();   // instances: 0 the floor, 1 the box
    const std::vector<Light> lights = someLights();
    Camera camera;
    camera.target = {0.0, 0.5, 0.0};
    camera.distance = 6.0;
    const std::optional<LightSets> plain = previewSets(scene, lights, {0, camera, std::nullopt, std::nullopt});
    ASSERT_TRUE(plain);
    ASSERT_EQ(plain->L, (std::vector<std::uint32_t>{0, 1}));
    const std::optional<LightSets> served =
        previewSets(scene, lights, {0, camera, std::vector<std::uint32_t>{1}, std::vector<std::uint32_t>{0}});
    ASSERT_TRUE(served);
    EXPECT_EQ(served->V, (std::vector<std::uint32_t>{1}));
    EXPECT_EQ(served->L, (std::vector<std::uint32_t>{0}));   // the box is outside the row bounding L
    EXPECT_TRUE(served->I.empty());
}

// pvsReach: the rows of the cells a light stands in; none for a light outside every cell or a sun.
TEST(LitPreview, PvsReachIsTheRowOfTheCellsALightStandsIn)
{
    const std::vector<Bounds> cells = {{glm::vec3(-5, 0, -5), glm::vec3(0, 3, 5)}, {glm::vec3(0, 0, -5), glm::vec3(5, 3, 5)}};
    pvs::VisibilityRows rows(2, 3);
    rows.set(0, 0, true);
    rows.set(1, 1, true);
    rows.set(1, 2, true);
    std::vector<pvs::PvsObject> objects(3);
    objects[0].instances = {0};
    objects[1].instances = {1, 4};
    objects[2].instances = {2};
    Light lamp;
    lamp.position = {2.0, 1.0, 0.0};
    EXPECT_EQ(pvsReach(cells, rows, objects, lamp), (std::vector<std::uint32_t>{1, 2, 4}));
    lamp.position = {9.0, 1.0, 0.0};
    EXPECT_FALSE(pvsReach(cells, rows, objects, lamp));
    Light panel;
    panel.type = LightType::Area;
    panel.area.corner = {-1.0, 2.5, -1.0};
    panel.area.u = {2.0, 0.0, 0.0};
    panel.area.v = {0.0, 0.0, 2.0};
    EXPECT_EQ(pvsReach(cells, rows, objects, panel), (std::vector<std::uint32_t>{0, 1, 2, 4}));   // across both cells
    Light sun;
    sun.type = LightType::Directional;
    EXPECT_FALSE(pvsReach(cells, rows, objects, sun));
}

TEST(LitPreview, OverlapAndComplexityCountEachLightAsTheReferenceLightsAlone)
{
    const auto scene = boxOnAFloor();
    const std::vector<Light> lights = someLights();
    const LitTexels texels = litTexels(*scene);
    const LightingScene lighting(*scene);
    // Each light alone, shadowed (the reference) and unshadowed (its emitters' terms).
    std::vector<std::vector<glm::dvec3>> alone;
    for (const Light& light : lights)
        alone.push_back(directIrradiance(lighting, {light}, texels.points, DirectLightOptions{.path = LightingPath::Reference}));
    const std::vector<Emitter> emitters = lightEmitters(lights);
    const auto open = [&](std::size_t l, const ShadingPoint& p) {
        double sum = 0.0;
        for (const Emitter& e : emitters)
            if (e.light == l)
                sum += emitterTerm(lights[l], e.position, p.position, p.normal);
        return sum;
    };
    const LitPreviewFrame overlap = exactFrameShowing(scene, lights, LitShading::Overlap, 2);
    const LitPreviewFrame complexity = exactFrameShowing(scene, lights, LitShading::Complexity, 2);
    ASSERT_TRUE(overlap.exact && complexity.exact);
    std::size_t over = 0, lit = 0, partial = 0, shadowed = 0, most = 0;
    for (std::size_t k = 0; k < texels.pointOfTexel.size(); ++k) {
        const std::size_t j = texels.pointOfTexel[k];
        if (j == SIZE_MAX)
            continue;
        std::size_t reaching = 0;
        TexelLightCounts counts;
        for (std::size_t l = 0; l < lights.size(); ++l) {
            const double shadowedTerm = alone[l][j].r;   // white lights: every channel the same
            reaching += shadowedTerm > 0.0 ? 1 : 0;
            const double unshadowed = open(l, texels.points[j]);
            if (unshadowed <= 0.0)
                continue;
            if (shadowedTerm <= 0.0)
                ++counts.shadowed;
            else if (shadowedTerm >= unshadowed * (1.0 - 1e-5))
                ++counts.lit;
            else
                ++counts.partial;
        }
        const glm::vec3 wantOverlap = overlapColour(reaching, 2), wantComplexity = complexityColour(counts, 2);
        const glm::vec3 shownOverlap = mapAt(overlap, texels, k), shownComplexity = mapAt(complexity, texels, k);
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(shownOverlap[c], wantOverlap[c]) << "texel " << k << ": " << reaching << " lights";
            ASSERT_EQ(shownComplexity[c], wantComplexity[c]) << "texel " << k;
        }
        over += reaching > 2 ? 1 : 0;
        lit += counts.lit, partial += counts.partial, shadowed += counts.shadowed;
        most = std::max(most, reaching);
    }
    EXPECT_GT(over, 0u) << "three lights over a budget of two somewhere";
    EXPECT_EQ(overlap.mostLights, most);
    EXPECT_GT(lit, 0u);
    EXPECT_GT(partial, 0u) << "the area light's penumbra";
    EXPECT_GT(shadowed, 0u);
}

} // namespace

TEST(LightCostPanel, TheSummarySumsTheLightsAndTheCostliestShare)
{
    const auto cost = [](double ms, std::uint64_t rays, bool stale) {
        LightingCache::LightCost c;
        c.ms = ms;
        c.rays = rays;
        c.stale = stale;
        return c;
    };
    const std::vector<LightingCache::LightCost> costs = {cost(10.0, 1'000'000, false), cost(60.0, 2'500'000, false),
                                                         cost(30.0, 500'000, true), cost(0.0, 0, false)};
    EXPECT_EQ(lightCostSummary(costs, 1).toStdString(),
              "4 lights, 1 stale: 4.00 million shadow rays and 0.10 s to refresh them all; the 1 costliest take 60%");
    EXPECT_TRUE(lightCostSummary(costs, 2).endsWith("the 2 costliest take 90%"));
    EXPECT_TRUE(lightCostSummary(costs, 9).endsWith("the 4 costliest take 100%"));
    EXPECT_EQ(lightCostSummary({}).toStdString(), "No lights in the lit view.");
}

TEST(LitPreview, TheErrorViewAgreesWithTheReferenceOnceExactAndShowsTheLowResolutionPassesError)
{
    const auto scene = boxOnAFloor();
    std::vector<Light> lights = someLights();
    std::mutex mutex;
    std::condition_variable arrived;
    std::vector<LitPreviewFrame> frames;
    LitPreview preview([&](LitPreviewFrame frame) {
        std::lock_guard lock(mutex);
        frames.push_back(std::move(frame));
        arrived.notify_all();
    });
    preview.start(5, {.scene = scene, .lights = lights, .shading = LitShading::Error});
    const auto waitReferenced = [&](std::size_t after) {
        std::unique_lock lock(mutex);
        return arrived.wait_for(lock, std::chrono::seconds(120), [&] {
            const LitPreviewFrame& f = frames.back();
            return frames.size() > after && ((f.exact && f.referenceLights == f.lights) || !f.error.empty());
        });
    };
    ASSERT_TRUE(waitReferenced(0));
    std::size_t seen = 0;
    {
        std::lock_guard lock(mutex);
        const LitPreviewFrame& exact = frames.back();
        ASSERT_TRUE(exact.error.empty()) << exact.error;
        // The fast path is the reference up to float rounding: every texel agrees.
        EXPECT_LT(exact.errorMax, double(kErrorAgrees));
        EXPECT_EQ(exact.errorOverPercent, 0.0);
        const LitTexels texels = litTexels(*scene);
        for (std::size_t k = 0; k < texels.pointOfTexel.size(); k += 7) {
            if (texels.pointOfTexel[k] != SIZE_MAX) {
                ASSERT_EQ(mapAt(exact, texels, k), errorColour(0.0f)) << "texel " << k;
            }
        }
        seen = frames.size();
    }
    // The area light moves: its low-resolution pass is shown against its new reference (errors
    // where it interpolated), then its exact refresh agrees again.
    lights[2].area.corner += glm::dvec3(0.7, 0.0, 0.4);
    preview.setLights(lights);
    ASSERT_TRUE(waitReferenced(seen));
    {
        std::lock_guard lock(mutex);
        ASSERT_GE(frames.size(), seen + 2);
        const LitPreviewFrame& rough = frames[seen];
        EXPECT_EQ(rough.rough, 1u);
        EXPECT_EQ(rough.referenceLights, rough.lights);
        EXPECT_GT(rough.errorMax, double(kErrorAgrees));
        EXPECT_LT(frames.back().errorMax, double(kErrorAgrees));
    }
    preview.stop();
    EXPECT_EQ(parseLitShading("error"), LitShading::Error);
}

TEST(LitReference, ErrorsAreRelativeToTheReferenceWithAFloorAndColouredByDecade)
{
    const std::vector<glm::dvec3> reference = {glm::dvec3(100.0), glm::dvec3(10.0), glm::dvec3(0.0), glm::dvec3(1e-5)};
    const std::vector<glm::dvec3> shown = {glm::dvec3(100.0), glm::dvec3(11.0), glm::dvec3(0.05), glm::dvec3(2e-5)};
    const std::vector<float> error = relativeError(shown, reference);
    EXPECT_FLOAT_EQ(error[0], 0.0f);
    EXPECT_FLOAT_EQ(error[1], 0.1f);
    EXPECT_FLOAT_EQ(error[2], 0.5f);    // against the floor: 1e-3 of the brightest (0.1)
    EXPECT_FLOAT_EQ(error[3], 1e-4f);   // 1e-5 off, against the floor
    EXPECT_EQ(errorColour(0.0f), errorColour(0.5f * kErrorAgrees));
    EXPECT_NE(errorColour(0.0f), errorColour(kErrorAgrees));
    EXPECT_EQ(errorColour(1.0f), errorColour(5.0f));   // 100% and over: red
    EXPECT_EQ(errorColour(std::nanf("")), errorColour(1.0f));
}
