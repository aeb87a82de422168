#pragma once
// Internal to the CPU bitmask sampler: the narrowed shaft. Per tile of receiver samples, the
// source samples that some receiver sample of the tile still sees; an occluder whose
// backprojections from the tile cannot contain one of them is skipped for the tile (what the
// large occluders already block narrows the shaft for the small ones that follow).

#include <array>
#include <cstdint>

#include "../BitmaskRows.h"
#include "Occluders.h"
#include "Shaft.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"

namespace sightline::bitmask {

/// Source samples that some receiver sample of a tile still sees: as a box of sample-centre
/// coordinates (empty when min > max), a quick first test, and as the set itself. Leaves and
/// grilles leave scattered holes whose box is nearly the whole source; the set still rejects an
/// occluder whose backprojection covers no open sample.
struct SourceBox {
    double sMin = 1.0, sMax = 0.0, tMin = 1.0, tMax = 0.0;
    std::array<std::uint64_t, kMaxSourceSamples / 64> open{};
    bool empty() const { return sMin > sMax; }
    /// Whether any open sample has a bit index in [first, last].
    bool anyOpen(int first, int last) const;
};

/// The source samples that at least one receiver sample in [a0, a1] x [b0, b1] still sees, from
/// the map as it stands.
SourceBox unblockedBox(const Shaft& shaft, const HiddenSampleMap& map, int a0, int a1, int b0, int b1);

/// Whether the backprojection of `o` from any of the given receiver samples can contain a sample
/// of `box`. The backprojection of a point is an affine (parallel patches) or projective function
/// of the receiver point, so on a flat receiver its extremes over a rectangle of samples lie at
/// the rectangle's corners; a bumpy receiver's rectangle is not planar, so there the caller passes
/// every sample of it. Clip-path occluders always may.
bool mayHit(const Shaft& shaft, const Occluder& o, Path path, const int* samples, int sampleCount, const SourceBox& box);

/// mayHit for a float-path occluder on a flat receiver, from the four corners of a rectangle of
/// samples, in single precision.
bool mayHitFloat(const Shaft& shaft, const detail::FloatPolygon& polygon, const std::array<int, 4>& corners,
                 const SourceBox& box);

} // namespace sightline::bitmask
