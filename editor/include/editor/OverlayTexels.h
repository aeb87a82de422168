#pragma once
// The colours an overlay paints on a patch, one per sample. No Qt: the renderer (also used
// headless) takes them as they are.

#include <cstdint>
#include <vector>

#include "lighting/SoftShadow.h"
#include "visibility/ImportanceMap.h"

namespace sightline::ui {

/// One RGBA8 colour per patch sample, sample (a, b) at index b * na + a (docs/design.md §2), so the
/// renderer maps texel (a, b) onto the cell around sample (a, b).
struct OverlayTexels {
    int na = 0, nb = 0;
    std::vector<std::uint8_t> rgba;   ///< 4 * na * nb bytes
    bool smooth = false;              ///< interpolate between sample centres (light) or not (importance)

    bool empty() const { return rgba.empty(); }
    std::uint32_t rgbaAt(int a, int b) const;   ///< 0xRRGGBBAA
};

/// Importance in viridis (base/ColourMap.h, the colours of the CLI's images and legend).
OverlayTexels importanceTexels(const ImportanceMap& map);
/// The light fraction per channel, clamped to [0, 1], like the CLI's `shadow --out` image.
OverlayTexels lightTexels(const LightImage& light);

} // namespace sightline::ui
