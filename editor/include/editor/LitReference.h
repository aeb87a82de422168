#pragma once
// The lit view's error against the reference (LitShading::Error): per light the reference path's
// field (lighting/DirectLight.h, LightingPath::Reference: every segment cast, no tile proof, no
// low-resolution pass) for the light as it is now, refreshed light by light within a time budget,
// so that what the view shows can be compared with the answer it promises, texel by texel. Plain
// C++ (no Qt), used on the lit view's worker.

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/DirectLight.h"
#include "lighting/Light.h"

namespace sightline::ui {

class LitReference {
public:
    /// Refreshes the lights whose reference is missing or out of date (their geometry or power
    /// changed: colour alone does not) until `budgetMs` is spent, at least one a call. Returns
    /// whether every light's reference is current.
    bool update(const LightingScene& scene, const std::vector<ShadingPoint>& points, const std::vector<Light>& lights,
                double budgetMs);
    /// Lights whose reference is current for `lights`.
    std::size_t current(const std::vector<Light>& lights) const;
    /// Per point the reference irradiance of `lights` (each light's colour times its field),
    /// summed in double light by light; meaningful once update returned true.
    std::vector<glm::dvec3> irradiance(const std::vector<Light>& lights, std::size_t points) const;

private:
    struct Kept {
        Light light;                 ///< as computed, colour white
        std::vector<float> field;    ///< its white irradiance per point
        bool valid = false;
    };
    bool isCurrent(std::size_t index, const Light& light) const;
    std::vector<Kept> kept_;
};

/// Per point |Y(shown) - Y(reference)| / max(Y(reference), floor), Y the luminance and the floor
/// 1e-3 of the brightest reference Y (so that the dark end of a falloff does not dominate).
std::vector<float> relativeError(const std::vector<glm::dvec3>& shown, const std::vector<glm::dvec3>& reference);

/// Errors below kErrorAgrees (the float rounding of the kept fields) dark green; above it, on a log
/// scale up to 100%, blue through yellow to red.
inline constexpr float kErrorAgrees = 1e-4f;
glm::vec3 errorColour(float relative);

} // namespace sightline::ui
