#pragma once
// Renders a document's view without a window: OSMesa (or EGL) through HeadlessContext, the same
// ViewportRenderer and LiveVisibility as the editor. Serves `sightline --screenshot` on machines
// without a display and the screenshot tests.

#include <QImage>

#include "Camera.h"
#include "LiveVisibility.h"
#include "PatchOverlay.h"
#include "ViewportRenderer.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::ui {

class EditorDocument;

struct OffscreenResult {
    QImage image;                 ///< width x height, RGB
    VisibilityResult visibility;  ///< what the rays were drawn from
    std::uint64_t raysDrawn = 0;
};

/// Throws sightline::Error (no GL context, shader errors). With `overlay`, the sampled result goes
/// to it as a new frame and its colours are drawn (set its kind, statistic or animation result
/// before).
OffscreenResult renderOffscreen(const EditorDocument& document, const Camera& camera, const ViewStyle& style, int width,
                                int height, gl::Backend backend = gl::Backend::OSMesa, PatchOverlay* overlay = nullptr);

} // namespace sightline::ui
