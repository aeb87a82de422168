#pragma once
// What each light gives a point before shadows: the contract's formulas (docs/lights.md), one
// function per light type, shared by the reference and the fast path so that both sum the same
// terms and differ only in how they decide visibility.
//
// A light is a set of emitters: one for a point, spot or directional light, an area light's
// na x nb samples (placed as a patch's samples, docs/design.md §2). At a point x with unit normal n,
// emitter s at distance d along unit l = (s - x) / d gives
//     point        I max(0, n.l) / d^2, times clamp(1 - (d/R)^4, 0, 1)^2 with a range R
//     spot         the point's term times clamp((cos t - cos b) / (cos a - cos b), 0, 1)^2,
//                  t the angle between the spot's direction and -l
//     directional  E max(0, n.(-d)), d the way the light travels
//     area sample  L (A / (na nb)) max(0, m.(-l)) max(0, n.l) / d^2, A = |u x v|,
//                  m = normalize(u x v) (|m.(-l)| when two-sided)
// times the light's colour, and counts only when the segment from x to s is unblocked. A
// directional light's segment runs from x along -d to beyond the scene's bounds.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "lighting/Light.h"
#include "visibility/Scene.h"

namespace sightline {

/// One point a light's shadow rays run to.
struct Emitter {
    glm::dvec3 position{0.0};   ///< unused for a directional light (its end depends on the point)
    std::uint32_t light = 0;    ///< index into the light list
};

/// The emitters of `lights` in order (a light's samples in bit order, b * na + a).
std::vector<Emitter> lightEmitters(const std::vector<Light>& lights);

/// The scalar term (W/m² per unit colour) emitter `position` of `light` gives at x with unit
/// normal n, before shadows; 0 where x coincides with the emitter.
double emitterTerm(const Light& light, const glm::dvec3& position, const glm::dvec3& x, const glm::dvec3& n);

/// emitterTerm for one light with what depends on the light alone worked out once (an area light's
/// normal and sample area, a spot's cone cosines): the same operations on the same values, so the
/// same bits, at a fraction of the cost over many points.
class EmitterTerm {
public:
    explicit EmitterTerm(const Light& light);
    double operator()(const glm::dvec3& position, const glm::dvec3& x, const glm::dvec3& n) const;

private:
    const Light* light_;
    glm::dvec3 areaNormal_{0.0};   ///< normalize(u x v), as cross / |cross|
    double sampleRadiance_ = 0.0;  ///< radiance * (A / (na nb))
    double clamp2_ = 0.0;          ///< clampMetres^2
    double cosInner_ = 1.0, cosOuter_ = 1.0;
};

inline double EmitterTerm::operator()(const glm::dvec3& position, const glm::dvec3& x, const glm::dvec3& n) const
{
    const Light& light = *light_;
    if (light.type == LightType::Directional)
        return light.intensity * std::max(0.0, -glm::dot(n, light.direction));
    const glm::dvec3 toLight = position - x;
    const double d2 = glm::dot(toLight, toLight);
    // Facing away (from the receiver's side, or from a one-sided area light's): zero, decided
    // before the square root.
    if (!(d2 > 0.0) || !(glm::dot(n, toLight) > 0.0) ||
        (light.type == LightType::Area && !light.twoSided && !(glm::dot(areaNormal_, toLight) < 0.0)))
        return 0.0;
    const double d = std::sqrt(d2);
    const glm::dvec3 l = toLight / d;
    const double cosReceiver = glm::dot(n, l);
    if (!(cosReceiver > 0.0))
        return 0.0;
    if (light.type == LightType::Area) {
        const double cosLight = -glm::dot(areaNormal_, l);
        const double facing = light.twoSided ? std::abs(cosLight) : std::max(0.0, cosLight);
        const double clamped = std::max(d2, clamp2_);
        return sampleRadiance_ * facing * cosReceiver / clamped;
    }
    double term = light.intensity * cosReceiver / d2;
    if (light.range > 0.0) {
        const double ratio = d / light.range;
        const double window = std::clamp(1.0 - ratio * ratio * ratio * ratio, 0.0, 1.0);
        term *= window * window;
    }
    if (light.type == LightType::Spot) {
        const double cosT = -glm::dot(light.direction, l);
        const double cone = std::clamp((cosT - cosOuter_) / (cosInner_ - cosOuter_), 0.0, 1.0);
        term *= cone * cone;
    }
    return term;
}

/// Where a directional light's segment from x ends: along -direction, beyond every point of
/// `bounds` (the scene's), so that no triangle past it could matter.
struct DirectionalReach {
    explicit DirectionalReach(const Bounds& bounds);
    glm::dvec3 end(const Light& light, const glm::dvec3& x) const;

    glm::dvec3 centre{0.0};
    double radius = 0.0;   ///< of a sphere around the bounds, plus a metre
};

} // namespace sightline
