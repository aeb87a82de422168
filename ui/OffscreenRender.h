#pragma once
// Renders a document's view without a window: OSMesa (or EGL) through HeadlessContext, the same
// ViewportRenderer and LiveVisibility as the editor. Serves `sightline --screenshot` on machines
// without a display and the screenshot tests.

#include <QImage>

#include "Camera.h"
#include "LiveVisibility.h"
#include "ViewportRenderer.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::ui {

class EditorDocument;

struct OffscreenResult {
    QImage image;                 ///< width x height, RGB
    VisibilityResult visibility;  ///< what the rays were drawn from
    std::uint64_t raysDrawn = 0;
};

/// Throws sightline::Error (no GL context, shader errors).
OffscreenResult renderOffscreen(const EditorDocument& document, const Camera& camera, const ViewStyle& style, int width,
                                int height, gl::Backend backend = gl::Backend::OSMesa);

} // namespace sightline::ui
