#pragma once
// What a camera sees of a scene, as instances: O'Rorke's V (GPU Gems ch. 15) for the light
// visibility sets, shared by `sightline-cli lights --sets` and the editor's sets view.

#include <cstdint>
#include <vector>

#include "editor/Camera.h"
#include "lighting/DirectLight.h"

namespace sightline::ui {

/// The instances a `width` x `height` view from `camera` shows: the first hits of rays through
/// the pixel centres, sorted, each once. A sliver between pixels is missed, never invented.
std::vector<std::uint32_t> visibleInstances(const Camera& camera, const LightingScene& lighting, int width = 640, int height = 360);

} // namespace sightline::ui
