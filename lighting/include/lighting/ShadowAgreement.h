#pragma once
// How far a visibility answer that is not exact (the GL path's shadow maps) lies from the exact
// one, counted per (point, emitter) pair: the emitters of lightEmitters (LightEmission.h), the
// exact answer by docs/design.md §2's segment test as the reference path decides it.

#include <cstdint>
#include <span>
#include <vector>

#include "lighting/DirectLight.h"
#include "lighting/Light.h"

namespace sightline {

/// Per point, one bit per emitter: set where the emitter is unshadowed at the point.
struct EmitterBits {
    std::size_t points = 0;
    std::size_t emitters = 0;
    std::size_t words = 0;              ///< 32-bit words per point: ceil(emitters / 32)
    std::vector<std::uint32_t> bits;    ///< points x words

    EmitterBits() = default;
    EmitterBits(std::size_t pointCount, std::size_t emitterCount);
    bool lit(std::size_t point, std::size_t emitter) const
    {
        return (bits[point * words + emitter / 32] >> (emitter % 32)) & 1u;
    }
    void setLit(std::size_t point, std::size_t emitter) { bits[point * words + emitter / 32] |= 1u << (emitter % 32); }
};

/// The exact bits for every pair whose term (emitterTerm) is non-zero; pairs with a zero term stay
/// clear. Ties (docs/design.md §2) may go either way, as in the reference path.
EmitterBits exactEmitterBits(const LightingScene& scene, const std::vector<Light>& lights,
                             std::span<const ShadingPoint> points, int threads = 0);

struct ShadowAgreement {
    std::uint64_t pairs = 0;            ///< (point, emitter) pairs with a non-zero term
    std::uint64_t falseLit = 0;         ///< unshadowed in the answer, shadowed exactly
    std::uint64_t falseShadowed = 0;    ///< shadowed in the answer, unshadowed exactly
    std::uint64_t differing() const { return falseLit + falseShadowed; }
};

/// `answer` against `exact` over the pairs with a non-zero term (`exact`'s set bits and the pairs
/// the two share a zero term on are told apart by the terms again).
ShadowAgreement compareEmitterBits(const std::vector<Light>& lights, std::span<const ShadingPoint> points,
                                   const EmitterBits& answer, const EmitterBits& exact);

} // namespace sightline
