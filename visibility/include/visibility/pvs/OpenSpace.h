#pragma once
// What any point of a box can see at most, proved for all view cells at once from the scene's
// axis-aligned walls: the open space around the scene cut into boxes, the openings between them,
// and a portal vis over those (docs/pvs.md, "Open space").
//
// A kd-tree splits a box around the scene, the cells and the objects at the planes of the planar
// regions of ShaftProof.h (coplanar axis-aligned triangles fused across shared edges: a wall, a
// floor), the plane with the most region area in a node first. Two leaves whose closed boxes share
// a rectangle of positive area meet in a passage on their split plane; the passage is sealed when
// the plane's triangles cover the closed rectangle, and otherwise its portal is the convex hull of
// what they leave uncovered (a wall's passage shrinks to its doorway).
//
// Why it is a proof. A segment from a point p of a box to a point q of an object that meets no
// triangle before q stays inside the root box (convex, holding both) and goes from leaf to leaf.
// Where it leaves one leaf's closed box it is on the closed rectangles that leaf shares with the
// leaves around that point (one at a face, several at an edge or a corner); were one of them sealed,
// the point would be on a triangle. So consecutive leaves on the segment are joined by open passages,
// and the segment is a line through that chain of portals, which the portal vis (bsp/PortalVis.h:
// Teller's portal sequences, separating planes, windings that only ever grow) keeps; q is in the
// closed box of the last leaf. An object none of whose triangles meets a leaf that some leaf of the
// box reaches is hidden from every point of the box. Leaves no open passage joins to a leaf of
// any source box (a sealed room, the inside of a wall) are dropped before the vis; when the open
// leaves or portals pass the limits, each leaf's row is its whole connected part (the flood alone:
// still a proof, only looser).

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"
#include "visibility/pvs/PvsData.h"

namespace sightline::pvs {

class ShaftProver;

struct OpenSpaceLimits {
    std::size_t maxLeaves = 12'000;          ///< kd leaves built, at most
    /// Square metres a region's bounds must cover for its plane to split: walls, not furniture
    /// (a passage a wall partly covers shrinks to what it leaves open, so doorways need no split).
    double minSplitArea = 4.0;
    std::size_t maxVisLeaves = 4'000;        ///< open leaves the portal vis takes, at most
    std::size_t maxVisPortals = 4'000;       ///< open portals the portal vis takes, at most
    std::size_t stepsPerPortal = 20'000;     ///< the portal vis's budget (PortalVisOptions)
    int threads = 0;                         ///< the portal vis's; 0: all cores
};

struct OpenSpaceStats {
    std::size_t leaves = 0, passages = 0, sealedPassages = 0;
    std::size_t openLeaves = 0, openPortals = 0;   ///< in the parts some source box touches
    std::size_t parts = 0;                          ///< connected parts some source box touches
    bool portalVis = false;                         ///< false: rows are whole parts (over the limits)
    double buildMs = 0.0, visMs = 0.0;
};

class OpenSpace {
public:
    /// `objects`: each object's world triangles (3 vertices each); `sources`: every box hiddenFrom
    /// will be asked about (the cells and the blocks), so the vis covers their parts only.
    OpenSpace(const ShaftProver& prover, const Bounds& sceneBounds, const std::vector<std::vector<glm::vec3>>& objects,
              const std::vector<Bounds>& sources, const OpenSpaceLimits& limits = {});

    /// Bits over the objects (VisibilityRows layout): set for an object no segment from a point of
    /// `box` reaches (above). A box outside the root or touching a leaf no source touched: none set.
    std::vector<std::uint8_t> hiddenFrom(const Bounds& box) const;

    /// The boxes some segment from a point of `from` may enter, as flags over the open boxes;
    /// empty when that is not known (then every box may be).
    std::vector<char> reachableFrom(const Bounds& from) const;
    /// Whether no point of `target` is reached (a cell-to-cell row): no box meeting it is in
    /// `reachable` (reachableFrom's answer).
    bool hides(const std::vector<char>& reachable, const Bounds& target) const;

    const OpenSpaceStats& stats() const { return stats_; }

    struct Box {
        glm::dvec3 lo{0.0}, hi{0.0};
    };
    struct Node {
        Box box;
        int axis = -1;   ///< -1: a leaf
        double split = 0.0;
        std::uint32_t child[2]{0, 0};
        std::int32_t leaf = -1;
    };

private:
    void build(const ShaftProver& prover, const Box& root, const OpenSpaceLimits& limits);
    void leavesMeeting(const Box& box, std::vector<std::uint32_t>& out) const;
    template <class Test>
    void leavesWhere(const Test& meets, std::vector<std::uint32_t>& out) const;
    /// Whether `box` is inside the root (what the answers hold for).
    bool inside(const Bounds& box) const;

    std::size_t objectCount_ = 0;
    std::vector<Node> nodes_;
    std::vector<std::uint32_t> leafNode_;        ///< per leaf, its node
    std::vector<std::int32_t> openIndex_;        ///< per leaf: its row in objectRows_, -1: not in a source's part
    std::vector<std::uint8_t> objectRows_;       ///< per open leaf, the objects it may see (bits)
    VisibilityRows leafRows_;                    ///< the portal vis's rows over the open leaves
    std::vector<std::uint32_t> partOf_;          ///< without the vis: each open leaf's connected part
    OpenSpaceStats stats_;
};

/// Whether the closed triangle abc and the closed box meet (separating axes, Akenine-Möller), in
/// double; `margin` grows the box.
bool triangleMeetsBox(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const OpenSpace::Box& box, double margin);

} // namespace sightline::pvs
