#pragma once
// Internal to the CPU bitmask sampler: the bitmask pass (§2-5). Receiver samples are cut into
// square tiles, each a unit of parallel work that owns its samples' rows (no two threads write
// one bitmask); each tile walks the occluders whose influence region meets it, largest first,
// each on the cheapest path its own samples allow (Path), skipping those the narrowed shaft
// rules out (Narrowing.h).

#include <cstdint>
#include <vector>

#include "../BitmaskRows.h"
#include "Occluders.h"
#include "Shaft.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline::bitmask {

/// Tiles of 8x8 receiver samples; 8x8 against 4x4 on the 128x128 wall receiver, 1024 source
/// samples: 27% more pairs (coarser narrowing) but a third less per-(occluder, tile) work.
constexpr int kTile = 8;

/// What the per-tile loop reads of an occluder, stored in processing order so that a tile's walk
/// through its bin runs forwards through memory: loading a whole Occluder was the loop's largest
/// stall.
struct TileOccluder {
    detail::FloatPolygon single;   ///< the vertices (and parallel factors) as float pairs
    std::int16_t a0, a1, b0, b1;   ///< receiver sample range (kMaxReceiverSide fits)
    Path path;
    bool closed;                   ///< of a watertight instance (culling may trim it, §7)
    double maxD;
    const Occluder* occluder;      ///< the double-precision data
};
static_assert(kMaxReceiverSide <= 32767, "TileOccluder's sample range");

/// An occluder's place in the largest-first order: `rank` from sizeRank, smaller first.
struct SizeKey {
    std::uint32_t rank;
    std::uint32_t occluder;
};

/// A 24-bit rank that orders sizes (backprojected cells, >= 0) largest first, to within 2^-12 of
/// each other: sizes that close may share a rank.
std::uint32_t sizeRank(double cells);

/// Sorts by rank, equal ranks keeping their order (stable): two counting passes of 12 bits, where
/// a comparison sort took a tenth of a swapped call's setup. `scratch` is working storage.
void sortLargestFirst(std::vector<SizeKey>& keys, std::vector<SizeKey>& scratch);

/// Per tile, the occluders whose region meets it, largest first: they block the most, and what
/// they block narrows the shaft for the small ones that follow. One global sort, then binning in
/// that order, keeps every bin sorted. Storage is kept between calls.
class TileBins {
public:
    /// `leave`: per occluder of `set`, left out (the hybrid's small triangles); may be empty.
    /// `closedInstance`: per instance, a watertight mesh (TileOccluder::closed); may be empty.
    void build(const Shaft& shaft, const OccluderSet& set, const std::vector<char>& leave,
               const std::vector<char>& closedInstance, const WorldTriangles& triangles);

    int tilesA() const { return tilesA_; }
    std::size_t tileCount() const { return bins_.size(); }
    const std::vector<std::uint32_t>& bin(std::size_t tile) const { return bins_[tile]; }
    const TileOccluder& occluder(std::uint32_t position) const { return tileOccluders_[position]; }
    /// The receiver samples (bit indices) of a tile, appended to `out`.
    void tileSamples(std::size_t tile, int receiverNa, int receiverNb, std::vector<int>& out) const;

private:
    int tilesA_ = 0;
    std::vector<SizeKey> keys_, keysScratch_;
    std::vector<std::uint32_t> order_;
    std::vector<TileOccluder> tileOccluders_;   // in order_
    std::vector<std::vector<std::uint32_t>> bins_;   // positions in tileOccluders_
};

struct TilePassCounts {
    std::uint64_t pairs = 0;            ///< (occluder, receiver sample) pairs backprojected
    std::uint64_t floatPairs = 0;       ///< of those, answered by the float kernel
    std::uint64_t floatFallbacks = 0;   ///< pairs the kernel could not prove, sent to double
    std::uint64_t narrowedAway = 0;     ///< (occluder, tile) pairs the narrowed shaft skipped

    TilePassCounts& operator+=(const TilePassCounts& other);
};

/// The float kernel answers a lane only when the samples it may get wrong lie within this many
/// metres (ray to occluder boundary) of the exact answer's boundary: well inside the contract's
/// ties (1e-5 m), so nothing it answers can be a non-tie disagreement (BitmaskRows.h).
constexpr double kFloatBandBudget = 6e-6;

/// Runs the pass over every tile, or over the tiles `only` lists (positions in the bins), in
/// parallel; ORs into `map`.
TilePassCounts bitmaskPass(const Shaft& shaft, const TileBins& bins, HiddenSampleMap& map, bool narrow,
                           const std::vector<std::uint32_t>* only = nullptr);

} // namespace sightline::bitmask
