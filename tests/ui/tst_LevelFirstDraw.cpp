// A newly opened level is prepared off the GUI thread and its first draw spread over frames
// (ViewportRenderer::setSceneFile(LevelMesh, true)): the picture it ends on must be the one a
// whole draw gives, pixel for pixel, with the depth test working across the chunks.
#include <cmath>
#include <cstdint>

#include <QImage>
#include <gtest/gtest.h>

#include "editor/Camera.h"
#include "RenderTestSupport.h"
#include "TestScenes.h"
#include "editor/ViewportRenderer.h"
#include "visibility/Scene.h"
#include "visibility/gl/HeadlessContext.h"

using namespace sightline;
using namespace sightline::ui;


TEST(LevelFirstDraw, InChunksOverFramesGivesTheWholeDrawsPicture)
{
    const auto context = gl::HeadlessContext::create(gl::Backend::OSMesa);
    const gl::Functions& gl = context->functions();
    RenderTarget target;
    ASSERT_TRUE(target.create(gl, 320, 240));

    const Scene scene = test::crossingSheets(130);   // 33,802 triangles: more than one chunk
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
        whole = test::readBack(gl, target);
    }
    QImage empty;
    {
        ViewportRenderer renderer(gl);
        renderer.render(frame);
        empty = test::readBack(gl, target);
        renderer.setSceneFile(prepareLevelMesh(scene), true);
        EXPECT_TRUE(renderer.levelIncomplete());
        // The upload's frame draws none of it; then a chunk a frame until it is whole.
        renderer.render(frame);
        EXPECT_EQ(test::readBack(gl, target), empty);
        int frames = 0;
        while (renderer.levelIncomplete() && frames < 100) {
            renderer.render(frame);
            ++frames;
            if (renderer.levelIncomplete()) {
                const QImage partial = test::readBack(gl, target);
                EXPECT_NE(partial, empty) << "frame " << frames << " drew nothing";
                EXPECT_NE(partial, whole) << "frame " << frames << " drew everything";
            }
        }
        EXPECT_GE(frames, 2);
        EXPECT_LE(frames, 3);   // 202,812 vertices in chunks of 72,000
        chunked = test::readBack(gl, target);
        // A frame that changes the view draws it whole again, at once.
        frame.camera.yaw += 0.1;
        renderer.render(frame);
        EXPECT_FALSE(renderer.levelIncomplete());
        frame.camera.yaw -= 0.1;
        renderer.render(frame);
        EXPECT_EQ(test::readBack(gl, target), whole);
    }
    EXPECT_NE(whole, empty);
    EXPECT_EQ(chunked, whole) << "the chunked first draw ends on another picture";
    target.destroy(gl);
}
