#include "editor/SectionCutHandle.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace sightline::ui {

namespace {

constexpr double kScreenFraction = 0.06;   // the arrows' length relative to the depth (as the gizmo's 0.15)
constexpr double kMarginPixels = 24.0;
constexpr double kGripPixels = 16.0;      // the grip's radius on screen, with room for the cursor
constexpr double kAlongY = 0.95;           // |forward.y| beyond this: the view looks (nearly) along Y
constexpr glm::dvec3 kUp{0.0, 1.0, 0.0};  // the handle moves along world Y

} // namespace

std::optional<ScreenBox> screenBox(const Camera& camera, const std::vector<glm::dvec3>& points, int width, int height,
                                   double margin)
{
    std::optional<ScreenBox> box;
    for (const glm::dvec3& point : points) {
        const glm::dvec3 p = toPixels(camera, point, width, height);
        if (!(p.z > 0.0) || !std::isfinite(p.x) || !std::isfinite(p.y))
            continue;
        if (!box)
            box = ScreenBox{p.x, p.y, p.x, p.y};
        box->x0 = std::min(box->x0, p.x);
        box->y0 = std::min(box->y0, p.y);
        box->x1 = std::max(box->x1, p.x);
        box->y1 = std::max(box->y1, p.y);
    }
    if (box) {
        box->x0 -= margin;
        box->y0 -= margin;
        box->x1 += margin;
        box->y1 += margin;
    }
    return box;
}

std::optional<CutHandle> cutHandle(const Camera& camera, double cutHeight, int width, int height,
                                   const std::vector<ScreenBox>& keepClear)
{
    if (!std::isfinite(cutHeight))
        return std::nullopt;
    const double aspect = double(width) / std::max(height, 1);
    glm::dvec3 right = camera.right();
    right.y = 0.0;
    // Along the cut plane away from the viewer (up the screen in the top view).
    const glm::dvec3 away = glm::cross(glm::dvec3(0.0, 1.0, 0.0), right);
    // Offsets across (in half-widths at the target) and away (in half-heights), in order of preference.
    static constexpr double kSpots[][2] = {{0.75, 0.0}, {-0.75, 0.0}, {0.75, 0.5},  {-0.75, 0.5},
                                           {0.75, -0.5}, {-0.75, -0.5}, {0.45, 0.0}, {-0.45, 0.0}};
    std::optional<CutHandle> first;
    for (const auto& [across, along] : kSpots) {
        CutHandle handle;
        handle.point = camera.target + across * camera.halfHeight() * aspect * right + along * camera.halfHeight() * away;
        handle.point.y = cutHeight;
        handle.size = std::max(kScreenFraction * camera.screenDepth(handle.point), 1e-3);
        const glm::dvec3 p = toPixels(camera, handle.point, width, height);
        if (!(p.z > 0.0) || p.x < kMarginPixels || p.x > width - kMarginPixels || p.y < kMarginPixels ||
            p.y > height - kMarginPixels)
            continue;
        if (!first)
            first = handle;
        const glm::dvec3 up(0.0, handle.size, 0.0);
        const auto footprint = screenBox(camera, {handle.point - up, handle.point, handle.point + up}, width, height, kGripPixels);
        if (!footprint || std::none_of(keepClear.begin(), keepClear.end(), [&](const ScreenBox& b) { return b.overlaps(*footprint); }))
            return handle;
    }
    return first;
}

bool pickCutHandle(const CutHandle& handle, const Camera& camera, double x, double y, int width, int height,
                   double tolerance)
{
    const glm::dvec3 up(0.0, handle.size, 0.0);
    const glm::dvec3 a = toPixels(camera, handle.point + up, width, height);
    const glm::dvec3 b = toPixels(camera, handle.point - up, width, height);
    const glm::dvec3 c = toPixels(camera, handle.point, width, height);
    if (!(a.z > 0.0 && b.z > 0.0 && c.z > 0.0))
        return false;
    // The arrows' span, or the grip at the middle (all that shows when looking along Y).
    return distanceToSegment({x, y}, glm::dvec2(a), glm::dvec2(b)) <= tolerance ||
           glm::length(glm::dvec2(x, y) - glm::dvec2(c)) <= 1.5 * tolerance;
}

CutDrag beginCutDrag(const CutHandle& handle, const Camera& camera, double x, double y, int width, int height)
{
    CutDrag drag;
    drag.handle = handle;
    drag.startHeight = handle.point.y;
    drag.startY = y;
    if (std::abs(camera.forward().y) > kAlongY) {
        // Metres on the cut plane per pixel: the view's height at the plane's depth over the pixels.
        const double depth = camera.orthographic ? camera.distance : std::abs(glm::dot(handle.point - camera.eye(), camera.forward()));
        drag.metresPerPixel = 2.0 * depth * std::tan(camera.fovY / 2.0) / std::max(height, 1);
        return drag;
    }
    drag.startParam = axisParameter(handle.point, kUp, pixelRay(camera, x, y, width, height));
    return drag;
}

double dragCut(const CutDrag& drag, const Camera& camera, double x, double y, int width, int height, double step)
{
    const double moved = drag.metresPerPixel > 0.0
                             ? (drag.startY - y) * drag.metresPerPixel   // up the screen raises the cut
                             : axisParameter(drag.handle.point, kUp, pixelRay(camera, x, y, width, height)) - drag.startParam;
    const double to = drag.startHeight + moved;
    return step > 0.0 ? std::round(to / step) * step : to;
}

} // namespace sightline::ui
