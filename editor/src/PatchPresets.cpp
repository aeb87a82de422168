#include "editor/PatchPresets.h"

#include <array>
#include <cmath>

#include <glm/geometric.hpp>

namespace sightline::ui {

namespace {

constexpr std::array kPresets{
    PatchPreset{"Doorway", 0.9, 2.1},
    PatchPreset{"Window", 1.2, 1.2},
    PatchPreset{"Player standing", 0.6, 1.8},
    PatchPreset{"Player crouching", 0.6, 1.2},
};

bool upright(const Patch& patch) { return std::abs(patch.normal().y) < 0.5; }

/// Whether u, rather than v, is the edge nearer the vertical (then it carries the height).
bool uIsUp(const Patch& patch)
{
    return upright(patch) && std::abs(patch.u.y) / glm::length(patch.u) > std::abs(patch.v.y) / glm::length(patch.v);
}

} // namespace

std::span<const PatchPreset> patchPresets() { return kPresets; }

std::optional<std::size_t> presetOf(const Patch& patch)
{
    const bool swapped = uIsUp(patch);
    const double width = glm::length(swapped ? patch.v : patch.u), height = glm::length(swapped ? patch.u : patch.v);
    for (std::size_t i = 0; i < kPresets.size(); ++i)
        if (std::abs(width - kPresets[i].width) < 1e-3 && std::abs(height - kPresets[i].height) < 1e-3)
            return i;
    return std::nullopt;
}

Patch resizedPatch(const Patch& patch, double width, double height)
{
    Patch out = patch;
    const bool swapped = uIsUp(patch);
    out.u = glm::normalize(patch.u) * (swapped ? height : width);
    out.v = glm::normalize(patch.v) * (swapped ? width : height);
    if (!upright(patch)) {
        out.corner = patch.centre() - 0.5 * (out.u + out.v);
        return out;
    }
    // The bottom edge's midpoint stays: the lower of the two edges across the upright direction.
    const glm::dvec3 up = swapped ? patch.u : patch.v, across = swapped ? patch.v : patch.u;
    const glm::dvec3 newUp = swapped ? out.u : out.v, newAcross = swapped ? out.v : out.u;
    const bool upIsUp = up.y >= 0.0;   // the edge at the corner is the bottom one
    const glm::dvec3 bottom = patch.corner + 0.5 * across + (upIsUp ? glm::dvec3(0.0) : up);
    out.corner = bottom - 0.5 * newAcross - (upIsUp ? glm::dvec3(0.0) : newUp);
    return out;
}

} // namespace sightline::ui
