#pragma once
// Renders a document's view without a window: OSMesa (or EGL) through HeadlessContext, the same
// ViewportRenderer and LiveVisibility as the editor. Serves `sightline --screenshot` on machines
// without a display and the screenshot tests.

#include <QImage>

#include <optional>

#include "editor/Camera.h"
#include "editor/LiveVisibility.h"
#include "PatchOverlay.h"
#include "editor/ViewportRenderer.h"
#include "project/Approximation.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::ui {

class EditorDocument;

struct OffscreenResult {
    QImage image;                 ///< width x height, RGB
    VisibilityResult visibility;  ///< what the rays were drawn from
    std::uint64_t raysDrawn = 0;
    std::optional<JudgedDisagreement> disagreement;   ///< drawn in place of the rays, when asked for
};

/// Throws sightline::Error (no GL context, shader errors). With `overlay`, the sampled result goes
/// to it as a new frame and its colours are drawn (set its kind, statistic or animation result
/// before). With `disagreement`, the rays where that approximation answers differently from the
/// exact answer are drawn in their place, as the editor's disagreement view draws them.
OffscreenResult renderOffscreen(const EditorDocument& document, const Camera& camera, const ViewStyle& style, int width,
                                int height, gl::Backend backend = gl::Backend::OSMesa, PatchOverlay* overlay = nullptr,
                                const Approximation* disagreement = nullptr);

} // namespace sightline::ui
