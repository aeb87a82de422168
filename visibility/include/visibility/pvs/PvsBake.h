#pragma once
// The PVS bake (issue 17 §2): which objects each view cell may see.
//
// An object is visible from a cell when some segment from a point of the cell's box to a point of
// the object's triangles meets no other triangle (DESIGN.md §4). The bake samples that question
// and proves every "visible" it writes with a witness ray: a first-hit cast (FirstHitCaster.h)
// from a point of the cell whose first triangle is the object's. Sampling can therefore only miss
// visibility, never invent it (except for boxes that overlap the cell, which are visible by
// definition of a box and written so). Per (cell, object), in order, stopping at the first witness:
//
//  0. Groups: objects are grouped by bounds (a BVH); a group no unblocked shaft ray of the pass
//     reaches (step 3 against the group's box, its faces sampled at least as densely as the
//     cell's) hides all its objects at once.
//  1. Overlap: the object's bounds meet the cell's box -> visible.
//  2. Direct rays: a few stratified points of the cell (seeded from the scene hash and the cell id)
//     towards, for objects of at most 64 triangles, the point of each triangle nearest the cell's
//     centre (a floor or a long wall is mostly in other rooms), then a few area-stratified points
//     on the object's triangles (seeded from the object).
//  3. Shafts (Eisemann & Décoret 2007, the exact bitmask sampler, CpuBitmaskSampler.h, as §11's
//     from-region future work): between each cell face and each face of the object's bounds that
//     can see each other. A pair of box faces is not always a valid patch pair (DESIGN.md §2:
//     each must lie strictly on one side of the other's plane), so each face is clipped to the part
//     strictly in front of the other's plane (1 mm margin); every segment from the cell to the box
//     leaves the cell through some face F and enters the box through some face G, and its exit
//     and entry points lie in F clipped by G's plane and G clipped by F's, so these clipped pairs
//     cover every segment between the boxes (less the margins). The sampler gives every blocked
//     ray of the pair at once; an unblocked ray reaches the object's *bounds*, which is only a
//     proxy: it is continued into the box with a first-hit cast, and only a first hit on the
//     object counts. A few unblocked rays per pair are tried (spread over the pair's samples).
//
// Passes: the coarse pass runs every cell at the coarse sample counts, so the editor has an
// answer for every cell soon; the refine pass reruns only the pairs the coarse pass left hidden,
// with more samples (adaptive: visible pairs are done, hidden ones are where sampling can miss).
// Safe mode gives up the witness for the refine pass's shafts: a pair whose fine shaft reached the
// object's bounds by an unblocked ray is kept even when no continuation met the object (foliage:
// a box of thin leaves is mostly air). It is conservative with respect to the bounds at the fine
// sample spacing, not a proof of invisibility for what it culls; docs/pvs.md reports what it
// reaches against the reference.
//
// Determinism: each cell's row depends only on the scene, the settings and the cell (no shared
// state between cells, fixed sampler strategy, seeds from the scene hash and cell id), so the
// output is byte-identical whatever the thread count or the split of cells over shards or ranks.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/Scene.h"
#include "visibility/pvs/PvsData.h"

namespace sightline {
class CpuBitmaskSampler;
}

namespace sightline::pvs {

class FirstHitCaster;

struct PvsSettings {
    int coarseSamples = 3;     ///< shaft samples per face side, coarse pass (n x n on each face)
    int fineSamples = 6;       ///< shaft samples per face side, refine pass (at most 32)
    int directCellPoints = 8;  ///< direct rays: points of the cell (coarse pass; refine uses 4x)
    int directObjectPoints = 8;///< direct rays: points on the object (coarse; refine uses 4x)
    int witnessTries = 4;      ///< unblocked shaft rays continued per face pair (coarse; refine 8x)
    bool refine = true;        ///< run the refine pass
    /// Safe mode (refine pass): a pair stays visible when a fine shaft ray reached the object's
    /// bounds unblocked even though no continuation was seen to hit its triangles.
    bool safe = false;
    int threads = 0;           ///< 0 = all cores (the answer never depends on it)

    /// Canonical text of the settings that change the answer (not `threads`): part manifests and
    /// the .pvs header's settings hash are built from it.
    std::string canonical() const;
    /// Throws sightline::Error for counts out of range.
    void validate() const;
};

enum class PvsPass { Coarse, Refine };

/// Bake progress for a caller that shows it (the editor's debugger) or logs it. Called from
/// worker threads, possibly concurrently: keep it cheap and thread-safe.
struct PvsProgress {
    /// A cell's row after a pass (bits over objects, VisibilityRows layout).
    std::function<void(PvsPass pass, std::size_t cell, const std::vector<std::uint8_t>& row)> onCell;
    /// Checked between cells; true stops the bake (bake() then throws PvsCancelled).
    const std::atomic<bool>* cancel = nullptr;
};

struct PvsCancelled : std::exception {
    const char* what() const noexcept override { return "PVS bake cancelled"; }
};

struct PvsStats {
    double coarseMs = 0.0, refineMs = 0.0;
    std::uint64_t overlapPairs = 0, directWitnesses = 0, shaftWitnesses = 0;
    std::uint64_t safeWitnesses = 0;   ///< safe mode: pairs kept for an unblocked ray to the bounds alone
    std::uint64_t shaftPairs = 0;     ///< face pairs sampled with the bitmask sampler
    std::uint64_t shaftRays = 0;      ///< rays those pairs answered
    std::uint64_t witnessCasts = 0;   ///< first-hit casts
    std::uint64_t nodeTests = 0;      ///< object groups (BVH nodes) tested
    std::uint64_t nodesCulled = 0;    ///< of those, hidden with all their objects
};

class PvsBaker {
public:
    /// `sceneSha256` seeds the sampling (with each cell's index). Cells are validated
    /// (validateCells) and settings too; both throw sightline::Error.
    PvsBaker(const Scene& scene, std::vector<Bounds> cells, std::vector<PvsObject> objects, std::string sceneSha256,
             PvsSettings settings);
    ~PvsBaker();

    const std::vector<Bounds>& cells() const { return cells_; }
    const std::vector<PvsObject>& objects() const { return objects_; }

    /// Bakes the listed cells (indices into cells(); all when empty): the coarse pass over all of
    /// them first, then refinement. Returns rows for every cell (cells not
    /// listed stay all zero). Throws PvsCancelled when progress.cancel is set.
    VisibilityRows bake(const std::vector<std::size_t>& cellIndices = {}, const PvsProgress& progress = {},
                        PvsStats* stats = nullptr) const;

    /// One cell, one pass, in the calling thread: `row` holds the previous passes' answer
    /// (empty for the coarse pass) and is updated.
    void bakeCell(std::size_t cell, PvsPass pass, std::vector<std::uint8_t>& row, PvsStats* stats = nullptr) const;

private:
    bool visibleByOverlap(std::size_t cell, std::size_t object) const;
    bool visibleByDirectRays(std::size_t cell, std::size_t object, int cellPoints, int objectPoints,
                             std::uint32_t salt) const;
    bool visibleThroughShafts(std::size_t cell, std::size_t object, int samples, int witnessTries, PvsStats* stats,
                              bool* boxSeen) const;
    std::vector<std::pair<Patch, Patch>> facePairs(const Bounds& cellBox, const Bounds& targetBox, int samples,
                                                   bool denseTarget) const;
    HiddenSampleMap sampleShaft(const Patch& source, const Patch& receiver, PvsStats* stats) const;
    bool boxReachable(std::size_t cell, const Bounds& box, int samples, PvsStats* stats) const;
    void buildObjectTree();
    bool hitsObject(const glm::vec3& from, const glm::vec3& towards, float tfar, std::size_t object) const;

    std::vector<Bounds> cells_;
    std::vector<PvsObject> objects_;
    std::vector<std::int32_t> objectOfInstance_;
    std::uint64_t seed_ = 0;
    PvsSettings settings_;
    std::unique_ptr<FirstHitCaster> caster_;
    std::unique_ptr<CpuBitmaskSampler> sampler_;
    /// Objects grouped by bounds: a binary tree, node 0 the root; a leaf holds one object.
    struct ObjectNode {
        Bounds bounds;
        std::int32_t object = -1;
        std::uint32_t first = 0, second = 0;
        std::uint32_t begin = 0, end = 0;   ///< its objects: treeObjects_[begin, end)
    };
    std::vector<ObjectNode> nodes_;
    std::vector<std::uint32_t> treeObjects_;
    /// Per object: points on its triangles, area-stratified (the direct rays' targets).
    std::vector<std::vector<glm::vec3>> objectPoints_;
    /// Per object of few triangles, its triangles (3 vertices each): nearest-point targets.
    std::vector<std::vector<glm::vec3>> smallSoups_;
};

/// Stratified points: `count` points of a box (a jittered k x k x k grid, k^3 >= count, the first
/// `count` in a fixed order) from `seed`. Shared by the bake and the reference, with different seeds.
std::vector<glm::vec3> boxPoints(const Bounds& box, int count, std::uint64_t seed);

/// `count` points on a triangle soup (3 vertices per triangle), stratified by area, from `seed`.
/// Empty for a soup of zero area.
std::vector<glm::vec3> surfacePoints(const std::vector<glm::vec3>& triangleVertices, int count, std::uint64_t seed);

/// splitmix64, the seeds' mixer.
std::uint64_t mixSeed(std::uint64_t a, std::uint64_t b);
/// The first 16 hex digits of a SHA-256 as a number (0 for an empty string).
std::uint64_t seedFromSha(const std::string& sha256Hex);

} // namespace sightline::pvs
