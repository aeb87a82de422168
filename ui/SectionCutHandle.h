#pragma once
// The section cut's handle (issue 16 §1: "give the cut its own toggle and height (menu, shortcut,
// a handle)"): a grip on the cut plane, drawn a constant size on screen, that the designer drags
// up and down to set the cut height. Pure geometry on a Camera, like the gizmo, so it is tested
// without a window; the viewport draws it and the controller forwards the mouse.
//
// Where it sits: on the cut plane, to the right of the orbit target (three quarters of the way to
// the view's right edge at the target's depth), so it stays in view wherever the camera orbits
// and never covers the selection's gizmo at the centre. A drag moves it along world Y under the
// cursor; looking straight down (the top view), where Y points into the screen, the cursor's
// vertical motion raises and lowers it instead.

#include <optional>

#include "Camera.h"

namespace sightline::ui {

struct CutHandle {
    glm::dvec3 point{0.0};   ///< on the cut plane (point.y is the cut height)
    double size = 0.1;       ///< metres: the arrows' length, constant on screen
};

/// The handle for a cut at `cutHeight`, or nothing when that spot is behind the eye or outside
/// the width x height view (with a margin, so it is never half off the edge).
std::optional<CutHandle> cutHandle(const Camera& camera, double cutHeight, int width, int height);

/// Whether pixel (x, y) is on the handle (within `tolerance` pixels of its arrows' span).
bool pickCutHandle(const CutHandle& handle, const Camera& camera, double x, double y, int width, int height,
                   double tolerance = 10.0);

/// A drag in progress, computed from where it started (no drift).
struct CutDrag {
    CutHandle handle;            ///< as grabbed: the drag follows this vertical line
    double startHeight = 0.0;
    double startParam = 0.0;     ///< along Y, where the grab's ray passes nearest the line
    double startY = 0.0;         ///< the cursor's start (pixels)
    double metresPerPixel = 0.0; ///< > 0: the view looks along Y; the cursor's vertical motion is used
};

CutDrag beginCutDrag(const CutHandle& handle, const Camera& camera, double x, double y, int width, int height);
/// The cut height for the cursor at (x, y); with `step` > 0 on a multiple of it (snapping, G).
double dragCut(const CutDrag& drag, const Camera& camera, double x, double y, int width, int height, double step = 0.0);

} // namespace sightline::ui
