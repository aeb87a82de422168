#pragma once
// Leaf-to-leaf visibility over a BSP's portals, safe: a leaf is culled from another's row only
// when no line of sight can join them, proved from the portals' geometry, never sampled.
//
// A line from leaf A to leaf B crosses a chain of portals A -> ... -> B, each leaving the leaf the
// last one entered, each crossed from behind its plane to its front. For one starting portal the
// search walks such chains (Teller's portal sequences, as Quake's vis) and keeps, at each step,
// the part of the next portal a line through the whole chain so far could still cross:
//  - in front of the starting portal's plane, and the source (the starting portal's winding) cut to
//    what lies behind the next portal's plane;
//  - inside the anti-penumbra of the source and the previous portal: every plane through an edge of
//    one and a corner of the other that has one wholly on each side separates them, so a line
//    through both stays beyond it (docs/pvs.md derives it); and the source is cut, the same way, to
//    what the lines through the last two portals reach when followed backwards.
// Each separation is tested on the windings' actual extents (min/max along the plane's normal), not
// on a fixed epsilon, and every cut keeps a margin of kPortalOnPlane: windings only ever grow by
// rounding, so the rows hold every leaf a line reaches (lines within the margin of an edge are ties).
// A first flood through the portals that face each other bounds every chain (vis's "might see").

#include <cstddef>
#include <vector>

#include "visibility/bsp/BspPortals.h"
#include "visibility/bsp/QuakeBsp.h"
#include "visibility/pvs/PvsData.h"

namespace sightline::bsp {

struct PortalVisOptions {
    /// Chain steps one starting portal may take before its row falls back to its flood (still safe,
    /// only looser): bounds the time a hostile level can cost.
    std::size_t stepsPerPortal = 20'000'000;
    int threads = 0;   ///< 0: all cores
};

struct PortalVisStats {
    std::size_t directedPortals = 0;
    std::size_t floodPortals = 0;     ///< summed over directed portals: what the first flood reaches
    std::size_t visiblePortals = 0;   ///< summed: what the chains reach
    std::size_t steps = 0;            ///< chain steps taken
    std::size_t portalsOverBudget = 0;   ///< starting portals whose rows fell back to the flood
};

/// Rows over the level's visleafs (row l, bit m: leaf l + 1 sees leaf m + 1) from its open portals
/// (openPortals). Every leaf sees itself and its neighbours. Throws sightline::Error when the
/// portals' bit sets would pass pvs::kMaxRowTableBytes.
pvs::VisibilityRows portalVis(const QuakeBsp& bsp, const std::vector<LeafPortal>& open,
                              const PortalVisOptions& options = {}, PortalVisStats* stats = nullptr);

/// The same over any convex leaves 1..leafCount and the portals between them (pvs/OpenSpace.h's
/// boxes): nothing here needs a BSP but the leaves' count.
pvs::VisibilityRows portalVis(int leafCount, const std::vector<LeafPortal>& open, const PortalVisOptions& options = {},
                              PortalVisStats* stats = nullptr);

} // namespace sightline::bsp
