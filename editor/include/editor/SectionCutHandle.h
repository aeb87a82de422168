#pragma once
// The section cut's handle ("give the cut its own toggle and height (menu, shortcut,
// a handle)"): a grip on the cut plane, drawn a constant size on screen, that the designer drags
// up and down to set the cut height. Pure geometry on a Camera, like the gizmo, so it is tested
// without a window; the viewport draws it and the controller forwards the mouse.
//
// Where it sits: on the cut plane, to the right of the orbit target (three quarters of the way to
// the view's right edge at the target's depth), so it stays in view wherever the camera orbits
// and never covers the selection's gizmo at the centre. Where that spot would cover something
// the designer clicks (a patch, the gizmo: boxes on the screen the caller names), it takes the
// first clear one of a few others: left of the target, then farther or nearer on the cut plane,
// then closer to the centre. (In the demo's opening view the right-hand spot lies on the
// receiver, and a click on the receiver grabbed the cut instead.) A drag moves it along world Y
// under the cursor; looking straight down (the top view), where Y points into the screen, the
// cursor's vertical motion raises and lowers it instead.

#include <optional>
#include <vector>

#include "editor/Camera.h"

namespace sightline::ui {

struct CutHandle {
    glm::dvec3 point{0.0};   ///< on the cut plane (point.y is the cut height)
    double size = 0.1;       ///< metres: the arrows' length, constant on screen
};

/// A box on the screen, in pixels (x right, y down), that the handle keeps clear of.
struct ScreenBox {
    double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
    bool overlaps(const ScreenBox& o) const { return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1; }
};

/// The pixels `points` cover on the screen (those in front of the eye), grown by `margin`; nothing
/// when none is in front.
std::optional<ScreenBox> screenBox(const Camera& camera, const std::vector<glm::dvec3>& points, int width, int height,
                                   double margin = 0.0);

/// The handle for a cut at `cutHeight`, or nothing when no spot for it is in front of the eye and
/// inside the width x height view (with a margin, so it is never half off the edge). Its spot is
/// the first of the candidates above whose grip and arrows overlap none of `keepClear`; when every
/// one does, the first in view.
std::optional<CutHandle> cutHandle(const Camera& camera, double cutHeight, int width, int height,
                                   const std::vector<ScreenBox>& keepClear = {});

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
