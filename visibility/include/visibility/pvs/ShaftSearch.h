#pragma once
// From a view cell to a target box: is something there visible, proven hidden, or neither?
// (the adaptive part of the PVS bake, in the spirit of the adaptive from-region
// sampling the paper's §11 points to, with the proofs of ShaftProof.h.)
//
// Every segment from the cell's box to the target's box leaves the cell through some face F and
// enters the target through some face G; its exit point lies in F on the outer side of G's plane,
// its entry point in G on the outer side of F's plane. So the face pairs clipped that way
// (coveringFacePairs) cover every such segment, and a target none of whose sub-shafts lets a
// segment through is hidden. Each pair is refined breadth-first:
//
//  - the sub-shaft's central segment (centre of f to centre of g) is cast with Embree
//    (FirstHitCaster.h). If nothing blocks it, it is a witness: for a box target (a group of
//    objects, a view cell) the target is reachable; for an object target the segment is continued
//    into the box and counts only when its first hit is the object's.
//  - otherwise the first few triangles it meets are tried as blockers of the whole sub-shaft
//    (ShaftProof.h: a planar region, or a ball inside a closed solid). Proven: done.
//  - otherwise the sub-shaft is split in two across an edge of f or g: the one whose half moves
//    the central segment's crossing with the first blocker's plane the most (the spread there),
//    unless the segments' spread at the blocker is already below `smallestGap`; such sub-shafts
//    are left open.
//
// Hidden: every sub-shaft proven. Visible: a witness. Unknown: sub-shafts left open (at the
// smallest gap or when the budget of sub-shafts ran out). The default mode then spends
// `residueRays` rays spread over what is left open, looking for a witness (the "nearly blocked"
// part, where sampling must be dense); the safe mode keeps Unknown as visible.
//
// Deterministic: the order of sub-shafts and the residue rays' jitter depend only on the inputs
// and `seed`.

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "visibility/Scene.h"
#include "visibility/pvs/ShaftProof.h"

namespace sightline::pvs {

class FirstHitCaster;

enum class Reach { Visible, Hidden, Unknown };

struct SearchLimits {
    int maxShafts = 32;          ///< sub-shafts evaluated for one (cell, target), all face pairs together
    double smallestGap = 0.05;   ///< metres: sub-shafts whose spread at the blocker is below this are not split
    /// Rays over the sub-shafts left open: this many spread over the whole pair, of which the open
    /// sub-shafts get their share of its segments (area x area), at least 64 (0: none).
    int residueRays = 0;
};

struct SearchTarget {
    Bounds box;
    std::int32_t object = -1;   ///< an object (a witness must hit its triangles first), or -1: a box
    /// The target's own instances: their triangles never count as blockers of it.
    OwnInstances own;
};

struct SearchStats {
    std::uint64_t shafts = 0;        ///< sub-shafts evaluated
    std::uint64_t casts = 0;         ///< Embree first-hit casts (central segments, blockers, residue)
    std::uint64_t planeProofs = 0;   ///< sub-shafts proven by a planar region
    std::uint64_t solidProofs = 0;   ///< sub-shafts proven by a closed solid
    std::uint64_t openShafts = 0;    ///< sub-shafts left open (Unknown answers)
    std::uint64_t residueRays = 0;
    std::uint64_t residueWitnesses = 0;   ///< Unknown answers turned Visible by a residue ray
    void add(const SearchStats& o);
};

class ShaftSearch {
public:
    /// `objectOfInstance` maps a scene instance to its object index (-1: none); all three must
    /// outlive the search.
    ShaftSearch(const FirstHitCaster& caster, const ShaftProver& prover, const std::vector<std::int32_t>& objectOfInstance);

    Reach search(const Bounds& cell, const SearchTarget& target, const SearchLimits& limits, std::uint64_t seed,
                 SearchStats* stats) const;

private:
    enum class Outcome { Witness, Proven, Open };
    /// How to split an open sub-shaft: which edge (0, 1: f's u, v; 2, 3: g's), and the
    /// segments' spread where they were blocked (below the smallest gap: not split).
    struct Split {
        int edge = 0;
        double spread = 0.0;
        double smallestGap = 0.0;
        bool hopeless = false;   ///< every blocker met is far smaller than any split could use
        double reach = 0.0;      ///< how far the central segment got (1: to the target's face)
    };
    static void chooseSplit(const Quad& f, const Quad& g, const glm::dvec3& at, const glm::dvec3& normal, double t, Split* split);
    Outcome evaluate(const Bounds& cell, const SearchTarget& target, const Quad& f, const Quad& g, Split* split,
                     SearchStats& stats) const;
    bool witnessRay(const SearchTarget& target, const glm::dvec3& from, const glm::dvec3& to, SearchStats& stats) const;
    /// The default mode's residue over the sub-shafts the search left open (of the pair's `total`
    /// measure): Visible when a ray is a witness, else Unknown.
    Reach residue(const SearchTarget& target, const std::vector<std::pair<Quad, Quad>>& open, double total,
                  const SearchLimits& limits, std::uint64_t seed, SearchStats& stats) const;

    const FirstHitCaster& caster_;
    const ShaftProver& prover_;
    const std::vector<std::int32_t>& objectOf_;
};

/// Face pairs (a face of `cell` clipped to the outer side of the target face's plane, a face of
/// `target` clipped to the outer side of the cell face's plane) that cover every segment from the
/// cell's box to the target's box; empty when the boxes overlap.
std::vector<std::pair<Quad, Quad>> coveringFacePairs(const Bounds& cell, const Bounds& target);

/// Whether two boxes share a point (closed boxes).
bool boxesMeet(const Bounds& a, const Bounds& b);
/// Whether two boxes share interior points (a positive volume).
bool boxesOverlapInside(const Bounds& a, const Bounds& b);

} // namespace sightline::pvs
