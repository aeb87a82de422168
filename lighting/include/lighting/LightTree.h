#pragma once
// A light tree and its cuts (Walter et al.'s Lightcuts, 2005, per tile of points as Barczak's
// tiles x lights): beyond a few hundred lights, most of the lamps that reach a point each add
// little, and a cluster of them can stand in for all: its representative's term, scaled by the
// cluster's total intensity, with the representative's shadow alone. This is an approximation,
// not the contract's exact sum; the CLI charts its error against the reference in the same run.
//
// The tree is over the point lights only (spots, suns and area lights stay exact): a binary tree
// by median splits along the longest axis of the positions. Each node keeps the box of its
// lights, the sum of intensity x colour, the largest range and a representative, chosen at each
// node between its children's with probability proportional to their intensity (a hash of the
// node's index and the seed, so a cut is deterministic).
//
// The cut for a box of points starts at the root and splits, largest first, every node whose
// bound on what it can give any point of the box (total intensity over the squared distance
// between the node's box and the points' box; zero beyond every range) exceeds `error` times the
// estimate of the total (each node's total intensity over the squared distance from its
// representative to the box's centre). Leaves are single lights and count exactly.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/Light.h"

namespace sightline {

class LightTree {
public:
    /// The tree over the point lights of `lights` (validated; they must outlive the tree). `seed`
    /// picks the representatives.
    explicit LightTree(const std::vector<Light>& lights, std::uint64_t seed = 1);

    /// Whether light `index` is in the tree (a point light), so a cut stands for it.
    bool clusters(std::size_t index) const { return index < inTree_.size() && inTree_[index]; }
    std::size_t size() const { return order_.size(); }

    /// One entry of a cut: a single light (exact) or a cluster's stand-in.
    struct Entry {
        std::uint32_t representative = 0;   ///< the light itself, or the cluster's representative
        std::uint32_t count = 1;            ///< lights it stands for
        /// The light to shade with: a single light as it is; for a cluster, the representative with
        /// its colour scaled so that its term times colour is the cluster's total intensity x
        /// colour times the representative's geometry.
        Light standIn;
    };

    /// The cut for points in the box [lo, hi], at most `maxEntries` entries (splitting stops
    /// there). `error` > 0.
    void cut(const glm::dvec3& lo, const glm::dvec3& hi, double error, std::size_t maxEntries, std::vector<Entry>& out) const;

private:
    struct Node {
        glm::dvec3 lo{0.0}, hi{0.0};
        glm::dvec3 colourSum{0.0};     ///< sum of intensity x colour
        double weight = 0.0;           ///< sum of intensity x largest colour channel
        double range = 0.0;            ///< largest range; infinity when some light has none
        std::uint32_t representative = 0;
        std::uint32_t first = 0, count = 0;   ///< its lights in order_
        std::int32_t left = -1, right = -1;
    };
    std::int32_t build(std::uint32_t first, std::uint32_t count, std::uint64_t seed);
    Entry entryOf(const Node& node) const;

    const std::vector<Light>& lights_;
    std::vector<bool> inTree_;
    std::vector<std::uint32_t> order_;
    std::vector<Node> nodes_;
};

} // namespace sightline
