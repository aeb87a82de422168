#pragma once
// The PVS bake: which objects (and, on request, which other cells) each view cell
// may see.
//
// An object is visible from a cell when some segment from a point of the cell's box to a point of
// the object's triangles meets no other triangle (docs/design.md §4). Per cell, the objects are visited
// through a tree of their bounds (a BVH, deterministic median splits), and for each group box or
// object the bake asks ShaftSearch.h, which answers with one of:
//
//  - Visible: a witness, a first-hit ray (FirstHitCaster.h) from a point of the cell whose first
//    triangle is the object's (for a group box: a ray reaching the box). Boxes that overlap the
//    cell are visible by definition (no witness). When the first, small budget of sub-shafts
//    settles nothing, a few direct rays from stratified points of the cell towards points of the
//    object's triangles (the point of each triangle nearest the cell's centre for objects of at
//    most 64 triangles, then area-stratified ones) look for a witness on the object itself (a
//    chair or a plant fills little of its box).
//  - Hidden: a proof (ShaftProof.h): the face pairs between the cell's box and the target's box
//    cover every segment between them; each was split into sub-shafts until every one was shown
//    blocked by a single planar region or a single closed solid. A hidden group hides all of its
//    objects at once.
//  - Unknown: neither, within the pass's budget (sub-shafts per target, smallest gap split to).
//
// Before any of that, objects the open space proves hidden from the block's or the cell's box
// (OpenSpace.h: a portal vis over the boxes between the scene's axis-aligned walls) are culled,
// unless their box meets it.
//
// Passes. The coarse pass works on blocks: neighbouring cells (at most kBlockCells, grouped by a
// tree of the cells' bounds) whose union box is tested as one source. What is proven hidden from
// a block's box is hidden from each of its cells, so the coarse rows (everything the block did
// not prove hidden) are conservative and come early: the editor has a usable answer for every
// cell at a fraction of the cost. The refine pass then bakes each cell alone, over what its block
// did not prove hidden: first with the coarse budget (`coarseShafts` sub-shafts per target) and
// the direct rays, then, for what is still Unknown, with the fine budget. What is Unknown after
// that is where visibility, if any, passes through openings narrower than the smallest gap: the
// default mode spends `residueRays` rays there looking for a witness and culls the pair when none
// is found (sampling can miss such visibility, never invent it); the safe mode keeps it visible,
// so every pair the safe mode culls is proven hidden.
//
// Distance cut-off (`maxDistance` > 0): an object or cell whose box is farther than that from every
// point of the cell's box is culled without a test (a designer's choice, not visibility).
//
// Determinism: each cell's row depends only on the scene, the settings, the cell list and the cell
// (its block is a function of the cell list; no state is shared between cells; seeds come from
// the scene hash and the cell or block id; traversal orders are fixed), so the output is
// byte-identical whatever the thread count or the split of cells over shards or ranks (a shard
// bakes the blocks of its cells itself).

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "visibility/Scene.h"
#include "visibility/pvs/PvsData.h"
#include "visibility/pvs/ShaftSearch.h"

namespace sightline::pvs {

class FirstHitCaster;
class OpenSpace;
struct OpenSpaceStats;

/// The settings' integer ranges (PvsSettings::validate; the project's "pvs" key is checked
/// against them before narrowing to int).
inline constexpr int kMaxCoarseShafts = 1 << 20;
inline constexpr int kMaxFineShafts = 1 << 24;
inline constexpr int kMaxResidueRays = 1 << 20;

struct PvsSettings {
    int coarseShafts = 16;      ///< sub-shafts per (cell, target) at first (a block: kBlockShafts times more)
    int fineShafts = 512;       ///< sub-shafts per (cell, target) still Unknown after the coarse budget
    double smallestGap = 0.02;  ///< metres: the refine pass splits sub-shafts down to this spread
    int residueRays = 65536;    ///< default mode: rays per pair over what is left open (ShaftSearch.h)
    int directCellPoints = 8;   ///< direct rays (after the first budget): points of the cell
    int directObjectPoints = 8; ///< direct rays: area-stratified points on the object
    double maxDistance = 0.0;   ///< metres; 0: no distance cut-off
    bool cellRows = false;      ///< also bake cell-to-cell rows (the Quake formats' clusters)
    bool refine = true;         ///< run the refine pass
    /// Safe mode: pairs left Unknown stay visible, so every culled pair is proven hidden.
    bool safe = false;
    /// Cull first what the open space proves hidden (OpenSpace.h); off only to measure it.
    bool openSpace = true;
    int threads = 0;            ///< 0 = all cores (the answer never depends on it)

    /// Canonical text of the settings that change the answer (not `threads`): part manifests and
    /// the .pvs header's settings hash are built from it.
    std::string canonical() const;
    /// Throws sightline::Error for values out of range.
    void validate() const;
};

/// The coarse pass's smallest gap (metres): it stops splitting early and leaves the rest Unknown.
inline constexpr double kCoarseGap = 0.25;
/// Cells per block of the coarse pass (at most), and its sub-shafts per (block, target), in
/// coarse_shafts: a block's answer serves all its cells.
inline constexpr std::uint32_t kBlockCells = 16;
inline constexpr int kBlockShafts = 2;

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
    double coarseMs = 0.0, refineMs = 0.0, cellRowsMs = 0.0;
    std::uint64_t overlapPairs = 0, directWitnesses = 0, shaftWitnesses = 0;
    std::uint64_t provenHidden = 0;     ///< pairs culled by a proof (their own, or their group's)
    std::uint64_t spaceHidden = 0;      ///< of those, by the open space's (OpenSpace.h)
    std::uint64_t unknownPairs = 0;     ///< pairs Unknown after the last pass
    std::uint64_t safeKept = 0;         ///< of those, kept visible by the safe mode
    std::uint64_t distanceCulled = 0;   ///< pairs culled by the distance cut-off
    std::uint64_t nodeTests = 0;        ///< object groups (BVH nodes) tested
    std::uint64_t nodesCulled = 0;      ///< of those, proven hidden with all their objects
    std::uint64_t directCasts = 0;      ///< direct rays cast
    SearchStats search;                 ///< sub-shafts, casts, proofs
    void add(const PvsStats& o);
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
    const PvsSettings& settings() const { return settings_; }

    /// Bakes the listed cells (indices into cells(); all when empty): the coarse pass over all of
    /// them first, then refinement. Returns rows for every cell (cells not listed stay all zero).
    /// Throws PvsCancelled when progress.cancel is set.
    VisibilityRows bake(const std::vector<std::size_t>& cellIndices = {}, const PvsProgress& progress = {},
                        PvsStats* stats = nullptr) const;

    /// Cell-to-cell rows for the listed cells (all when empty): bit d of row c is set when some
    /// segment between the boxes of cells c and d meets no triangle (witnessed; proven hidden
    /// otherwise, or, after the budget, as the mode says). Each row is baked from its own cell's
    /// side, so in the default mode two rows may disagree on a pair. Every cell sees itself.
    VisibilityRows bakeCellRows(const std::vector<std::size_t>& cellIndices = {}, const PvsProgress& progress = {},
                                PvsStats* stats = nullptr) const;

    /// How many blocks the cells are grouped in for the coarse pass (at most kBlockCells cells
    /// each, neighbours by the cell tree's median splits), and the block of a cell.
    std::size_t blockCount() const { return blocks_.size(); }
    std::size_t blockOf(std::size_t cell) const { return blockOf_[cell]; }
    /// The open space's partition and vis (OpenSpace.h), built with the baker.
    const OpenSpaceStats& openSpaceStats() const;

private:
    /// Visits the object tree from a box: nodes proven hidden hide their objects (`hide`), the
    /// objects of the others that are `pending` are tested one by one (`testObject`).
    void traverse(const Bounds& from, const std::function<bool(std::size_t)>& pending, const SearchLimits& limits,
                  std::uint64_t seed, const std::function<void(std::size_t)>& testObject,
                  const std::function<void(std::size_t)>& hide, PvsStats& stats) const;
    /// The coarse pass for a block: the objects proven hidden from every point of its box.
    std::vector<std::uint8_t> bakeBlock(std::size_t block, PvsStats& stats) const;
    /// The refine pass for a cell: its row, given what its block proved hidden.
    std::vector<std::uint8_t> bakeCell(std::size_t cell, const std::vector<std::uint8_t>& blockHidden, PvsStats& stats) const;
    bool visibleByDirectRays(std::size_t cell, std::size_t object, PvsStats& stats) const;
    bool hitsObject(const glm::vec3& from, const glm::vec3& towards, float tfar, std::size_t object) const;
    std::uint64_t cellSeed(std::size_t cell) const;

    std::vector<Bounds> cells_;
    std::vector<PvsObject> objects_;
    std::vector<std::int32_t> objectOfInstance_;
    std::uint64_t seed_ = 0;
    PvsSettings settings_;
    std::unique_ptr<FirstHitCaster> caster_;
    std::unique_ptr<ShaftProver> prover_;
    std::unique_ptr<ShaftSearch> search_;
    std::unique_ptr<OpenSpace> openSpace_;
    /// Objects the open space proves hidden from `box` whose bounds do not meet it (boxes that
    /// meet are visible by definition), added to `hidden`; counted in `stats`.
    void hideByOpenSpace(const Bounds& box, std::vector<std::uint8_t>& hidden, PvsStats& stats) const;
    /// Boxes grouped by bounds: a binary tree, node 0 the root; a leaf holds one item.
    struct Node {
        Bounds bounds;
        std::int32_t item = -1;
        std::uint32_t first = 0, second = 0;
        std::uint32_t begin = 0, end = 0;   ///< its items: order[begin, end)
    };
    struct Tree {
        std::vector<Node> nodes;
        std::vector<std::uint32_t> order;
        std::vector<std::uint32_t> position;   ///< item -> its index in order
    };
    static Tree buildTree(const std::vector<Bounds>& boxes);
    Tree objectTree_, cellTree_;
    struct Block {
        Bounds bounds;
        std::vector<std::size_t> cells;
    };
    std::vector<Block> blocks_;
    std::vector<std::size_t> blockOf_;
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
