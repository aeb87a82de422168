#include "editor/Gizmo.h"

#include <algorithm>
#include <cmath>

namespace sightline::ui {

namespace {

constexpr double kScreenFraction = 0.15;     // handle length relative to the eye distance (Camera::screenDepth)
constexpr double kRadiansPerPixel = 0.01;

} // namespace

GizmoFrame gizmoFrame(const ObjectState& state, GizmoMode mode, const Camera& camera, GizmoSpace space)
{
    GizmoFrame frame;
    frame.pivot = pivotOf(state);
    if (mode == GizmoMode::Scale || space == GizmoSpace::Local)
        frame.axes = localAxesOf(state);
    else
        frame.axes = {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)};
    frame.length = std::max(kScreenFraction * camera.screenDepth(frame.pivot), 1e-3);
    return frame;
}

int pickGizmoAxis(const GizmoFrame& frame, const Camera& camera, double x, double y, int width, int height,
                  double tolerance)
{
    const glm::dvec3 origin = toPixels(camera, frame.pivot, width, height);
    if (origin.z <= 0.0)
        return -1;
    int best = -1;
    double bestDistance = tolerance;
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3 tip = toPixels(camera, frame.pivot + frame.length * frame.axes[std::size_t(axis)], width, height);
        if (tip.z <= 0.0)
            continue;
        // Skip the first fifth of the handle, where the three meet and a pick would be a guess.
        const glm::dvec2 a(origin), b(tip);
        const double d = distanceToSegment({x, y}, a + 0.2 * (b - a), b);
        if (d < bestDistance) {
            bestDistance = d;
            best = axis;
        }
    }
    return best;
}

GizmoDrag beginGizmoDrag(GizmoMode mode, int axis, const ObjectState& start, const Camera& camera, double x, double y,
                         int width, int height, GizmoSpace space)
{
    GizmoDrag drag;
    drag.mode = mode;
    drag.space = space;
    drag.axis = axis;
    drag.start = start;
    drag.frame = gizmoFrame(start, mode, camera, space);
    drag.startParam = axisParameter(drag.frame.pivot, drag.frame.axes[std::size_t(axis)], pixelRay(camera, x, y, width, height));
    drag.startX = x;
    return drag;
}

ObjectState dragGizmo(const GizmoDrag& drag, const Camera& camera, double x, double y, int width, int height,
                      const GizmoSnap& snap)
{
    const glm::dvec3& axis = drag.frame.axes[std::size_t(drag.axis)];
    const auto snapped = [](double value, double step) { return step > 0.0 ? std::round(value / step) * step : value; };
    switch (drag.mode) {
    case GizmoMode::Move: {
        const double s = axisParameter(drag.frame.pivot, axis, pixelRay(camera, x, y, width, height));
        // On the grid: the pivot's own coordinate along the (world) axis, not the distance moved,
        // so an object placed off the grid lands on it at its first snapped step. A local axis
        // need not meet the grid: there the distance moved is snapped.
        const double from = drag.space == GizmoSpace::World ? glm::dot(drag.frame.pivot, axis) : 0.0;
        const double delta = snapped(from + s - drag.startParam, snap.move) - from;
        return translated(drag.start, delta * axis);
    }
    case GizmoMode::Rotate:
        return rotated(drag.start, axis, snapped((x - drag.startX) * kRadiansPerPixel, snap.angle));
    case GizmoMode::Scale: {
        const double s = axisParameter(drag.frame.pivot, axis, pixelRay(camera, x, y, width, height));
        const double factor = std::max(0.02, snapped(1.0 + (s - drag.startParam) / drag.frame.length, snap.scale));
        return scaled(drag.start, drag.axis, factor);
    }
    }
    return drag.start;
}

} // namespace sightline::ui
