#pragma once
// The colour map of importance maps and heat overlays: viridis (van der Walt & Smith, matplotlib),
// perceptually uniform and readable by colour-blind viewers, dark for 0 and yellow for 1.
//
// Evaluated by Matt Zucker's degree-6 polynomial fit (public domain), within about 1/255 of the
// matplotlib table, so the CLI's PNG, the editor's overlay and its legend agree exactly.

#include <cstdint>

#include <glm/vec3.hpp>

namespace sightline {

/// Linear-ish sRGB in [0, 1]; t is clamped to [0, 1] (NaN gives the colour of 0).
glm::vec3 viridis(float t);

struct Rgb8 {
    std::uint8_t r = 0, g = 0, b = 0;
    bool operator==(const Rgb8&) const = default;
};
Rgb8 viridis8(float t);

} // namespace sightline
