#pragma once
// The lights of a project (the "lights" key; docs/lights.md has the contract's formulas).
//
// Units are radiometric and the formulas are those of glTF's KHR_lights_punctual, so that a light
// read from a glTF file means the same here: a point or spot light's intensity is W/sr, a
// directional light's W/m², an area light's radiance W/m²/sr. Colours scale each channel.
//
// An area light is a rectangular emitter sampled exactly like a patch (the same corner, edges and
// sample grid as visibility/Patch.h): facing a planar receiver it is Eisemann & Décoret's source
// patch (§8), so the bitmask sampler answers its visibility, and every method and outside checker
// agrees on where its samples are.

#include <cstddef>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Patch.h"

namespace sightline {

enum class LightType { Point, Spot, Directional, Area };

const char* toString(LightType type);

struct Light {
    LightType type = LightType::Point;
    std::string name;              ///< may be empty; shown as "light N" in messages
    glm::dvec3 colour{1.0};        ///< per channel, >= 0

    // Point and spot.
    glm::dvec3 position{0.0};
    double intensity = 1.0;        ///< W/sr (point, spot); W/m² (directional)
    double range = 0.0;            ///< > 0: the smooth window clamp(1 - (d/R)^4, 0, 1)^2; 0: none

    // Spot and directional: the way the light travels (unit length once validated).
    glm::dvec3 direction{0.0, -1.0, 0.0};
    double innerAngle = 0.0;       ///< spot, radians: 0 <= inner < outer <= pi/2
    double outerAngle = 0.7853981633974483;

    // Area: the emitting rectangle and its sample grid; it emits on the side of normalize(u x v).
    Patch area;
    double radiance = 1.0;         ///< W/m²/sr
    bool twoSided = false;
    /// Area lights standing for virtual point lights (Indirect.h) only, never read from a file:
    /// distances below this count as this in the 1/d² (the VPL clamp); 0 for every real light.
    double clampMetres = 0.0;

    /// Samples this light contributes: na x nb for an area light, else 1.
    int sampleCount() const { return type == LightType::Area ? area.sampleCount() : 1; }
};

/// Limits that keep a hostile file from asking for unbounded work or memory: at most kMaxLights
/// lights, kMaxAreaLightSide samples along each side of an area light, and kMaxLightSamples
/// samples in all.
inline constexpr std::size_t kMaxLights = 100000;
inline constexpr int kMaxAreaLightSide = 1024;
inline constexpr std::size_t kMaxLightSamples = 1u << 20;

/// Throws sightline::Error naming `key` ("lights[3].intensity") when the light cannot be used:
/// non-finite numbers, negative colour, intensity or radiance, a zero direction, spot angles
/// outside 0 <= inner < outer <= pi/2, a non-positive range, a degenerate area, a sample grid
/// outside the limits, coordinates beyond docs/design.md §2's range. Normalises `direction`.
void validateLight(Light& light, const std::string& key);

/// Validates every light (keys "lights[i]...") and the limits on their count and samples.
void validateLights(std::vector<Light>& lights, const std::string& what);

/// The name shown for light `index`: its own, or "light <index>".
std::string displayName(const std::vector<Light>& lights, std::size_t index);

} // namespace sightline
