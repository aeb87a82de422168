#pragma once
// Rectangular sample patches and the rules for a valid source/receiver pair (docs/design.md §2).
//
// A patch is a parallelogram with corner c and edge vectors u, v in world space (metres); its normal
// is normalize(u x v). Regular sample (a, b) of its na x nb grid lies at
//     c + (a + 0.5) / na * u + (b + 0.5) / nb * v,   a in [0, na), b in [0, nb),
// and has bit index b * na + a. Positions are computed in double precision so that every method
// (and any outside checker) agrees on them to the last float bit.

#include <cstdint>
#include <string>

#include <glm/vec3.hpp>

namespace sightline {

struct Patch {
    glm::dvec3 corner{0.0};
    glm::dvec3 u{1.0, 0.0, 0.0};
    glm::dvec3 v{0.0, 1.0, 0.0};
    int na = 32;   ///< samples along u
    int nb = 32;   ///< samples along v

    int sampleCount() const { return na * nb; }
    glm::dvec3 sample(int a, int b) const
    {
        return corner + (a + 0.5) / na * u + (b + 0.5) / nb * v;
    }
    /// Sample by bit index i = b * na + a.
    glm::dvec3 sample(int i) const { return sample(i % na, i / na); }
    glm::dvec3 normal() const;
    glm::dvec3 centre() const { return corner + 0.5 * (u + v); }
    /// Corner k of the parallelogram, k in [0, 4): c, c + u, c + v, c + u + v (bit 0 adds u, bit 1
    /// adds v). Every method's shaft and culling uses this one expression, so they agree bitwise.
    glm::dvec3 cornerPoint(int k) const { return corner + double(k & 1) * u + double(k >> 1) * v; }
};

/// Limits on sample grids. The source set is a bitmask of at most 1024 bits (8 RGBA32UI render
/// targets, Eisemann & Décoret §6.1); receiver grids go to 1024 x 1024 (a 512x512 floor is the
/// documented target, the rest is head-room).
inline constexpr int kMaxSourceSamples = 1024;
inline constexpr int kMaxReceiverSide = 1024;

/// Throws sightline::Error when a patch cannot be sampled: non-finite numbers, zero-length or
/// parallel edges (degenerate), sample counts outside the limits. `role` is "source" or "receiver".
void validatePatch(const Patch& patch, const std::string& role);

/// Throws sightline::Error unless both patches are valid and each lies entirely, strictly, on one
/// side of the other's plane (docs/design.md §2). Touching or crossing the other's plane is refused.
void validatePatchPair(const Patch& source, const Patch& receiver);

} // namespace sightline
