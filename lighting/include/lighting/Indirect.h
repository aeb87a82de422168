#pragma once
// One bounce of indirect light by virtual point lights (Keller's instant radiosity, as Barczak
// 2006 §2 uses it), and the Monte-Carlo reference it is measured against.
//
// Photons leave the lights in proportion to their power (each light's share of the count by
// largest remainders, so the set is deterministic for a seed), each carrying the light's power
// over its photon count, and travel to the first surface they meet. There each becomes a VPL: a
// diffuse reflector of albedo x its flux (the surface's own albedo where its mesh carries one,
// Mesh::albedo, per channel; else the options' albedo), which gives a point x at distance d
//     E = albedo Phi max(0, m.(-l)) max(0, n.l) / (pi d^2),
// m the surface's normal towards the photon's source. That is exactly an area light of one sample
// whose radiance x area is albedo Phi / pi (LightEmission.h), so VPLs are shadowed by the same
// exact paths as every other light. The 1/d^2 of a VPL next to x is bounded by clamping d to at
// least `clampMetres` (the papers' clamp); the energy that removes is reported.
//
// The reference gathers the same bounce at x: cosine-weighted directions, the first surface y
// each meets, and the exact direct irradiance there: E(x) = albedo / N sum E_direct(y).

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/DirectLight.h"
#include "lighting/Light.h"

namespace sightline {

struct IndirectOptions {
    int vpls = 256;                ///< photons traced (those that meet nothing leave the scene)
    std::uint64_t seed = 1;
    double albedo = 0.5;           ///< the diffuse reflectance of surfaces without their own, in [0, 1)
    double clampMetres = 0.1;      ///< VPL distances below this count as this (0: no clamp)
    int threads = 0;
};

struct VplSet {
    std::vector<Light> vpls;       ///< one-sample area lights, one per photon that met a surface
    glm::dvec3 emitted{0.0};       ///< the lights' power the photons carried, per channel (W)
    int photons = 0;
    double ms = 0.0;
};

/// Throws sightline::Error for options out of range (a count past 1e6, albedo outside [0, 1),
/// a negative or non-finite clamp).
void validateIndirectOptions(const IndirectOptions& options);

/// Traces the photons. `lights` must have passed validateLights.
VplSet traceVpls(const LightingScene& scene, const std::vector<Light>& lights, const IndirectOptions& options);

struct IndirectResult {
    std::vector<glm::dvec3> irradiance;   ///< one bounce at each point, clamped
    double clampLoss = 0.0;               ///< share of the unclamped energy over the points the clamp removed
    DirectLightStats stats;
};

/// The VPLs' irradiance at the points (the fast direct path with the VPLs as lights).
IndirectResult vplIrradiance(const LightingScene& scene, const VplSet& vpls, std::span<const ShadingPoint> points,
                             const IndirectOptions& options);

/// The Monte-Carlo reference of the same bounce: `samples` cosine-weighted directions per point.
std::vector<glm::dvec3> gatheredIndirect(const LightingScene& scene, const std::vector<Light>& lights,
                                         std::span<const ShadingPoint> points, int samples, const IndirectOptions& options);

} // namespace sightline
