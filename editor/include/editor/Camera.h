#pragma once
// The viewport camera of a level editor: orbit around a target, pan, dolly, fly (right mouse +
// WASD), frame a box. Plain data plus free functions, so navigation is tested without a window.
//
// Conventions (docs/design.md §2): right-handed, Y up, metres. yaw turns about +Y, pitch tilts up;
// at yaw = pitch = 0 the camera looks down -Z.

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline::ui {

struct Camera {
    glm::dvec3 target{0.0};
    double distance = 10.0;   ///< eye to target, metres
    double yaw = 0.0;         ///< radians
    double pitch = -0.3;      ///< radians, in (-pi/2, pi/2)
    double fovY = 0.8727;     ///< radians (50 degrees)
    /// Orthographic projection (the axis views, numpad 5): parallel rays, and a view
    /// 2 * distance * tan(fovY / 2) high, so switching keeps the scale at the target. The eye
    /// stays `distance` behind the target, as in perspective: the near plane and the section cut's
    /// depth are where they were, and what is behind the eye is neither drawn nor picked.
    bool orthographic = false;

    glm::dvec3 forward() const;   ///< unit, eye -> target
    glm::dvec3 right() const;     ///< unit, horizontal
    glm::dvec3 up() const;        ///< unit
    glm::dvec3 eye() const { return target - distance * forward(); }

    glm::mat4 view() const;
    /// Half the view's height at the target's depth, in metres (in orthographic views, everywhere).
    double halfHeight() const;
    /// The depth that sets a point's size on screen: its distance from the eye in perspective,
    /// the target's distance in orthographic views (where depth does not shrink anything). Handles
    /// drawn a constant size on screen scale with it.
    double screenDepth(const glm::dvec3& point) const;
    /// Near and far planes follow the distance and the scene's size, so depth precision holds
    /// from a close-up of a patch to a whole level.
    glm::mat4 projection(double aspect, double sceneRadius) const;
};

/// A ray through a pixel: origin at the eye, unit direction.
struct Ray {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};
};

/// How far an orbit turns for a pixel of mouse motion by default (the Preferences' 1x).
inline constexpr double kOrbitRadiansPerPixel = 0.008;
/// Turns the camera about its target by a mouse motion in pixels.
void orbit(Camera& camera, double dxPixels, double dyPixels, double radiansPerPixel = kOrbitRadiansPerPixel);
/// Moves target and eye in the view plane so the point under the cursor follows it.
void pan(Camera& camera, double dxPixels, double dyPixels, int viewportHeight);
/// Wheel steps (positive = closer); the distance changes by a constant factor per step.
void dolly(Camera& camera, double steps);
/// Fly mode: turns the view about the eye (not the target).
void look(Camera& camera, double dxPixels, double dyPixels, double radiansPerPixel = kOrbitRadiansPerPixel);
/// Fly mode: moves eye and target by `move` in camera axes (x right, y up, z forward), metres.
void fly(Camera& camera, const glm::dvec3& move);
/// Keeps the eye at or above `floorY` (navigation took the camera under the floor).
/// Orbiting (and dollying) tilts the view up just enough; panning and flying lift eye and target.
void keepAbove(Camera& camera, double floorY, bool orbiting);
/// Looks at the whole box from the current direction.
void frame(Camera& camera, const Bounds& bounds);

/// Home: a fixed three-quarter view over the level (from the south-west, 35 degrees down, in
/// perspective), whatever the camera was: Home from eye level framed an outside wall, and from
/// an axis view stayed orthographic.
Camera overviewCamera(const Bounds& bounds);

/// The axis views of a level editor (Blender's numpad 7 / 1 / 3): straight down, along -Z, along -X.
enum class AxisView { Top, Front, Side };
/// The camera looking along `view` at the whole box, orthographic, framed as frame() does.
Camera axisView(AxisView view, const Bounds& bounds);
/// The view from `from`'s centre towards `to`'s centre ("look through the source",
/// the sniper's view of the doorway): the eye on the patch, 1 cm in front of it, the target at the
/// other patch, a field of view that holds the other patch with a margin.
Camera lookThrough(const glm::dvec3& from, const glm::dvec3& fromNormal, const glm::dvec3& to, double toRadius);

/// The ray through pixel (x, y) of a width x height viewport (origin top left, y down): from the
/// eye in perspective; in orthographic views from the pixel's point on the eye's plane, along the
/// view direction.
Ray pixelRay(const Camera& camera, double x, double y, int width, int height);
/// A world point in pixels (origin top left); z is its depth along the view direction from the
/// eye (< 0 behind it).
glm::dvec3 toPixels(const Camera& camera, const glm::dvec3& point, int width, int height);

/// Parameter s of the point pivot + s * axis (axis of unit length) nearest to the ray: where a
/// handle dragged along that axis follows the cursor. 0 when the ray runs along the axis.
double axisParameter(const glm::dvec3& pivot, const glm::dvec3& axis, const Ray& ray);
/// Distance from p to the segment a-b (pixels, for picking handles drawn as lines).
double distanceToSegment(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b);

} // namespace sightline::ui
