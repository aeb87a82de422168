// A new light map with the same uvs lights the cached level again (LevelRelight.h) instead of
// drawing it again: the picture must be the one a whole draw with that map gives, pixel for pixel,
// for the lit view and for AO, with the wireframe and a selection; and the atlas image a preview
// fills from its gather table (TexelAtlas.h) must be the image of the texels it stands for.
#include <cmath>
#include <limits>

#include <QImage>
#include <gtest/gtest.h>

#include "editor/Camera.h"
#include "editor/LitPreview.h"
#include "RenderTestSupport.h"
#include "TestScenes.h"
#include "editor/TexelAtlas.h"
#include "editor/ViewportRenderer.h"
#include "visibility/Scene.h"
#include "visibility/gl/HeadlessContext.h"

using namespace sightline;
using namespace sightline::ui;

namespace {

/// A map with structure at the texel scale: a light that changed everywhere.
std::vector<glm::vec3> pattern(int width, int height, float phase)
{
    std::vector<glm::vec3> map(std::size_t(width) * std::size_t(height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            map[std::size_t(y) * std::size_t(width) + std::size_t(x)] =
                glm::vec3(0.5f + 0.5f * std::sin(0.37f * float(x) + phase), 0.5f + 0.5f * std::cos(0.23f * float(y) - phase),
                          float((x * 7 + y * 3) % 11) / 10.0f);
    return map;
}

FrameState frameOf(const RenderTarget& target)
{
    FrameState frame;
    frame.camera.target = glm::dvec3(0.0);
    frame.camera.distance = 26.0;
    frame.camera.pitch = -0.5;
    frame.camera.yaw = 0.5;
    frame.width = target.width;
    frame.height = target.height;
    frame.framebuffer = target.framebuffer;
    frame.sceneRadius = 15.0;
    frame.style.showRays = false;
    frame.style.cutaway = false;
    return frame;
}

struct Case {
    const char* name;
    bool lit, wireframe;
    int selected;
};

} // namespace

TEST(LevelRelight, ANewMapWithTheSameUvsGivesTheWholeDrawsPicture)
{
    const auto context = gl::HeadlessContext::create(gl::Backend::OSMesa);
    const gl::Functions& gl = context->functions();
    RenderTarget target;
    ASSERT_TRUE(target.create(gl, 320, 240));
    const Scene scene = test::crossingSheets(24);
    const LitTexels texels = litTexels(scene);
    ASSERT_TRUE(texels.uvs);
    const int w = texels.layout.width, h = texels.layout.height;
    const std::vector<glm::vec3> before = pattern(w, h, 0.0f), between = pattern(w, h, 0.6f), after = pattern(w, h, 1.3f);

    for (const Case& c : {Case{"lit", true, false, -1}, Case{"lit, wireframe, selection", true, true, 0},
                          Case{"AO", false, false, -1}, Case{"AO, wireframe, selection", false, true, 1}}) {
        SCOPED_TRACE(c.name);
        FrameState frame = frameOf(target);
        frame.style.litView = c.lit;
        frame.style.ambientOcclusion = !c.lit;
        frame.style.wireframe = c.wireframe;
        if (c.selected >= 0)
            frame.selection = {ObjectKind::SceneObject, std::size_t(c.selected)};

        QImage whole, first;
        {
            ViewportRenderer renderer(gl);
            renderer.setSceneFile(scene);
            renderer.setAmbientOcclusion(*texels.uvs, w, h, after);
            renderer.render(frame);
            EXPECT_EQ(renderer.lastLevelPass(), LevelPass::Drawn);
            whole = test::readBack(gl, target);
        }
        ViewportRenderer renderer(gl);
        renderer.setSceneFile(scene);
        const auto show = [&](const std::vector<glm::vec2>& uvs, const std::vector<glm::vec3>& map) {
            renderer.setAmbientOcclusion(uvs, w, h, map);
            renderer.render(frame);
            return renderer.lastLevelPass();
        };
        EXPECT_EQ(show(*texels.uvs, before), LevelPass::Drawn);
        first = test::readBack(gl, target);
        ASSERT_NE(first, whole) << "the two maps should light the level differently";
        renderer.render(frame);
        EXPECT_EQ(renderer.lastLevelPass(), LevelPass::Cached);

        // The first new map draws the level with its surfaces (a settled view has none); the
        // next one lights it again from them.
        EXPECT_EQ(show(*texels.uvs, between), LevelPass::Drawn);
        EXPECT_EQ(show(*texels.uvs, after), LevelPass::Relit);
        EXPECT_EQ(test::readBack(gl, target), whole) << "lit again, the level differs from a whole draw with the map";
        renderer.render(frame);
        EXPECT_EQ(renderer.lastLevelPass(), LevelPass::Cached);

        // The camera moved with no new map: drawn without surfaces, so a map after it draws.
        frame.camera.yaw += 0.05;
        renderer.render(frame);
        EXPECT_EQ(renderer.lastLevelPass(), LevelPass::Drawn);
        EXPECT_EQ(show(*texels.uvs, before), LevelPass::Drawn);
        EXPECT_EQ(show(*texels.uvs, after), LevelPass::Relit);
        frame.camera.yaw -= 0.05;

        // Other uvs (the scene's texels changed): drawn whole.
        std::vector<glm::vec2> shifted = *texels.uvs;
        for (glm::vec2& uv : shifted)
            if (uv.x >= 0.0f)
                uv.x += 0.5f / float(w);
        EXPECT_EQ(show(shifted, after), LevelPass::Drawn);
    }
    target.destroy(gl);
}

TEST(LevelRelight, TheMapOfAnotherSizeOrAViewChangeDrawsTheLevel)
{
    const auto context = gl::HeadlessContext::create(gl::Backend::OSMesa);
    const gl::Functions& gl = context->functions();
    RenderTarget target;
    ASSERT_TRUE(target.create(gl, 160, 120));
    const Scene scene = test::crossingSheets(24);
    const LitTexels texels = litTexels(scene);
    const int w = texels.layout.width, h = texels.layout.height;
    FrameState frame = frameOf(target);
    frame.style.litView = true;
    ViewportRenderer renderer(gl);
    renderer.setSceneFile(scene);
    renderer.setAmbientOcclusion(*texels.uvs, w, h, pattern(w, h, 0.0f));
    renderer.render(frame);
    // A new map and a new view in one frame: the view decides.
    renderer.setAmbientOcclusion(*texels.uvs, w, h, pattern(w, h, 0.4f));
    frame.camera.yaw += 0.1;
    renderer.render(frame);
    EXPECT_EQ(renderer.lastLevelPass(), LevelPass::Drawn);
    // Without the lit view or AO the map is not shown: a new one changes nothing.
    frame.style.litView = false;
    renderer.render(frame);
    const QImage unlit = test::readBack(gl, target);
    renderer.setAmbientOcclusion(*texels.uvs, w, h, pattern(w, h, 0.9f));
    renderer.render(frame);
    EXPECT_EQ(renderer.lastLevelPass(), LevelPass::Cached);
    EXPECT_EQ(test::readBack(gl, target), unlit);
    // A map of another size has other texels: the level is drawn with it.
    frame.style.litView = true;
    renderer.render(frame);
    std::vector<glm::vec2> uvs = *texels.uvs;
    renderer.setAmbientOcclusion(uvs, w + 1, h, std::vector<glm::vec3>(std::size_t(w + 1) * std::size_t(h), glm::vec3(0.5f)));
    renderer.render(frame);
    EXPECT_EQ(renderer.lastLevelPass(), LevelPass::Drawn);
    target.destroy(gl);
}

TEST(TexelAtlas, GatheredImageHasEachTexelAndItsGutter)
{
    AoTexelLayout layout;
    layout.width = 8;
    layout.height = 4;
    AoTexelTile a;
    a.x = 1, a.y = 1, a.width = 2, a.height = 2, a.firstPoint = 0;
    AoTexelTile degenerate;
    degenerate.firstPoint = 4;
    AoTexelTile b;
    b.x = 5, b.y = 1, b.width = 1, b.height = 1, b.firstPoint = 4;
    layout.tiles = {a, degenerate, b};
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<glm::vec3> colour = {glm::vec3(0.1f), glm::vec3(0.2f), glm::vec3(nan), glm::vec3(0.4f), glm::vec3(0.5f)};
    const glm::vec3 blank(9.0f);
    const std::vector<glm::vec3> image = atlasImage(layout, colour, blank);
    ASSERT_EQ(image.size(), 32u);
    const auto at = [&](int x, int y) { return image[std::size_t(y) * 8 + std::size_t(x)]; };
    // Texels, a non-finite one blank.
    EXPECT_EQ(at(1, 1), colour[0]);
    EXPECT_EQ(at(2, 1), colour[1]);
    EXPECT_EQ(at(1, 2), blank);
    EXPECT_EQ(at(2, 2), colour[3]);
    // Gutters take their nearest texel (the corners diagonally), inside the atlas only.
    EXPECT_EQ(at(0, 0), colour[0]);
    EXPECT_EQ(at(3, 0), colour[1]);
    EXPECT_EQ(at(0, 1), colour[0]);
    EXPECT_EQ(at(0, 3), blank);   // next to the non-finite texel
    EXPECT_EQ(at(3, 3), colour[3]);
    for (int y = 0; y <= 2; ++y)
        for (int x = 4; x <= 6; ++x)
            EXPECT_EQ(at(x, y), colour[4]) << x << ", " << y;
    // Beyond every gutter: blank.
    EXPECT_EQ(at(7, 0), blank);
    EXPECT_EQ(at(5, 3), blank);
    // The table behind it names those texels.
    const std::vector<std::uint32_t> sources = atlasSources(layout);
    EXPECT_EQ(sources[0], 0u);
    EXPECT_EQ(sources[7], kBlankPixel);
    EXPECT_EQ(gatherAtlas(sources, colour, blank), image);
}

TEST(TexelAtlas, TheLitViewsPointTableGivesTheImageOfItsTexels)
{
    const LitTexels texels = litTexels(test::crossingSheets(24));
    ASSERT_FALSE(texels.points.empty());
    std::vector<glm::vec3> perPoint(texels.points.size());
    for (std::size_t j = 0; j < perPoint.size(); ++j)
        perPoint[j] = glm::vec3(float(j % 97) / 96.0f, float(j % 13) / 12.0f, 0.25f);
    std::vector<glm::vec3> perTexel(texels.pointOfTexel.size(), glm::vec3(0.0f));
    for (std::size_t k = 0; k < perTexel.size(); ++k)
        if (texels.pointOfTexel[k] != SIZE_MAX)
            perTexel[k] = perPoint[texels.pointOfTexel[k]];
    EXPECT_EQ(gatherAtlas(texels.pointOfPixel, perPoint, glm::vec3(0.0f)), atlasImage(texels.layout, perTexel, glm::vec3(0.0f)));
}
