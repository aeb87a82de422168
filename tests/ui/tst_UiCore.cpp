// The editor's logic without a window: camera, picking, edits, gizmo, ray subsets, the document
// with undo and files, live visibility against the reference, and the headless screenshot.

#include <gtest/gtest.h>

#include <algorithm>
#include <condition_variable>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <numbers>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "editor/BackgroundSampler.h"
#include "editor/Camera.h"
#include "EditorDocument.h"
#include "editor/Gizmo.h"
#include "editor/LiveVisibility.h"
#include "editor/ObjectEdits.h"
#include "editor/ObjectFlags.h"
#include "editor/PatchPairFix.h"
#include "editor/PatchWarnings.h"
#include "editor/PvsDebugger.h"
#include "editor/PatchPresets.h"
#include "OffscreenRender.h"
#include "editor/Picking.h"
#include "editor/RayEnds.h"
#include "editor/SectionCutHandle.h"
#include "TestScenes.h"
#include "UiTestScene.h"
#include "editor/ViewSettings.h"
#include "ViewportController.h"
#include "editor/ViewportRenderer.h"
#include "plugins/SceneFormats.h"
#include "project/Project.h"
#include "project/SceneImport.h"
#include "base/Error.h"
#include "base/NpyFile.h"
#include "visibility/RayCastSampler.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::ui {
namespace {

using test::floorPatches;
using test::freshFolder;
using test::writeFloorObj;

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance)
{
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(Camera, PixelRaysAndProjectionAgree)
{
    Camera camera;
    camera.target = {1.0, 2.0, 3.0};
    camera.distance = 7.0;
    camera.yaw = 0.7;
    camera.pitch = -0.4;
    for (const glm::dvec2 pixel : {glm::dvec2(0, 0), glm::dvec2(640, 360), glm::dvec2(1279, 719), glm::dvec2(100, 600)}) {
        const Ray ray = pixelRay(camera, pixel.x, pixel.y, 1280, 720);
        const glm::dvec3 back = toPixels(camera, ray.origin + 5.0 * ray.direction, 1280, 720);
        EXPECT_NEAR(back.x, pixel.x, 1e-6);
        EXPECT_NEAR(back.y, pixel.y, 1e-6);
        EXPECT_GT(back.z, 0.0);
    }
    // The target is at the centre of the view.
    const glm::dvec3 centre = toPixels(camera, camera.target, 1280, 720);
    EXPECT_NEAR(centre.x, 640.0, 1e-9);
    EXPECT_NEAR(centre.y, 360.0, 1e-9);
}

TEST(Camera, FramedBoxIsInView)
{
    Camera camera;
    camera.yaw = -2.0;
    Bounds box;
    box.extend(glm::vec3(-3, 0, 2));
    box.extend(glm::vec3(5, 4, 9));
    frame(camera, box);
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 corner((k & 1) ? 5 : -3, (k & 2) ? 4 : 0, (k & 4) ? 9 : 2);
        const glm::dvec3 p = toPixels(camera, corner, 800, 800);
        EXPECT_GT(p.z, 0.0);
        EXPECT_GE(p.x, 0.0);
        EXPECT_LE(p.x, 800.0);
        EXPECT_GE(p.y, 0.0);
        EXPECT_LE(p.y, 800.0);
    }
}

// Navigation took the camera under the floor.
TEST(Camera, NavigationKeepsTheEyeAboveTheFloor)
{
    Camera camera;
    camera.target = {0, 0.5, 0};
    camera.distance = 10.0;
    camera.pitch = -0.3;
    for (int k = 0; k < 50; ++k) {
        orbit(camera, 0.0, -40.0);   // tilting the view up swings the eye down
        keepAbove(camera, 0.0, true);
        EXPECT_GE(camera.eye().y, -1e-9) << k;
    }
    EXPECT_NEAR(camera.eye().y, 0.0, 1e-6);   // it stopped at the floor, not before
    EXPECT_NEAR(camera.target.y, 0.5, 1e-12);   // orbiting leaves the target
    Camera flying = camera;
    fly(flying, {0.0, -5.0, 0.0});
    keepAbove(flying, 0.0, false);
    EXPECT_NEAR(flying.eye().y, 0.0, 1e-9);
    const Camera high = camera;
    Camera same = high;
    keepAbove(same, -100.0, true);   // far above the floor: untouched
    EXPECT_EQ(same.pitch, high.pitch);
    EXPECT_EQ(same.target, high.target);
}

TEST(Camera, OrbitKeepsTargetAndDistance)
{
    Camera camera;
    camera.target = {1, 1, 1};
    const double distance = camera.distance;
    orbit(camera, 120.0, -40.0);
    EXPECT_EQ(camera.target, glm::dvec3(1, 1, 1));
    EXPECT_NEAR(glm::length(camera.eye() - camera.target), distance, 1e-9);
    // Fly-look keeps the eye.
    const glm::dvec3 eye = camera.eye();
    look(camera, 50.0, 30.0);
    expectNear(camera.eye(), eye, 1e-9);
}

TEST(Picking, PatchOnSurfaceLiesOnTheHitSurfaceFacingTheViewer)
{
    const Scene scene = loadScene(writeFloorObj(freshFolder("picking")));
    const WorldTriangles triangles = worldTriangles(scene);
    const Ray ray{{1.0, 5.0, 2.0}, glm::normalize(glm::dvec3(0.2, -1.0, 0.1))};
    const auto hit = pickSurface(triangles, ray);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->point.y, 0.0, 1e-9);
    expectNear(hit->normal, {0, 1, 0}, 1e-12);   // facing the ray's origin, above the floor
    const Patch patch = patchOnSurface(*hit, 2.0, 1.0, 8, 4, 0.02);
    expectNear(patch.centre(), hit->point + glm::dvec3(0, 0.02, 0), 1e-12);
    expectNear(patch.normal(), {0, 1, 0}, 1e-12);
    EXPECT_NEAR(glm::length(patch.u), 2.0, 1e-12);
    EXPECT_NEAR(glm::length(patch.v), 1.0, 1e-12);
    EXPECT_EQ(patch.na, 8);
    EXPECT_EQ(patch.nb, 4);
    // From below, the normal flips to face the viewer.
    const auto under = pickSurface(triangles, {{1.0, -5.0, 2.0}, {0.0, 1.0, 0.0}});
    ASSERT_TRUE(under);
    expectNear(under->normal, {0, -1, 0}, 1e-12);
    EXPECT_FALSE(pickSurface(triangles, {{1.0, 5.0, 2.0}, {0.0, 1.0, 0.0}}));
}

TEST(Picking, PatchHitTest)
{
    const Patch source = floorPatches().first;
    EXPECT_TRUE(pickPatch(source, {{-3.0, 1.5, 0.0}, {1.0, 0.0, 0.0}}));
    EXPECT_FALSE(pickPatch(source, {{-3.0, 2.5, 0.0}, {1.0, 0.0, 0.0}}));
    EXPECT_FALSE(pickPatch(source, {{-3.0, 1.5, 0.0}, {-1.0, 0.0, 0.0}}));
}

TEST(ObjectEdits, RotateAndScaleKeepThePivot)
{
    const Patch source = floorPatches().first;
    const Patch turned = std::get<Patch>(rotated(source, {0, 1, 0}, 0.8));
    expectNear(turned.centre(), source.centre(), 1e-12);
    EXPECT_NEAR(glm::length(turned.u), 1.0, 1e-12);
    const Patch wide = std::get<Patch>(scaled(source, 0, 3.0));
    expectNear(wide.centre(), source.centre(), 1e-12);
    EXPECT_NEAR(glm::length(wide.u), 3.0, 1e-12);

    const glm::mat4 box = glm::translate(glm::mat4(1.0f), glm::vec3(2, 0, 1));
    const glm::mat4 spun = std::get<glm::mat4>(rotated(box, {0, 1, 0}, 1.0));
    expectNear(pivotOf(spun), {2, 0, 1}, 1e-6);
}

TEST(ObjectEdits, ComposeInvertsDecompose)
{
    Decomposed parts;
    parts.position = {1.5, -2.0, 3.25};
    parts.rotationDegrees = {20.0, -35.0, 60.0};
    parts.scale = {2.0, 0.5, 1.25};
    const Decomposed back = decompose(compose(parts));
    expectNear(back.position, parts.position, 1e-5);
    expectNear(back.rotationDegrees, parts.rotationDegrees, 1e-3);
    expectNear(back.scale, parts.scale, 1e-5);
}

TEST(Gizmo, PicksAndDragsAlongTheAxisUnderTheCursor)
{
    Camera camera;
    camera.target = {0, 0, 0};
    camera.distance = 10.0;
    camera.yaw = 0.6;
    camera.pitch = -0.5;
    const glm::mat4 box(1.0f);
    const GizmoFrame frame = gizmoFrame(box, GizmoMode::Move, camera);
    auto pixelOf = [&](const glm::dvec3& p) { return toPixels(camera, p, 1000, 800); };
    for (int axis = 0; axis < 3; ++axis) {
        glm::dvec3 dir(0.0);
        dir[axis] = 1.0;
        const glm::dvec3 grab = pixelOf(frame.pivot + 0.7 * frame.length * dir);
        EXPECT_EQ(pickGizmoAxis(frame, camera, grab.x, grab.y, 1000, 800), axis);
        // Dragging the cursor to where the grabbed point should go moves the box by that much.
        const GizmoDrag drag = beginGizmoDrag(GizmoMode::Move, axis, box, camera, grab.x, grab.y, 1000, 800);
        const glm::dvec3 to = pixelOf(frame.pivot + (0.7 * frame.length + 1.25) * dir);
        const glm::dvec3 moved = pivotOf(dragGizmo(drag, camera, to.x, to.y, 1000, 800));
        expectNear(moved, 1.25 * dir, 1e-4);
    }
    const glm::dvec3 far = pixelOf(frame.pivot + glm::dvec3(0, -3.0, 0));
    EXPECT_EQ(pickGizmoAxis(frame, camera, far.x, far.y, 1000, 800), -1);
}

// Snapping. A move lands the pivot on the grid along the dragged axis, a rotation
// turns by whole steps, a scale changes by whole 10% steps.
TEST(Gizmo, SnapsMovesToTheGridAndRotationsAndScalesToSteps)
{
    Camera camera;
    camera.distance = 10.0;
    camera.yaw = 0.6;
    camera.pitch = -0.5;
    const glm::mat4 box = glm::translate(glm::mat4(1.0f), glm::vec3(0.13f, 0.0f, 0.0f));   // off the grid
    const GizmoFrame frame = gizmoFrame(box, GizmoMode::Move, camera);
    auto pixelOf = [&](const glm::dvec3& p) { return toPixels(camera, p, 1000, 800); };
    const GizmoSnap snap{0.25, std::numbers::pi / 12.0, 0.1};
    const glm::dvec3 grab = pixelOf(frame.pivot + 0.7 * frame.length * glm::dvec3(1, 0, 0));
    const GizmoDrag drag = beginGizmoDrag(GizmoMode::Move, 0, box, camera, grab.x, grab.y, 1000, 800);
    for (double by : {0.05, 0.2, 0.61, 1.37, -0.9}) {
        const glm::dvec3 to = pixelOf(frame.pivot + (0.7 * frame.length + by) * glm::dvec3(1, 0, 0));
        const glm::dvec3 free = pivotOf(dragGizmo(drag, camera, to.x, to.y, 1000, 800));
        const glm::dvec3 snapped = pivotOf(dragGizmo(drag, camera, to.x, to.y, 1000, 800, snap));
        EXPECT_NEAR(snapped.x, std::round(free.x / 0.25) * 0.25, 1e-5) << by;
        EXPECT_NEAR(snapped.y, 0.0, 1e-6);
        EXPECT_NEAR(snapped.z, 0.0, 1e-6);
    }
    const GizmoDrag turn = beginGizmoDrag(GizmoMode::Rotate, 1, box, camera, 500, 400, 1000, 800);
    for (double dx : {7.0, 40.0, 133.0}) {
        const glm::mat4 m = std::get<glm::mat4>(dragGizmo(turn, camera, 500 + dx, 400, 1000, 800, snap));
        const double angle = std::atan2(double(m[0][2]), double(m[0][0]));   // about +Y
        const double steps = angle / snap.angle;
        EXPECT_NEAR(steps, std::round(steps), 1e-4) << dx;
    }
    const GizmoFrame scaleFrame = gizmoFrame(box, GizmoMode::Scale, camera);
    const glm::dvec3 handle = pixelOf(scaleFrame.pivot + 0.7 * scaleFrame.length * scaleFrame.axes[0]);
    const GizmoDrag stretch = beginGizmoDrag(GizmoMode::Scale, 0, box, camera, handle.x, handle.y, 1000, 800);
    const glm::dvec3 to = pixelOf(scaleFrame.pivot + (0.7 + 0.37) * scaleFrame.length * scaleFrame.axes[0]);
    const glm::mat4 m = std::get<glm::mat4>(dragGizmo(stretch, camera, to.x, to.y, 1000, 800, snap));
    const double factor = glm::length(glm::dvec3(m[0]));
    EXPECT_NEAR(factor * 10.0, std::round(factor * 10.0), 1e-4);
    EXPECT_GT(factor, 1.25);
}

// Orthographic views. Pixel rays are parallel to the view, start on the eye's plane,
// and land where the projection matrix draws them; the gizmo picks and drags in them.
TEST(Camera, OrthographicRaysAreParallelAndMeetTheDrawnPixels)
{
    for (const bool orthographic : {false, true}) {
        Camera camera;
        camera.target = {1.0, 2.0, 3.0};
        camera.distance = 7.0;
        camera.yaw = 0.7;
        camera.pitch = -0.4;
        camera.orthographic = orthographic;
        const glm::mat4 viewProj = camera.projection(1280.0 / 720.0, 20.0) * camera.view();
        for (const glm::dvec2 pixel : {glm::dvec2(0, 0), glm::dvec2(640, 360), glm::dvec2(1279, 719), glm::dvec2(100, 600)}) {
            const Ray ray = pixelRay(camera, pixel.x, pixel.y, 1280, 720);
            if (orthographic) {
                expectNear(ray.direction, camera.forward(), 1e-12);
                EXPECT_NEAR(glm::dot(ray.origin - camera.eye(), camera.forward()), 0.0, 1e-9);
            }
            for (double along : {0.5, 5.0, 12.0}) {
                const glm::dvec3 point = ray.origin + along * ray.direction;
                const glm::dvec3 back = toPixels(camera, point, 1280, 720);
                EXPECT_NEAR(back.x, pixel.x, 1e-6);
                EXPECT_NEAR(back.y, pixel.y, 1e-6);
                EXPECT_NEAR(back.z, along * glm::dot(ray.direction, camera.forward()), 1e-9);
                const glm::vec4 clip = viewProj * glm::vec4(glm::vec3(point), 1.0f);   // what the GPU draws
                EXPECT_NEAR((clip.x / clip.w + 1.0) * 640.0, pixel.x, 0.05) << orthographic;
                EXPECT_NEAR((1.0 - clip.y / clip.w) * 360.0, pixel.y, 0.05) << orthographic;
            }
        }
    }
    // The scale at the target is kept when switching; zoom and pan work on it.
    Camera camera;
    camera.distance = 10.0;
    Camera ortho = camera;
    ortho.orthographic = true;
    const glm::dvec3 beside = camera.target + 2.0 * camera.right();
    EXPECT_NEAR(toPixels(camera, beside, 800, 600).x, toPixels(ortho, beside, 800, 600).x, 1e-9);
    dolly(ortho, 1.0);
    EXPECT_NEAR(ortho.halfHeight(), 0.85 * camera.halfHeight(), 1e-12);
    const glm::dvec3 before = toPixels(ortho, beside, 800, 600);
    pan(ortho, 30.0, -20.0, 600);
    const glm::dvec3 after = toPixels(ortho, beside, 800, 600);
    EXPECT_NEAR(after.x - before.x, 30.0, 1e-9);
    EXPECT_NEAR(after.y - before.y, -20.0, 1e-9);
    const Camera top = axisView(AxisView::Top, Bounds{glm::vec3(-1.0f), glm::vec3(1.0f)});
    EXPECT_TRUE(top.orthographic);
    EXPECT_FALSE(lookThrough({0, 0, 0}, {0, 0, 1}, {0, 0, 5}, 0.5).orthographic);
    // Kept in the project's view, and absent (perspective) in files that predate it.
    EXPECT_TRUE(cameraFromJson(cameraToJson(top))->orthographic);
    EXPECT_FALSE(cameraToJson(camera).contains("orthographic"));
    EXPECT_FALSE(cameraFromJson(cameraToJson(camera))->orthographic);
}

TEST(Gizmo, PicksAndDragsInAnOrthographicView)
{
    Camera camera;
    camera.distance = 10.0;
    camera.yaw = 0.6;
    camera.pitch = -0.5;
    camera.orthographic = true;
    const glm::mat4 box = glm::translate(glm::mat4(1.0f), glm::vec3(3.0f, 0.0f, -2.0f));   // off the view's centre
    const GizmoFrame frame = gizmoFrame(box, GizmoMode::Move, camera);
    EXPECT_NEAR(frame.length, 0.15 * camera.distance, 1e-12);   // the same size on screen wherever it is
    auto pixelOf = [&](const glm::dvec3& p) { return toPixels(camera, p, 1000, 800); };
    for (int axis = 0; axis < 3; ++axis) {
        glm::dvec3 dir(0.0);
        dir[axis] = 1.0;
        const glm::dvec3 grab = pixelOf(frame.pivot + 0.7 * frame.length * dir);
        EXPECT_EQ(pickGizmoAxis(frame, camera, grab.x, grab.y, 1000, 800), axis);
        const GizmoDrag drag = beginGizmoDrag(GizmoMode::Move, axis, box, camera, grab.x, grab.y, 1000, 800);
        const glm::dvec3 to = pixelOf(frame.pivot + (0.7 * frame.length - 0.8) * dir);
        expectNear(pivotOf(dragGizmo(drag, camera, to.x, to.y, 1000, 800)), frame.pivot - 0.8 * dir, 1e-6);
    }
}

namespace {

/// A view from above and aside, as the cut's handle tests look at the level.
Camera obliqueView()
{
    Camera camera;
    camera.target = {2.0, 1.0, -3.0};
    camera.distance = 12.0;
    camera.yaw = 0.4;
    camera.pitch = -0.7;
    return camera;
}

} // namespace

// The section cut's handle sits on the cut plane in view, and a drag moves the cut
// along Y under the cursor (by the cursor's vertical motion when the view looks along Y).
TEST(SectionCutHandle, SitsOnTheCutAndFollowsTheCursor)
{
    const Camera camera = obliqueView();
    const auto handle = cutHandle(camera, 2.5, 800, 600);
    ASSERT_TRUE(handle);
    EXPECT_EQ(handle->point.y, 2.5);
    const glm::dvec3 grip = toPixels(camera, handle->point, 800, 600);
    EXPECT_GT(grip.x, 600.0) << "right of the centre, clear of the gizmo";
    EXPECT_TRUE(pickCutHandle(*handle, camera, grip.x, grip.y + 3.0, 800, 600));
    EXPECT_FALSE(pickCutHandle(*handle, camera, grip.x - 60.0, grip.y, 800, 600));
    for (double by : {0.7, -1.3}) {
        const CutDrag drag = beginCutDrag(*handle, camera, grip.x, grip.y, 800, 600);
        const glm::dvec3 to = toPixels(camera, handle->point + glm::dvec3(0.0, by, 0.0), 800, 600);
        EXPECT_NEAR(dragCut(drag, camera, to.x, to.y, 800, 600), 2.5 + by, 1e-6);
        EXPECT_NEAR(dragCut(drag, camera, to.x, to.y, 800, 600, 0.25), std::round((2.5 + by) / 0.25) * 0.25, 1e-12);
    }
    EXPECT_FALSE(cutHandle(camera, 500.0, 800, 600)) << "a cut far above the view has no handle in it";

    Camera top = axisView(AxisView::Top, Bounds{glm::vec3(-5.0f), glm::vec3(5.0f)});
    for (const bool orthographic : {true, false}) {
        top.orthographic = orthographic;
        const auto above = cutHandle(top, 1.0, 800, 600);
        ASSERT_TRUE(above);
        const glm::dvec3 p = toPixels(top, above->point, 800, 600);
        EXPECT_TRUE(pickCutHandle(*above, top, p.x, p.y, 800, 600));
        const CutDrag drag = beginCutDrag(*above, top, p.x, p.y, 800, 600);
        // 50 pixels up the screen: raised by 50 pixels' worth of metres at the plane's depth.
        const double depth = orthographic ? top.distance : glm::dot(above->point - top.eye(), top.forward());
        EXPECT_NEAR(dragCut(drag, top, p.x, p.y - 50.0, 800, 600), 1.0 + 50.0 * 2.0 * depth * std::tan(top.fovY / 2.0) / 600.0, 1e-9);
    }
}

// The handle keeps clear of what the designer clicks: where its usual spot (right of the target)
// would cover a patch or the gizmo, it takes another; it covered the demo's receiver in the
// opening view, and a click on the receiver grabbed the cut instead.
TEST(SectionCutHandle, KeepsClearOfThePatchesAndTheGizmo)
{
    const Camera camera = obliqueView();
    const auto usual = cutHandle(camera, 2.5, 800, 600);
    ASSERT_TRUE(usual);
    const auto box = screenBox(camera, {usual->point + glm::dvec3(0.0, -0.3, 0.0), usual->point + glm::dvec3(0.4, 0.3, 0.2)},
                               800, 600, 8.0);
    ASSERT_TRUE(box);
    const glm::dvec3 usualGrip = toPixels(camera, usual->point, 800, 600);
    ASSERT_TRUE(usualGrip.x >= box->x0 && usualGrip.x <= box->x1 && usualGrip.y >= box->y0 && usualGrip.y <= box->y1);
    const auto moved = cutHandle(camera, 2.5, 800, 600, {*box});
    ASSERT_TRUE(moved);
    EXPECT_EQ(moved->point.y, 2.5) << "still on the cut";
    const glm::dvec3 grip = toPixels(camera, moved->point, 800, 600);
    EXPECT_TRUE(grip.x < box->x0 - 16.0 || grip.x > box->x1 + 16.0 || grip.y < box->y0 - 16.0 || grip.y > box->y1 + 16.0)
        << "grip at " << grip.x << ", " << grip.y;
    EXPECT_TRUE(grip.x > 24.0 && grip.x < 776.0 && grip.y > 24.0 && grip.y < 576.0) << "in view";
    EXPECT_TRUE(pickCutHandle(*moved, camera, grip.x, grip.y, 800, 600));
    // Nothing in its way: the usual spot. Everything in its way: still a handle, the usual one.
    EXPECT_EQ(cutHandle(camera, 2.5, 800, 600, {})->point, usual->point);
    EXPECT_EQ(cutHandle(camera, 2.5, 800, 600, {ScreenBox{0.0, 0.0, 800.0, 600.0}})->point, usual->point);
}

// World or local space. In local space the handles are the object's own axes, a move
// goes along them (snapping the distance moved), a turn is about them.
TEST(Gizmo, LocalSpaceMovesAndTurnsAlongTheObjectsOwnAxes)
{
    Camera camera;
    camera.distance = 10.0;
    camera.yaw = 0.6;
    camera.pitch = -0.5;
    const glm::mat4 box = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.4f, 0.0f, 0.0f)), 0.5f, glm::vec3(0, 1, 0));
    const glm::dvec3 ownX(std::cos(0.5), 0.0, -std::sin(0.5));
    EXPECT_EQ(gizmoFrame(box, GizmoMode::Move, camera).axes[0], glm::dvec3(1, 0, 0));
    const GizmoFrame local = gizmoFrame(box, GizmoMode::Move, camera, GizmoSpace::Local);
    expectNear(local.axes[0], ownX, 1e-6);
    auto pixelOf = [&](const glm::dvec3& p) { return toPixels(camera, p, 1000, 800); };
    const glm::dvec3 grab = pixelOf(local.pivot + 0.7 * local.length * ownX);
    ASSERT_EQ(pickGizmoAxis(local, camera, grab.x, grab.y, 1000, 800), 0);
    const GizmoDrag drag = beginGizmoDrag(GizmoMode::Move, 0, box, camera, grab.x, grab.y, 1000, 800, GizmoSpace::Local);
    const glm::dvec3 to = pixelOf(local.pivot + (0.7 * local.length + 1.3) * ownX);
    expectNear(pivotOf(dragGizmo(drag, camera, to.x, to.y, 1000, 800)), local.pivot + 1.3 * ownX, 1e-5);
    // Snapped: 1.3 m becomes 1.25 m along the axis, wherever the pivot started.
    expectNear(pivotOf(dragGizmo(drag, camera, to.x, to.y, 1000, 800, GizmoSnap{0.25, 0.0, 0.0})), local.pivot + 1.25 * ownX, 1e-5);
    // A turn about the local Z axis keeps the object's own Y in the plane it spans with Z... and its Z.
    const GizmoDrag turn = beginGizmoDrag(GizmoMode::Rotate, 2, box, camera, 500, 400, 1000, 800, GizmoSpace::Local);
    const glm::mat4 turned = std::get<glm::mat4>(dragGizmo(turn, camera, 540, 400, 1000, 800));
    expectNear(glm::normalize(glm::dvec3(turned[2])), glm::normalize(glm::dvec3(box[2])), 1e-6);
    EXPECT_GT(glm::length(glm::dvec3(turned[0]) - glm::dvec3(box[0])), 0.1);
}

// Size presets. A wall's patch keeps its bottom edge (it stands on the floor), whichever
// way its edges point; a floor's keeps its centre.
TEST(PatchPresets, ResizeKeepsAWallPatchsBottomEdge)
{
    const auto bottomMiddle = [](const Patch& p) {
        glm::dvec3 corners[4] = {p.corner, p.corner + p.u, p.corner + p.v, p.corner + p.u + p.v};
        std::sort(std::begin(corners), std::end(corners), [](const glm::dvec3& a, const glm::dvec3& b) { return a.y < b.y; });
        return 0.5 * (corners[0] + corners[1]);
    };
    Patch up;   // a wall's patch: u across, v up
    up.corner = {1.0, 0.02, -3.0};
    up.u = {0.0, 0.0, 1.0};
    up.v = {0.0, 1.0, 0.0};
    Patch down = up;   // v pointing down, from the top corner
    down.corner = up.corner + up.v;
    down.v = -up.v;
    down.u = -up.u;
    down.corner += up.u;
    Patch sideways = up;   // u up, v across
    sideways.u = up.v;
    sideways.v = up.u;
    sideways.corner = up.corner;
    for (const Patch& wall : {up, down, sideways}) {
        const Patch door = resizedPatch(wall, 0.9, 2.1);
        expectNear(bottomMiddle(door), bottomMiddle(wall), 1e-12);
        const glm::dvec3 vertical = std::abs(door.u.y) > std::abs(door.v.y) ? door.u : door.v;
        EXPECT_NEAR(glm::length(vertical), 2.1, 1e-12);
        expectNear(door.normal(), wall.normal(), 1e-12);
        EXPECT_EQ(door.na, wall.na);
        EXPECT_EQ(presetOf(door), std::optional<std::size_t>(0));
    }
    EXPECT_FALSE(presetOf(up)) << "1 x 1 m is custom";
    Patch floor;
    floor.corner = {0.0, 0.0, 0.0};
    floor.u = {2.0, 0.0, 0.0};
    floor.v = {0.0, 0.0, -2.0};
    const Patch player = resizedPatch(floor, 0.6, 1.8);
    expectNear(player.centre(), floor.centre(), 1e-12);
    EXPECT_NEAR(glm::length(player.u), 0.6, 1e-12);
    EXPECT_NEAR(glm::length(player.v), 1.8, 1e-12);
}

// Hide and lock are kept in the project (docs/design.md §3: keys the CLI keeps), each
// undoable; an occluder's flags live in its own entry and move with it; other shapes read as none.
TEST(ObjectFlags, AreKeptInTheProjectAndFollowTheirObjects)
{
    const std::filesystem::path folder = freshFolder("object-flags");
    const std::filesystem::path project = test::copyDemoProject(folder);
    EditorDocument document;
    document.open(project);
    const ObjectRef wall{ObjectKind::SceneObject, 2}, receiver{ObjectKind::Receiver, 0};
    document.setFlags(wall, {true, false}, "hide");
    document.setFlags(receiver, {false, true}, "lock");
    OccluderSpec crate;
    crate.name = "crate";
    crate.mesh = "box";
    document.addOccluder(crate);
    document.addOccluder(crate);
    document.setFlags({ObjectKind::Occluder, 1}, {true, true}, "hide and lock");
    EXPECT_TRUE(document.flags(wall).hidden);
    EXPECT_FALSE(document.isShown(wall));
    EXPECT_TRUE(document.isShown(receiver));
    EXPECT_FALSE(document.isPickable(receiver));
    EXPECT_EQ(document.hiddenMask(ObjectKind::Occluder), (std::vector<std::uint8_t>{0, 1}));
    // The first crate deleted: the second's flags go with it.
    document.select({ObjectKind::Occluder, 0});
    document.removeSelected();
    EXPECT_EQ(document.flags({ObjectKind::Occluder, 0}), (ObjectFlags{true, true}));
    document.save(folder / "flags.json");
    const nlohmann::json file = nlohmann::json::parse(std::ifstream(folder / "flags.json"));
    EXPECT_EQ(file.at("editor").at("hidden").at("instances"), nlohmann::json::array({2}));
    EXPECT_EQ(file.at("editor").at("locked").at("patches"), nlohmann::json::array({"receiver"}));
    EXPECT_FALSE(file.at("editor").contains("hidden") && file.at("editor").at("hidden").contains("patches"));
    EXPECT_EQ(file.at("occluders").at(0).at("editor"), (nlohmann::json{{"hidden", true}, {"locked", true}}));
    EditorDocument reopened;
    reopened.open(folder / "flags.json");
    EXPECT_EQ(reopened.flags(wall), (ObjectFlags{true, false}));
    EXPECT_EQ(reopened.flags(receiver), (ObjectFlags{false, true}));
    EXPECT_EQ(reopened.flags({ObjectKind::Occluder, 0}), (ObjectFlags{true, true}));
    // Undo takes each back; nothing left, the keys go.
    while (document.undoStack()->canUndo())
        document.undoStack()->undo();
    EXPECT_EQ(document.flags(wall), ObjectFlags{});
    EXPECT_FALSE(document.editorSettings().contains("hidden"));
    EXPECT_FALSE(document.editorSettings().contains("locked"));
    // Isolation: view state, ended by a change of the occluder list.
    document.setIsolated(receiver);
    EXPECT_FALSE(document.isShown(wall));
    EXPECT_EQ(document.hiddenMask(ObjectKind::SceneObject), std::vector<std::uint8_t>(document.sceneFile().instances.size(), 1));
    document.addOccluder(crate);
    document.setIsolated({ObjectKind::Occluder, 0});
    document.undoStack()->undo();
    EXPECT_FALSE(document.isolated());
    // Values of another shape read as no flag and are replaced when written.
    nlohmann::json odd = {{"hidden", 3}, {"locked", {{"instances", "all"}}}, {"camera", 1}};
    EXPECT_EQ(settingsFlags(odd, wall), ObjectFlags{});
    setSettingsFlags(odd, wall, {true, true});
    EXPECT_EQ(settingsFlags(odd, wall), (ObjectFlags{true, true}));
    EXPECT_EQ(odd.at("camera"), 1);
}

TEST(RaySubset, AllRaysUnderTheCapAndASpreadSubsetAboveIt)
{
    const RaySubset all = raySubset(64, 100, 10000);
    EXPECT_EQ(all.count(), 6400u);
    std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
    for (std::uint32_t k = 0; k < all.count(); ++k)
        seen.insert(subsetRay(all, k));
    EXPECT_EQ(seen.size(), 6400u);

    for (const auto& [sources, receivers, cap] : {std::tuple{1024, 1024, 4096}, std::tuple{1024, 262144, 65536}, std::tuple{3, 5, 7}}) {
        const RaySubset s = raySubset(sources, receivers, cap);
        EXPECT_LE(s.count(), std::uint64_t(cap));
        EXPECT_GE(s.count(), std::uint64_t(cap) / 2) << "the cap is used";
        std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
        std::set<std::uint32_t> receiversUsed;
        for (std::uint32_t k = 0; k < s.count(); ++k) {
            const auto [j, i] = subsetRay(s, k);
            EXPECT_LT(j, std::uint32_t(receivers));
            EXPECT_LT(i, std::uint32_t(sources));
            pairs.insert({j, i});
            receiversUsed.insert(j);
        }
        EXPECT_EQ(pairs.size(), s.count()) << "no ray drawn twice";
        EXPECT_EQ(receiversUsed.size(), s.receivers);
    }
}

TEST(EditorDocument, EveryEditIsUndoable)
{
    EditorDocument document;
    const auto [source, receiver] = floorPatches();
    document.setState({ObjectKind::Source, 0}, source, "place");
    document.setState({ObjectKind::Receiver, 0}, receiver, "place");
    EXPECT_TRUE(document.isModified());

    OccluderSpec box;
    box.name = "crate";
    box.mesh = "box";
    box.transform = glm::translate(glm::mat4(1.0f), glm::vec3(3, 1.5, 0));
    document.addOccluder(box);
    ASSERT_EQ(document.project().occluders.size(), 1u);
    EXPECT_EQ(document.selection(), (ObjectRef{ObjectKind::Occluder, 0}));
    EXPECT_EQ(document.scene().instances.size(), 1u);

    document.setState({ObjectKind::Occluder, 0}, glm::translate(glm::mat4(1.0f), glm::vec3(3, 5, 0)), "move");
    document.duplicateSelected();
    ASSERT_EQ(document.project().occluders.size(), 2u);
    EXPECT_EQ(document.project().occluders[1].name, "crate copy");
    document.removeSelected();
    EXPECT_EQ(document.project().occluders.size(), 1u);

    QUndoStack& undo = *document.undoStack();
    undo.undo();   // delete
    EXPECT_EQ(document.project().occluders.size(), 2u);
    undo.undo();   // duplicate
    undo.undo();   // move
    EXPECT_FLOAT_EQ(document.project().occluders[0].transform[3].y, 1.5f);
    undo.undo();   // add
    EXPECT_TRUE(document.project().occluders.empty());
    EXPECT_TRUE(document.scene().instances.empty());
    undo.undo();
    undo.undo();
    EXPECT_FALSE(document.isModified());
    undo.redo();
    EXPECT_EQ(document.project().source.corner, source.corner);
}

TEST(EditorDocument, SaveAndReopenRoundTripsAndRebasesPaths)
{
    const auto folder = freshFolder("document-save");
    const auto mesh = writeFloorObj(folder / "levels");
    EditorDocument document;
    document.open(mesh);
    EXPECT_EQ(document.project().scene, "floor.obj");
    EXPECT_NO_THROW(validatePatchPair(document.project().source, document.project().receiver))
        << "a level opened as a mesh gets a valid default pair";
    OccluderSpec box;
    box.name = "crate";
    box.mesh = "box";
    document.addOccluder(box);
    document.setState({ObjectKind::SceneObject, 0}, glm::translate(glm::mat4(1.0f), glm::vec3(0, -1, 0)), "lower");
    nlohmann::json settings;
    settings["camera"] = cameraToJson(Camera{});
    document.setEditorSettings(settings);

    nlohmann::json extra = document.project().extra;   // a light texture beside the level
    extra["light"] = {{"texture", "glow.png"}};
    Project withLight = document.project();
    withLight.extra = extra;
    std::filesystem::create_directories(folder / "projects");
    saveProject(withLight, folder / "levels" / "lit.json");
    EditorDocument lit;
    lit.open(folder / "levels" / "lit.json");
    lit.save(folder / "projects" / "lit.json");
    EXPECT_EQ(lit.project().extra["light"]["texture"],
              std::filesystem::absolute(folder / "levels" / "glow.png").lexically_normal().string())
        << "Save As into another folder rebases the light's texture too";

    document.save(folder / "projects" / "level.json");
    EXPECT_FALSE(document.isModified());
    // The relative form would climb out of the project's folder, which loading refuses
    // (base/PathRule.h): the editor writes the path absolute instead.
    EXPECT_EQ(document.project().scene, std::filesystem::absolute(folder / "levels" / "floor.obj").lexically_normal().string());

    EditorDocument again;
    again.open(folder / "projects" / "level.json");
    EXPECT_EQ(toJson(again.project()), toJson(document.project()));
    EXPECT_FLOAT_EQ(again.sceneFile().instances[0].transform[3].y, -1.0f);
    EXPECT_TRUE(cameraFromJson(again.editorSettings().at("camera")));
    // The CLI's scene is the editor's scene.
    EXPECT_EQ(worldTriangles(buildScene(loadProject(folder / "projects" / "level.json"))).vertices,
              worldTriangles(again.scene()).vertices);
    // Saved in place, a path stays as the user wrote it (here an allowed "../" one).
    Project written = again.project();
    written.scene = "../levels/floor.obj";
    written.allowOutsidePaths = true;
    saveProject(written, folder / "projects" / "level.json");
    EditorDocument inPlace;
    inPlace.setAllowOutsidePaths(true);
    inPlace.open(folder / "projects" / "level.json");
    inPlace.save(folder / "projects" / "level.json");
    EXPECT_EQ(loadProject(folder / "projects" / "level.json", {.allowOutsidePaths = true}).scene, "../levels/floor.obj");
}

TEST(EditorDocument, AFileThatFailsToOpenLeavesTheDocumentAsItWas)
{
    const auto folder = freshFolder("document-bad");
    EditorDocument document;
    document.open(writeFloorObj(folder));
    const nlohmann::json before = toJson(document.project());
    std::ofstream(folder / "broken.json") << "{\"version\": 1, \"source\": 3}";
    EXPECT_THROW(document.open(folder / "broken.json"), Error);
    std::ofstream(folder / "missing-mesh.json")
        << R"({"version": 1, "scene": "nowhere.glb", "source": {"corner": [0,0,0], "u": [1,0,0], "v": [0,1,0]},
               "receiver": {"corner": [0,0,5], "u": [1,0,0], "v": [0,1,0]}})";
    EXPECT_THROW(document.open(folder / "missing-mesh.json"), Error);
    EXPECT_EQ(toJson(document.project()), before);
}

TEST(EditorDocument, PathsOutsideTheProjectsFolderNeedTheSetting)
{
    const auto folder = freshFolder("document-outside");
    writeFloorObj(folder / "levels");
    std::filesystem::create_directories(folder / "projects");
    std::ofstream(folder / "projects" / "p.json")
        << R"({"version": 1, "scene": "../levels/floor.obj", "source": {"corner": [0,0,0], "u": [1,0,0], "v": [0,1,0]},
               "receiver": {"corner": [0,0,5], "u": [1,0,0], "v": [0,1,0]}})";
    EditorDocument document;
    try {
        document.open(folder / "projects" / "p.json");
        FAIL() << "a scene outside the project's folder was read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("leaves the project's folder"), std::string::npos) << e.what();
    }
    document.setAllowOutsidePaths(true);   // File > Allow Project Paths Outside Its Folder
    EXPECT_NO_THROW(document.open(folder / "projects" / "p.json"));
    EXPECT_EQ(document.sceneFile().instances.size(), 1u);
}

TEST(LiveVisibility, MatchesTheReferenceAndExplainsInvalidPairs)
{
    const std::filesystem::path project = test::copyDemoProject(freshFolder("live"));
    EditorDocument document;
    document.open(project);
    OccluderSpec box;
    box.mesh = "box";
    box.transform = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(12.0f, 1.2f, 5.0f)), glm::vec3(0.5f, 1.0f, 0.8f));
    document.addOccluder(box);

    LiveVisibility live;
    live.setScene(document.scene());
    const Project& p = document.project();
    const VisibilityResult result = live.sample(p.source, p.receiver);
    ASSERT_TRUE(result.valid) << result.error;
    const HiddenSampleMap reference = RayCastScene(buildScene(p)).sample(p.source, p.receiver);
    EXPECT_LE(result.map.differenceCount(reference), result.rays / 10000) << ">= 99.99% agreement (grazing rays)";

    Patch crossing = p.receiver;   // a floor patch through the source's plane
    crossing.corner = p.source.corner + glm::dvec3(-1.0, 0.0, -1.0);
    crossing.u = {2.0, 0.0, 0.0};
    crossing.v = {0.0, 0.0, 1.0};
    const VisibilityResult invalid = live.sample(p.source, crossing);
    EXPECT_FALSE(invalid.valid);
    EXPECT_FALSE(invalid.error.empty());
    EXPECT_EQ(invalid.rays, 0u);
}

TEST(LiveVisibility, UsesTheProjectsReceiverHeightsAndRefusesUnreadableOnes)
{
    // The demo's receiver raised by a height map read from the project (§8): the live CPU answer
    // is the reference's with the same heights, and differs from the flat one.
    const std::filesystem::path folder = freshFolder("live-heights");
    const std::filesystem::path file = test::copyDemoProject(folder);
    EditorDocument document;
    document.open(file);
    Project p = document.project();
    std::vector<float> metres(std::size_t(p.receiver.sampleCount()));
    for (int j = 0; j < p.receiver.sampleCount(); ++j)
        metres[std::size_t(j)] = 0.3f * float(j % p.receiver.na) / float(p.receiver.na);
    writeFloatNpy(metres, p.receiver.nb, p.receiver.na, folder / "heights.npy");
    p.extra["receiver_heights"] = {{"npy", "heights.npy"}};

    LiveVisibility live;
    live.setScene(document.scene());
    live.loadReceiverHeights(p, "demo.json");
    ASSERT_EQ(live.receiverHeights().metres.size(), std::size_t(p.receiver.sampleCount()));
    const VisibilityResult bumpy = live.sample(p.source, p.receiver);
    ASSERT_TRUE(bumpy.valid) << bumpy.error;
    RayCastOptions options;
    options.heights = &live.receiverHeights();
    const RayCastScene reference(buildScene(p));
    const HiddenSampleMap expected = reference.sample(p.source, p.receiver, options);
    EXPECT_LE(bumpy.map.differenceCount(expected), bumpy.rays / 10000);
    EXPECT_GT(expected.differenceCount(reference.sample(p.source, p.receiver)), bumpy.rays / 1000) << "the heights matter";

    p.extra["receiver_heights"] = {{"npy", "missing.npy"}};
    live.loadReceiverHeights(p, "demo.json");
    const VisibilityResult refused = live.sample(p.source, p.receiver);
    EXPECT_FALSE(refused.valid);
    EXPECT_NE(refused.error.find("missing.npy"), std::string::npos) << refused.error;
    p.extra.erase("receiver_heights");
    live.loadReceiverHeights(p, "demo.json");
    EXPECT_TRUE(live.sample(p.source, p.receiver).valid);
}

/// The floor level with floorPatches() placed on it.
void openFloorWithPatches(EditorDocument& document, const std::filesystem::path& folder)
{
    document.open(writeFloorObj(folder));
    const auto [source, receiver] = floorPatches();
    document.setState({ObjectKind::Source, 0}, source, "place");
    document.setState({ObjectKind::Receiver, 0}, receiver, "place");
}

/// Is this pixel the ray colour (yellow) rather than grey floor or dark background?
bool yellowish(QRgb c) { return qRed(c) > qBlue(c) + 40 && qGreen(c) > qBlue(c) + 30; }

TEST(OffscreenRender, RaysAreDrawnWhereTheShaftIsOpenAndNotWhereItIsCut)
{
    const auto folder = freshFolder("offscreen");
    EditorDocument document;
    openFloorWithPatches(document, folder);
    const auto [source, receiver] = floorPatches();
    const Camera camera = shaftView(source, receiver);
    ViewStyle style;
    style.rayCap = 1 << 20;
    style.freeColour = {1.0f, 0.85f, 0.15f, 1.0f};   // opaque, for a crisp check

    // A point inside the shaft, a quarter of the way from the source.
    const glm::dvec3 inside = source.centre() + 0.25 * (receiver.centre() - source.centre());
    const glm::dvec3 pixel = toPixels(camera, inside, 320, 240);
    const OffscreenResult open = renderOffscreen(document, camera, style, 320, 240);
    ASSERT_EQ(open.image.size(), QSize(320, 240));
    EXPECT_EQ(open.visibility.blocked, 0u);
    EXPECT_EQ(open.raysDrawn, 256u * 256u);
    EXPECT_TRUE(yellowish(open.image.pixel(int(pixel.x), int(pixel.y))));
    // Outside the shaft: no rays.
    const glm::dvec3 beside = toPixels(camera, inside + glm::dvec3(0.0, 2.5, 0.0), 320, 240);
    EXPECT_FALSE(yellowish(open.image.pixel(int(beside.x), int(beside.y))));

    style.showRays = false;
    EXPECT_FALSE(yellowish(renderOffscreen(document, camera, style, 320, 240).image.pixel(int(pixel.x), int(pixel.y))));
    style.showRays = true;

    // A wall across the whole shaft at x = 3 blocks every ray: none drawn, though the point
    // lies before the wall.
    OccluderSpec wall;
    wall.mesh = "plane";
    wall.transform = glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(3, 1.5f, 0)), glm::radians(90.0f), glm::vec3(0, 0, 1)),
                                glm::vec3(10.0f));
    document.addOccluder(wall);
    const OffscreenResult cut = renderOffscreen(document, camera, style, 320, 240);
    EXPECT_EQ(cut.visibility.blocked, cut.visibility.rays);
    EXPECT_FALSE(yellowish(cut.image.pixel(int(pixel.x), int(pixel.y))));
}

} // namespace

/// Is this pixel the placed occluders' violet (shaded), rather than grey, yellow or background?
bool violet(QRgb c) { return qBlue(c) > qGreen(c) + 30 && qRed(c) > qGreen(c) + 10; }

// Placed occluders were sampled but never drawn: "no cut" reached the shader as infinite clip
// distances and llvmpipe dropped their triangles.
TEST(OffscreenRender, PlacedOccludersAreDrawnAndTheSelectedOneHighlighted)
{
    const auto folder = freshFolder("offscreen-occluder");
    EditorDocument document;
    openFloorWithPatches(document, folder);
    const auto [source, receiver] = floorPatches();
    const Camera camera = shaftView(source, receiver);
    ViewStyle style;
    style.showRays = false;
    const glm::dvec3 middle = 0.5 * (source.centre() + receiver.centre());
    const glm::dvec3 pixel = toPixels(camera, middle, 320, 240);
    EXPECT_FALSE(violet(renderOffscreen(document, camera, style, 320, 240).image.pixel(int(pixel.x), int(pixel.y))));

    OccluderSpec crate;
    crate.mesh = "box";
    crate.transform = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(middle)), glm::vec3(0.6f));
    document.addOccluder(crate);
    document.select({ObjectKind::None, 0});   // adding selects it
    const OffscreenResult placed = renderOffscreen(document, camera, style, 320, 240);
    EXPECT_TRUE(violet(placed.image.pixel(int(pixel.x), int(pixel.y))))
        << std::hex << placed.image.pixel(int(pixel.x), int(pixel.y));
    style.wireframe = true;
    EXPECT_TRUE(violet(renderOffscreen(document, camera, style, 320, 240).image.pixel(int(pixel.x), int(pixel.y))));
    style.wireframe = false;

    document.select({ObjectKind::Occluder, 0});
    const OffscreenResult selected = renderOffscreen(document, camera, style, 320, 240);
    const QRgb c = selected.image.pixel(int(pixel.x), int(pixel.y));
    EXPECT_GT(qRed(c), qBlue(c)) << "the selected occluder is drawn in the selection's orange";
}


// Opening demo_floor.json froze the window for minutes while the GL sampler was
// timed on llvmpipe. A software rasterizer is never tried.
TEST(LiveVisibility, ASoftwareRasterizerIsNotTimed)
{
    const auto context = gl::HeadlessContext::create(gl::Backend::OSMesa);
    ASSERT_NE(context->renderer().find("llvmpipe"), std::string::npos) << context->renderer();
    const std::filesystem::path project = test::copyDemoProject(freshFolder("live-software"));
    EditorDocument document;
    document.open(project);
    LiveVisibility live;
    live.setGl(&context->functions());
    live.setScene(document.scene());
    const Project& p = document.project();
    const std::string line = live.chooseBackend(p.source, p.receiver);
    EXPECT_NE(line.find("software rasterizer"), std::string::npos) << line;
    EXPECT_EQ(live.backendName().rfind("CPU", 0), 0u) << live.backendName();
    EXPECT_TRUE(live.sample(p.source, p.receiver).valid);
}


// The demo level opened without a project put both default patches inside a wall
// (0.0% visible, no hint why).
TEST(EditorDocument, ABareLevelGetsPatchesInOpenSpaceThatSeeEachOther)
{
    const std::filesystem::path project = test::copyDemoProject(freshFolder("bare-level"));
    EditorDocument document;
    document.open(project.parent_path() / "demo_level.glb");
    const Project& p = document.project();
    const WorldTriangles triangles = worldTriangles(document.scene());
    for (const Patch* patch : {&p.source, &p.receiver})
        for (const glm::dvec3 d : {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1)}) {
            const auto hit = pickSurface(triangles, Ray{patch->centre(), d});
            EXPECT_TRUE(!hit || hit->distance >= 0.5) << "a patch centre " << (hit ? hit->distance : 0.0) << " m from a wall";
        }
    LiveVisibility live;
    live.setScene(document.scene());
    const VisibilityResult result = live.sample(p.source, p.receiver);
    ASSERT_TRUE(result.valid) << result.error;
    EXPECT_GT(result.visibleFraction(), 0.25);
    EXPECT_GT(glm::length(p.receiver.centre() - p.source.centre()), 10.0) << "across the level, not side by side";
}


// The default height (1.5 m over the level's lowest point) put the patches under a hilly terrain
// (every ray passed beneath the hills: 100% visible, drawn in the dark under the ground) and,
// in a level modelled in centimetres, inside its 20-unit floor slab. Each patch now stands over
// the ground under it, with nothing above it on a terrain.
TEST(EditorDocument, ABareTerrainOrSlabGetsPatchesOverItsGround)
{
    const auto folder = freshFolder("bare-terrain");
    test::writeTerrainObj(folder);
    {
        // A closed floor slab 3,600 units wide and 20 thick, its top at y = 0 (centimetres), wound outward.
        std::ofstream out(folder / "slab.obj");
        for (int k = 0; k < 8; ++k)
            out << "v " << (k & 4 ? 1800 : -1800) << " " << (k & 2 ? 0 : -20) << " " << (k & 1 ? 1800 : -1800) << "\n";
        out << "f 1 2 4\nf 1 4 3\nf 5 7 8\nf 5 8 6\nf 1 5 6\nf 1 6 2\nf 3 4 8\nf 3 8 7\nf 1 3 7\nf 1 7 5\nf 2 6 8\nf 2 8 4\n";
    }
    for (const char* level : {"terrain.obj", "slab.obj"}) {
        EditorDocument document;
        document.open(folder / level);
        const WorldTriangles triangles = worldTriangles(document.scene());
        for (const Patch* patch : {&document.project().source, &document.project().receiver}) {
            const auto ground = pickSurface(triangles, Ray{patch->centre(), {0.0, -1.0, 0.0}});
            ASSERT_TRUE(ground) << level << ": nothing under the patch at y = " << patch->centre().y;
            EXPECT_NEAR(ground->distance, 1.5, 0.01) << level;
            EXPECT_FALSE(pickSurface(triangles, Ray{patch->centre(), {0.0, 1.0, 0.0}}))
                << level << ": something above the patch at y = " << patch->centre().y;
        }
    }
}

// The section cut followed the orbit target (a pan or a moment of flying hid the
// level), and picking ignored it: a click on the floor selected the hidden ceiling, and placing a
// patch on a visible wall put it on the hidden ceiling.
TEST(SectionCut, HasItsOwnHeightAndPickingGoesThroughWhatItHides)
{
    const std::filesystem::path project = test::copyDemoProject(freshFolder("section-cut"));
    EditorDocument document;
    document.open(project);
    ViewportController controller(document);
    controller.setViewportSize(400, 300);
    ViewStyle style;
    style.cutHeight = 1.5;
    controller.setStyle(&style);
    Camera camera;
    camera.target = document.project().receiver.centre() + glm::dvec3(-3.0, 0.0, 0.0);
    camera.target.y = 0.0;
    camera.distance = 30.0;
    camera.pitch = -1.45;   // nearly straight down, from above the roof
    controller.setCamera(camera);

    const Cutaway before = cutaway(style, controller.camera());
    Camera panned = camera;
    panned.target += glm::dvec3(2.0, -1.0, 3.0);
    EXPECT_EQ(cutaway(style, panned).height, before.height) << "navigation never moves the cut";

    ASSERT_TRUE(controller.placePatchAt(ObjectKind::Source, QPointF(200, 150)));
    EXPECT_LT(document.project().source.centre().y, 1.5) << "placed on the floor, under the hidden roof";
    style.cutaway = false;
    ASSERT_TRUE(controller.placePatchAt(ObjectKind::Source, QPointF(200, 150)));
    EXPECT_GT(document.project().source.centre().y, 1.5) << "with the cut off, the roof is what is hit";
}


// F12 images get numbered names beside the project instead of one "sightline.png".
TEST(EditorDocument, ScreenshotNamesAreNumberedAndNeverReused)
{
    const auto folder = freshFolder("numbered");
    EXPECT_EQ(nextNumberedFile(folder, "demo"), folder / "demo-001.png");
    std::ofstream(folder / "demo-001.png") << "x";
    std::ofstream(folder / "demo-002.png") << "x";
    EXPECT_EQ(nextNumberedFile(folder, "demo"), folder / "demo-003.png");
    std::filesystem::create_symlink("missing-target", folder / "demo-003.png");   // a dangling link counts too
    EXPECT_EQ(nextNumberedFile(folder, "demo"), folder / "demo-004.png");
}


// A patch inside geometry gave 0.0% visible and no hint why; the editor now names the
// closed object that holds it.
TEST(Picking, EnclosingInstanceNamesTheClosedObjectAroundAPoint)
{
    const auto folder = freshFolder("enclosing");
    EditorDocument document;
    document.open(writeFloorObj(folder));
    OccluderSpec crate;
    crate.name = "crate";
    crate.mesh = "box";
    crate.transform = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(2.0f, 1.0f, 0.0f)), glm::vec3(2.0f));
    document.addOccluder(crate);
    const Scene& scene = document.scene();
    const WorldTriangles triangles = worldTriangles(scene);
    const auto inside = enclosingInstance(scene, triangles, glm::dvec3(2.2, 1.1, 0.1));
    ASSERT_TRUE(inside.has_value());
    EXPECT_EQ(scene.instances[*inside].name, "crate");
    EXPECT_FALSE(enclosingInstance(scene, triangles, glm::dvec3(5.0, 1.0, 0.0)).has_value()) << "outside the crate";
    EXPECT_FALSE(enclosingInstance(scene, triangles, glm::dvec3(2.0, 3.0, 0.0)).has_value()) << "above it";
}

// A blocked ray is drawn only up to where it is first stopped, with a dot there.
TEST(OffscreenRender, BlockedRaysStopAtTheirFirstHitWithADot)
{
    const auto folder = freshFolder("offscreen-stops");
    EditorDocument document;
    openFloorWithPatches(document, folder);
    const auto [source, receiver] = floorPatches();
    // A 2 m wall across the shaft halfway (x = 3): every ray is blocked there, at half its length.
    OccluderSpec wall;
    wall.mesh = "plane";
    wall.transform = glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(3, 1.5f, 0)), glm::radians(90.0f), glm::vec3(0, 0, 1)),
                                glm::vec3(2.0f));
    document.addOccluder(wall);
    const pvs::FirstHitCaster hits(document.scene());
    LiveVisibility live;
    live.setScene(document.scene());
    const VisibilityResult result = live.sample(source, receiver);
    ASSERT_EQ(result.blocked, result.rays);
    const RaySubset subset = raySubset(result.map.sourceCount(), result.map.receiverCount(), 4096);
    const std::vector<float> ends = drawnRayEnds(hits, result.map, source, receiver, subset);
    ASSERT_EQ(ends.size(), std::size_t(4096));
    for (float t : ends)
        ASSERT_NEAR(t, 0.5f, 1e-4f);

    const Camera camera = shaftView(source, receiver);
    ViewStyle style;
    style.showBlocked = true;
    style.blockedColour = {0.9f, 0.15f, 0.1f, 1.0f};   // opaque, for a crisp check
    style.stopColour = {0.1f, 1.0f, 1.0f, 1.0f};
    const OffscreenResult image = renderOffscreen(document, camera, style, 320, 240);
    EXPECT_EQ(image.visibility.rayEndsCap, 4096);
    const auto at = [&](const glm::dvec3& p) {
        const glm::dvec3 q = toPixels(camera, p, 320, 240);
        return image.image.pixel(int(q.x), int(q.y));
    };
    const auto red = [](QRgb c) { return qRed(c) > 150 && qGreen(c) < 90 && qBlue(c) < 90; };
    const glm::dvec3 along = receiver.centre() - source.centre();
    EXPECT_TRUE(red(at(source.centre() + 0.25 * along)));    // before the wall: drawn
    EXPECT_FALSE(red(at(source.centre() + 0.75 * along)));   // past it: not
    int dots = 0;
    const glm::dvec3 stop = toPixels(camera, source.centre() + 0.5 * along, 320, 240);
    for (int y = int(stop.y) - 12; y <= int(stop.y) + 12; ++y)
        for (int x = int(stop.x) - 12; x <= int(stop.x) + 12; ++x) {
            const QRgb c = image.image.pixel(x, y);
            dots += qRed(c) < 80 && qGreen(c) > 200 && qBlue(c) > 200;
        }
    EXPECT_GT(dots, 10) << "no dots where the rays stop";
}

// Live sampling runs on a worker thread. Every answer is the synchronous sampler's
// answer for the pair it names, generations only grow, requests queued behind a running one are
// replaced by the newest, and the newest is always answered.
TEST(BackgroundSampler, AnswersTheLatestRequestExactlyAndDropsTheOnesItReplaced)
{
    const std::filesystem::path project = test::copyDemoProject(freshFolder("background-sampler"));
    EditorDocument document;
    document.open(project);
    const Project& p = document.project();
    const auto scene = std::make_shared<const Scene>(document.scene());

    std::mutex mutex;
    std::condition_variable answered;
    std::vector<std::pair<std::uint64_t, VisibilityResult>> answers;
    BackgroundSampler worker([&](std::uint64_t generation, VisibilityResult result) {
        std::lock_guard lock(mutex);
        answers.emplace_back(generation, std::move(result));
        answered.notify_one();
    });
    constexpr int kRequests = 40;
    std::vector<Patch> receivers;
    for (int i = 1; i <= kRequests; ++i) {
        Patch receiver = p.receiver;
        receiver.corner += 0.05 * i * glm::normalize(receiver.u);
        receivers.push_back(receiver);
        worker.request({std::uint64_t(i), scene, p.source, receiver, nullptr, ""});
    }
    {
        std::unique_lock lock(mutex);
        ASSERT_TRUE(answered.wait_for(lock, std::chrono::seconds(60), [&] {
            return !answers.empty() && answers.back().first == kRequests;
        }));
    }
    // 40 requests posted far faster than one sample: most were replaced before they started.
    EXPECT_LT(answers.size(), std::size_t(kRequests));
    LiveVisibility reference;
    reference.setScene(*scene);
    std::uint64_t previous = 0;
    for (const auto& [generation, result] : answers) {
        EXPECT_GT(generation, previous);
        previous = generation;
        ASSERT_TRUE(result.valid) << result.error;
        const Patch& receiver = receivers[generation - 1];
        EXPECT_EQ(result.receiver.corner, receiver.corner);
        const VisibilityResult expected = reference.sample(p.source, receiver);
        EXPECT_EQ(result.blocked, expected.blocked) << "generation " << generation;
        EXPECT_TRUE(result.map == expected.map) << "generation " << generation;
    }

    // An invalid pair and unreadable heights are answers too, with the reason.
    Patch inside = p.receiver;
    inside.corner = p.source.corner;
    worker.request({100, scene, p.source, inside, nullptr, ""});
    std::unique_lock lock(mutex);
    ASSERT_TRUE(answered.wait_for(lock, std::chrono::seconds(60), [&] { return answers.back().first == 100; }));
    EXPECT_FALSE(answers.back().second.valid);
    EXPECT_NE(answers.back().second.error.find("invalid patch pair"), std::string::npos) << answers.back().second.error;
    lock.unlock();
    worker.request({101, scene, p.source, p.receiver, nullptr, "bumps.png: cannot be read"});
    lock.lock();
    ASSERT_TRUE(answered.wait_for(lock, std::chrono::seconds(60), [&] { return answers.back().first == 101; }));
    EXPECT_FALSE(answers.back().second.valid);
    EXPECT_EQ(answers.back().second.error, "bumps.png: cannot be read");
}



// A level written Z-up or upside down by another tool opens upright: the up axis is guessed from
// its floors, used (the default patches stand in its rooms and see each other as on the upright
// demo), saved as "scene_up", said to the user, and File > Import Settings changes it, undoably.
TEST(EditorDocument, ALevelWrittenAnotherWayUpOpensUprightAndItsImportSettingsChangeUndoably)
{
    const std::filesystem::path demo = test::copyDemoProject(freshFolder("other-up"));
    const std::filesystem::path folder = demo.parent_path();
    Scene upright = loadScene(folder / "demo_level.glb");
    const Bounds bounds = upright.bounds();
    for (const char* up : {"+z", "-y", "-x"}) {
        Scene written = upright;
        const glm::mat4 toFile(glm::inverse(SceneImport{up, 1.0}.transform()));
        for (Instance& instance : written.instances)
            instance.transform = toFile * instance.transform;
        const std::filesystem::path file = folder / (std::string("level_") + (up[0] == '+' ? "plus_" : "minus_") + up[1] + ".glb");
        saveScene(written, file);
        EditorDocument document;
        document.open(file);
        EXPECT_EQ(document.sceneImportSettings().up, up);
        EXPECT_NE(document.openNote().toStdString().find(std::string("looks ") + up + "-up"), std::string::npos);
        const Bounds opened = document.levelBounds();
        for (int axis = 0; axis < 3; ++axis) {   // the demo's own box again
            EXPECT_NEAR(opened.min[axis], bounds.min[axis], 1e-3f) << up << " axis " << axis;
            EXPECT_NEAR(opened.max[axis], bounds.max[axis], 1e-3f) << up << " axis " << axis;
        }
        LiveVisibility live;
        live.setScene(document.scene());
        const VisibilityResult result = live.sample(document.project().source, document.project().receiver);
        ASSERT_TRUE(result.valid) << result.error;
        EXPECT_GT(result.visibleFraction(), 0.25) << up;

        // Told it is Y-up after all: the level lies on its side; undone, it stands again.
        document.setSceneImportSettings(SceneImport{"+y", 1.0});
        EXPECT_GT(std::abs(document.levelBounds().max.y - bounds.max.y), 1.0f) << up;
        document.undoStack()->undo();
        EXPECT_NEAR(document.levelBounds().max.y, bounds.max.y, 1e-3f);
        EXPECT_THROW(document.setSceneImportSettings(SceneImport{"up", 1.0}), Error);
        // Saved, the setting goes with the project; reopened, the level stands as before.
        document.save(folder / "saved.json");
        EditorDocument reopened;
        reopened.open(folder / "saved.json");
        EXPECT_EQ(reopened.sceneImportSettings().up, up);
        EXPECT_TRUE(reopened.openNote().isEmpty());
        EXPECT_NEAR(reopened.levelBounds().max.y, bounds.max.y, 1e-3f);
    }
    // The upright demo is left as it is.
    EditorDocument document;
    document.open(folder / "demo_level.glb");
    EXPECT_EQ(document.sceneImportSettings().up, "+y");
    EXPECT_TRUE(document.openNote().isEmpty());
}

} // namespace sightline::ui

namespace sightline::ui {

// The most natural pair, a floor source 2 cm over the floor and a wall receiver standing on it,
// crossed the floor patch's plane by a centimetre; a floor patch running up to the wall crosses a
// wall patch's plane. Each gets a one-patch fix that makes the pair valid.
TEST(PatchPairFix, AFloorAndAWallPairIsFixedByLiftingOrShrinkingOnePatch)
{
    Patch floor;   // 2 x 2 m, 2 cm over the floor (y = 0), half a metre in front of the wall at z = 0
    floor.corner = {-1.0, 0.02, 2.5};
    floor.u = {2.0, 0.0, 0.0};
    floor.v = {0.0, 0.0, -2.0};   // facing up
    Patch wall;    // 2 x 2 m, 1 cm out from the wall, from 1 cm over the floor
    wall.corner = {-1.0, 0.01, 0.01};
    wall.u = {2.0, 0.0, 0.0};
    wall.v = {0.0, 2.0, 0.0};     // facing +z, into the room
    EXPECT_THROW(validatePatchPair(floor, wall), Error);
    const auto lift = fixPatchPair(floor, wall, /*preferSource=*/false);
    ASSERT_TRUE(lift);
    EXPECT_FALSE(lift->source);
    EXPECT_EQ(lift->description, "lift the receiver 2 cm above the source's plane");
    EXPECT_NO_THROW(validatePatchPair(floor, lift->patch));
    EXPECT_NEAR(lift->patch.corner.y, 0.03, 1e-12);   // 1 cm above the floor patch's plane
    EXPECT_EQ(lift->patch.u, wall.u);
    EXPECT_EQ(lift->patch.v, wall.v);

    // The wall patch already above it, the floor patch reaching the wall: moved into the room.
    Patch high = wall;
    high.corner.y = 0.1;
    Patch reaching = floor;
    reaching.corner.z = 2.0;
    reaching.v = {0.0, 0.0, -2.0};   // z from 2 down to 0: behind the wall patch's plane (z = 0.01)
    EXPECT_THROW(validatePatchPair(reaching, high), Error);
    const auto moved = fixPatchPair(reaching, high, /*preferSource=*/true);
    ASSERT_TRUE(moved);
    EXPECT_TRUE(moved->source);
    EXPECT_EQ(moved->description, "move the source 2 cm in front of the receiver's plane");
    EXPECT_NO_THROW(validatePatchPair(moved->patch, high));
    // Not allowed to move that far: shrunk to the room's side instead, by 2 cm.
    const auto shrunk = fixPatchPair(reaching, high, /*preferSource=*/true, /*maxMove=*/0.001);
    ASSERT_TRUE(shrunk);
    EXPECT_TRUE(shrunk->source);
    EXPECT_EQ(shrunk->description, "shrink the source by 2 cm to the receiver's front");
    EXPECT_NO_THROW(validatePatchPair(shrunk->patch, high));
    EXPECT_NEAR(glm::length(shrunk->patch.v), 1.98, 1e-9);
    EXPECT_EQ(shrunk->patch.u, reaching.u);

    // Nothing to fix, or nothing a fix can do.
    EXPECT_FALSE(fixPatchPair(floor, lift->patch, false));
    Patch flat = wall;
    flat.v = wall.u;   // degenerate
    EXPECT_FALSE(fixPatchPair(floor, flat, false));
    Patch across = wall;   // reaching a metre below the floor patch's plane: too far to lift, shrunk
    across.corner = {-1.0, -1.0, 0.01};
    const auto cut = fixPatchPair(floor, across, false);
    ASSERT_TRUE(cut);
    EXPECT_EQ(cut->description, "shrink the receiver by 103 cm to the source's front");
    EXPECT_NO_THROW(validatePatchPair(floor, cut->patch));
}

} // namespace sightline::ui

namespace sightline::ui {

// A PVS baked by the CLI opens in the editor (it said "invalid JSON: parse error" and baked again);
// one of another level, or of a level whose objects moved since, is refused saying why.
TEST(BakedPvs, TheClisPvsAndItsJsonOpenForTheirLevelAndNotForAnother)
{
    const std::filesystem::path folder = freshFolder("baked-pvs");
    // A 3 x 2 m wall at z = 2 with a 1 m square hole (as the CLI tests' scene).
    std::ofstream(folder / "wall.obj") << "v -1 -0.5 2\nv 2 -0.5 2\nv 2 1.5 2\nv -1 1.5 2\nv 0 0 2\nv 1 0 2\nv 1 1 2\nv 0 1 2\n"
                                          "f 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
    const nlohmann::json project = {
        {"version", 1},
        {"scene", "wall.obj"},
        {"source", {{"corner", {0, 0, 0}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}}},
        {"receiver", {{"corner", {0, 0, 4}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}}},
        {"occluders", {{{"name", "crate"}, {"mesh", "box"}, {"transform", {0.4, 0, 0, 0, 0, 0.3, 0, 0, 0, 0, 0.4, 0, 0.5, 0.15, 2.2, 1}}}}},
        {"pvs", {{"cells", {{{"min", {0, 0.1, -2}}, {"max", {1, 1, -1}}}, {{"min", {0, 0.1, 5}}, {"max", {1, 1, 6}}}}}}}};
    std::ofstream(folder / "p.json") << project.dump(2);
    const std::string bake = std::string(SIGHTLINE_CLI) + " pvs bake " + (folder / "p.json").string() + " --out " +
                             (folder / "p.pvs").string() + " --json " + (folder / "p.pvs.json").string() + " > /dev/null 2>&1";
    ASSERT_EQ(std::system(bake.c_str()), 0) << bake;

    EditorDocument document;
    document.open(folder / "p.json");
    for (const char* file : {"p.pvs", "p.pvs.json"}) {
        const pvs::PvsData data = readBakedPvs(folder / file, document.project(), document.scene());
        EXPECT_EQ(data.cells.size(), 2u) << file;
        EXPECT_EQ(data.objects.size(), document.scene().instances.size()) << file;   // the wall and the crate
        EXPECT_GT(data.rows.visibleCount(), 0u) << file;
    }
    const auto refusal = [&](const std::filesystem::path& file) {
        try {
            readBakedPvs(file, document.project(), document.scene());
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    // The crate moved since the bake: refused, naming it.
    ObjectRef crate{ObjectKind::Occluder, 0};
    document.setState(crate, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 1.0f)) * std::get<glm::mat4>(document.state(crate)),
                      "move crate");
    EXPECT_NE(refusal(folder / "p.pvs").find("('crate') is not where the bake saw it"), std::string::npos) << refusal(folder / "p.pvs");
    document.undoStack()->undo();
    EXPECT_EQ(refusal(folder / "p.pvs"), "accepted");
    // Another level file under the same name: another SHA-256.
    std::ofstream(folder / "wall.obj", std::ios::app) << "\n# edited\n";
    EXPECT_NE(refusal(folder / "p.pvs").find("baked from another scene than wall.obj"), std::string::npos);
    // Not a PVS at all.
    std::ofstream(folder / "bad.pvs") << "hello";
    EXPECT_NE(refusal(folder / "bad.pvs").find("bad.pvs"), std::string::npos);
}

} // namespace sightline::ui

namespace sightline::ui {

// A click through the section cut could land a patch on a wall's outside face: outside the
// building, facing the wall, below the floor; the status bar now says so.
TEST(PatchWarnings, APatchOnTheWrongSideOfAWallOrUnderTheFloorIsCalledOut)
{
    // A floor (facing up) over x, z in [-3, 3] x [0, 6], and a wall in z = 0 facing into the room (+z).
    const Scene room = test::sceneOf({test::quad({-3, 0, 0}, {0, 0, 6}, {6, 0, 0}, "floor"),
                                      test::quad({-3, 0, 0}, {6, 0, 0}, {0, 3, 0}, "wall")});
    const WorldTriangles triangles = worldTriangles(room);
    const Bounds level = room.bounds();
    const auto patch = [](glm::dvec3 centre, glm::dvec3 u, glm::dvec3 v) {
        Patch p;
        p.u = u;
        p.v = v;
        p.corner = centre - 0.5 * (u + v);
        return p;
    };
    const Patch floorSource = patch({0.0, 0.02, 3.0}, {1, 0, 0}, {0, 0, -1});   // facing up
    const Patch wallReceiver = patch({0.0, 1.0, 0.02}, {1, 0, 0}, {0, 1, 0});   // facing +z, into the room
    EXPECT_TRUE(patchWarnings(triangles, level, floorSource, wallReceiver).empty());

    const auto says = [&](const Patch& source, const Patch& receiver) {
        std::string all;
        for (const std::string& w : patchWarnings(triangles, level, source, receiver))
            all += w + "; ";
        return all;
    };
    // On the wall's outside, facing out: away from the source.
    const Patch outsideFacingOut = patch({0.0, 1.0, -0.02}, {-1, 0, 0}, {0, 1, 0});
    EXPECT_NE(says(floorSource, outsideFacingOut).find("the receiver faces away from the source"), std::string::npos);
    // On the wall's outside, facing the wall from 2 cm.
    const Patch outsideFacingWall = patch({0.0, 1.0, -0.02}, {1, 0, 0}, {0, 1, 0});
    EXPECT_NE(says(floorSource, outsideFacingWall).find("the receiver faces a surface 2 cm in front of it"), std::string::npos)
        << says(floorSource, outsideFacingWall);
    // 14 cm below the floor.
    const Patch underFloor = patch({0.0, -0.14, 3.0}, {1, 0, 0}, {0, 0, -1});
    EXPECT_NE(says(underFloor, wallReceiver).find("the source is below a floor"), std::string::npos) << says(underFloor, wallReceiver);
    // A ceiling wound upwards (a common export mistake) over a floor does not count.
    const Scene wrongCeiling = test::sceneOf({test::quad({-3, 0, 0}, {0, 0, 6}, {6, 0, 0}, "floor"),
                                              test::quad({-3, 3, 0}, {0, 0, 6}, {6, 0, 0}, "ceiling facing up")});
    EXPECT_TRUE(patchWarnings(worldTriangles(wrongCeiling), wrongCeiling.bounds(), patch({0.0, 1.0, 1.0}, {0, 0, 1}, {0, 1, 0}),
                              patch({0.0, 1.0, 5.0}, {0, 0, -1}, {0, 1, 0}))
                    .empty());
    // Far off.
    const Patch away = patch({100.0, 1.0, 3.0}, {0, 0, 1}, {0, 1, 0});
    EXPECT_NE(says(away, wallReceiver).find("the source is outside the level"), std::string::npos);
}

} // namespace sightline::ui

