#pragma once
// Internal to the CPU bitmask sampler: one call's shaft between the patches, as every part of the
// method sees it. Receiver samples in the source frame (ShaftGeometry.h: (s, t, d)), in double
// and as float pairs for the SIMD kernel; each receiver sample's jitter shift (§6.2); a bumpy
// receiver's levels (§8); the choice of path per occluder and set of samples; the slab clip.

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "../BitmaskRows.h"
#include "visibility/HoughMaskTable.h"
#include "visibility/Patch.h"
#include "visibility/ShaftGeometry.h"
#include "visibility/SourceJitter.h"

namespace sightline::bitmask {

/// How an occluder is backprojected from a set of receiver samples, cheapest first.
enum class Path : std::uint8_t {
    Float,    ///< the single-precision kernel (BitmaskRows.h): well conditioned for every sample
    Double,   ///< double precision, every vertex closer to the source than every sample
    Clip,     ///< some vertex may reach a sample's distance: clipped per sample
};

struct Shaft {
    ShaftFrames frames;
    int S, na, nb;                         ///< source grid
    int rna, rnb;                          ///< receiver grid
    const HoughMaskTable* table = nullptr; ///< Table mode (§5); exact when null
    std::vector<glm::dvec3> receiverInSource;   ///< (s, t, d) of each receiver sample in the source frame
    std::array<glm::dvec3, 4> sourceCornersInReceiver;
    double minReceiverDistance = 0.0;      ///< min over receiver of d_source
    bool parallel = false;                 ///< the receiver's distance from the source plane is constant
    double receiverDistance = 0.0;         ///< that distance, when parallel
    glm::dvec3 receiverCentre{0.0};        ///< in the source frame
    bool floatKernel = false;              ///< the SIMD kernel may take well-conditioned occluders
    bool jittered = false;
    std::vector<glm::dvec2> jitterShift;   ///< per receiver sample: its source grid's offset in (s, t)
    std::vector<float> receiverS, receiverT, receiverD;   ///< receiverInSource in float
    std::vector<float> rowCentres;         ///< the SIMD kernel's source rows
    double metresPerS = 1.0, metresPerT = 1.0;   ///< |u|, |v| of the source
    /// A bumpy receiver (§8): receiverInSource holds the displaced samples, and influence regions
    /// are projected onto the receiver-frame planes d = levels[0] (lowest bump) and d = levels[1]
    /// (highest). Flat: the receiver plane alone, d = 0.
    bool bumpy = false;
    std::array<double, 2> levels{0.0, 0.0};
    int levelCount = 1;
    double bumpySourceMargin = 0.0;    ///< clip at d_source > this
    double bumpyReceiverLevel = 0.0;   ///< clip at d_receiver > this

    /// `displaced`: a bumpy receiver's sample positions (world space, by bit index); null: flat.
    Shaft(const Patch& source, const Patch& receiver, const SourceJitter& jitter, const std::vector<glm::dvec3>* displaced);

    /// The triangle clipped to the part of the slab any segment can reach (ShaftGeometry.h).
    ClippedPolygon clip(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const;

    /// The distance from the source plane of the nearest receiver sample in [a0, a1] x [b0, b1]
    /// of a flat receiver: the distance is affine over the plane, so one of the box's corners.
    double nearestSample(int a0, int a1, int b0, int b1) const
    {
        const auto d = [&](int a, int b) { return receiverInSource[std::size_t(b * rna + a)].z; };
        return std::min(std::min(d(a0, b0), d(a1, b0)), std::min(d(a0, b1), d(a1, b1)));
    }

    /// The path for an occluder reaching `maxD` from the source, backprojected from receiver
    /// samples no nearer than `nearest`. Flat: the receiver-side clip margin already keeps every
    /// vertex out of the end margin. Bumpy: only occluders wholly short of the nearest displaced
    /// sample skip the per-sample clip; those reaching into the bump range are clipped at each
    /// sample's own distance. Float: d_R / (d_R - d_X) <= kMaxFloatFactor for every sample and
    /// vertex.
    Path pathFor(double maxD, double nearest) const;

    /// Vertices at or beyond a receiver sample's own distance d cannot lie on its segments: the
    /// part of an occluder that can hide anything from it lies short of this (the end margin of
    /// ExactSegment.h). For a bumpy receiver this is where the parts beyond a displaced sample
    /// (farther from the source than the sample) stop blocking it.
    static double clipDistance(double d);

private:
    void setBumps(const std::vector<glm::dvec3>& displaced);
};

} // namespace sightline::bitmask
