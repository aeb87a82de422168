#pragma once
// The reference for leaf-to-leaf visibility: a witness is a segment from a point inside one leaf to
// a point inside another that passes only through leaves a line of sight may cross (the first
// leaf's contents; with clear liquids, empty and liquid alike). The segment is followed through the
// BSP's own planes in double precision, split at every plane it crosses, so a witness is exact in
// the level's own terms; a row that lacks a witnessed leaf is wrong. Witnesses are searched, not
// proved absent: the search says where a row is wrong, never that it is tight.
//
// Candidate ends favour the places slivers of visibility hide: every corner and edge midpoint of
// the leaf's boundary (its tree portals, open or not), pulled a thousandth of the way to its
// centre, then random points between them and the centre.

#include <cstdint>
#include <utility>
#include <vector>

#include "visibility/bsp/BspPortals.h"
#include "visibility/bsp/QuakeBsp.h"
#include "visibility/pvs/PvsData.h"

namespace sightline::bsp {

/// Whether the segment a-b stays in leaves a line of sight from `contents` may cross.
bool segmentOpen(const QuakeBsp& bsp, const glm::dvec3& a, const glm::dvec3& b, int contents, bool clearLiquids);

struct WitnessOptions {
    int segmentsPerPair = 64;
    int pointsPerLeaf = 48;      ///< candidate ends per leaf (corners and edge midpoints first)
    std::uint64_t seed = 1;
    bool clearLiquids = false;
    int threads = 0;             ///< 0: all cores
};

struct WitnessCount {
    std::size_t pairs = 0;       ///< pairs searched
    std::size_t witnessed = 0;   ///< pairs a witness was found for
    std::vector<std::pair<int, int>> examples;   ///< culled: up to 16 witnessed pairs (leaf numbers), sorted
};

/// Searches every unordered pair of visleafs joined by open portals (directly or through others)
/// that `rows` culls (culled: either row lacks the other leaf) or keeps (both rows hold the other),
/// as `culled` asks. Deterministic for a seed.
WitnessCount searchWitnesses(const QuakeBsp& bsp, const std::vector<LeafPortal>& treePortals,
                             const pvs::VisibilityRows& rows, bool culled, const WitnessOptions& options);

} // namespace sightline::bsp
