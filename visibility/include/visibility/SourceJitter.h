#pragma once
// Decorrelated source sampling (Eisemann & Décoret §6.2): instead of one source sample set for
// every receiver sample, which shows as aliasing for large sources or aligned scenes, each
// receiver sample j sees the whole source grid shifted by its own offset, less than half a cell
// in each direction. In the bitmask method that is a shift of the backprojection (the paper's
// "perturb the positions of the backprojections"); the reference casts to the shifted positions,
// so every sampler answers the same question.
//
// The paper's noise, frac(α(sin(β y x) + γ x)), depends on sin's rounding; an integer hash gives
// the same offsets on every CPU and in GLSL (uint arithmetic wraps the same way), and offsets on
// a 2^-24 grid are exact in float and double.

#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "visibility/Patch.h"

namespace sightline {

/// A 32-bit mixing function (Wellons' lowbias32); the GL sampler's shader has the same one.
constexpr std::uint32_t mixBits(std::uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

struct SourceJitter {
    std::uint32_t seed = 0;   ///< 0: off (the regular grid of docs/design.md §2)

    bool enabled() const { return seed != 0; }

    /// The offset of the source grid for receiver sample j (bit index b * na + a of the
    /// receiver), in source cells: each coordinate in [-0.5, 0.5). Zero when off.
    glm::dvec2 offset(int j) const
    {
        if (!enabled())
            return glm::dvec2(0.0);
        const std::uint32_t h1 = mixBits(seed ^ mixBits(std::uint32_t(j) + 0x9e3779b9U));
        const std::uint32_t h2 = mixBits(h1 + 0x85ebca6bU);
        constexpr double kUnit = 1.0 / 16777216.0;   // 2^-24
        return {double(h1 >> 8) * kUnit - 0.5, double(h2 >> 8) * kUnit - 0.5};
    }

    /// The same offset as a world-space shift of every sample of `source`: sample i seen from
    /// receiver sample j lies at source.sample(i) + shift(source, j).
    glm::dvec3 shift(const Patch& source, int j) const
    {
        const glm::dvec2 o = offset(j);
        return o.x / source.na * source.u + o.y / source.nb * source.v;
    }
};

} // namespace sightline
