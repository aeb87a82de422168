// A newly opened level is prepared off the GUI thread and its first draw spread over frames
// (ViewportRenderer::setSceneFile(LevelMesh, true)): the picture it ends on must be the one a
// whole draw gives, pixel for pixel, with the depth test working across the chunks.
#include <cmath>
#include <cstdint>

#include <QImage>
#include <gtest/gtest.h>

#include "Camera.h"
#include "TestScenes.h"
#include "ViewportRenderer.h"
#include "visibility/Scene.h"
#include "visibility/gl/HeadlessContext.h"

using namespace sightline;
using namespace sightline::ui;

namespace {

/// A rolling sheet of n x n quads and a tilted plane through it: 2 n^2 + 2 triangles, surfaces
/// that cross, so that later chunks must be depth-tested against earlier ones.
Scene crossingSheets(int n)
{
    Mesh sheet = test::heightGrid("sheet", n, 10.0f, [](float x, float z) { return std::sin(x * 0.7f) * std::cos(z * 0.5f); });
    Mesh plane;
    plane.name = "plane";
    plane.positions = {{-10.0f, -2.0f, -10.0f}, {10.0f, -2.0f, -10.0f}, {10.0f, 2.0f, 10.0f}, {-10.0f, 2.0f, 10.0f}};
    plane.indices = {0, 2, 1, 0, 3, 2};
    Scene scene;
    scene.addMeshInstance(std::move(sheet));
    scene.addMeshInstance(std::move(plane));
    return scene;
}

QImage readBack(const gl::Functions& gl, const RenderTarget& target)
{
    QImage image(target.width, target.height, QImage::Format_RGBA8888);
    gl.BindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.ReadPixels(0, 0, target.width, target.height, GL_RGBA, GL_UNSIGNED_BYTE, image.bits());
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    return image;
}

} // namespace

TEST(LevelFirstDraw, InChunksOverFramesGivesTheWholeDrawsPicture)
{
    const auto context = gl::HeadlessContext::create(gl::Backend::OSMesa);
    const gl::Functions& gl = context->functions();
    RenderTarget target;
    ASSERT_TRUE(target.create(gl, 320, 240));

    const Scene scene = crossingSheets(130);   // 33,802 triangles: more than one chunk
    FrameState frame;
    frame.camera.target = glm::dvec3(0.0);
    frame.camera.distance = 30.0;
    frame.camera.pitch = -0.6;
    frame.camera.yaw = 0.4;
    frame.width = 320;
    frame.height = 240;
    frame.framebuffer = target.framebuffer;
    frame.sceneRadius = 15.0;
    frame.style.showRays = false;
    frame.style.cutaway = false;

    QImage whole, chunked;
    {
        ViewportRenderer renderer(gl);
        renderer.setSceneFile(scene);
        EXPECT_FALSE(renderer.levelIncomplete());   // drawn whole unless asked
        renderer.render(frame);
        whole = readBack(gl, target);
    }
    QImage empty;
    {
        ViewportRenderer renderer(gl);
        renderer.render(frame);
        empty = readBack(gl, target);
        renderer.setSceneFile(prepareLevelMesh(scene), true);
        EXPECT_TRUE(renderer.levelIncomplete());
        // The upload's frame draws none of it; then a chunk a frame until it is whole.
        renderer.render(frame);
        EXPECT_EQ(readBack(gl, target), empty);
        int frames = 0;
        while (renderer.levelIncomplete() && frames < 100) {
            renderer.render(frame);
            ++frames;
            if (renderer.levelIncomplete()) {
                const QImage partial = readBack(gl, target);
                EXPECT_NE(partial, empty) << "frame " << frames << " drew nothing";
                EXPECT_NE(partial, whole) << "frame " << frames << " drew everything";
            }
        }
        EXPECT_GE(frames, 2);
        EXPECT_LE(frames, 3);   // 202,812 vertices in chunks of 72,000
        chunked = readBack(gl, target);
        // A frame that changes the view draws it whole again, at once.
        frame.camera.yaw += 0.1;
        renderer.render(frame);
        EXPECT_FALSE(renderer.levelIncomplete());
        frame.camera.yaw -= 0.1;
        renderer.render(frame);
        EXPECT_EQ(readBack(gl, target), whole);
    }
    EXPECT_NE(whole, empty);
    EXPECT_EQ(chunked, whole) << "the chunked first draw ends on another picture";
    target.destroy(gl);
}
