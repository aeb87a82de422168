#pragma once
// The bitmask visibility sampler on the CPU (Eisemann & Décoret 2007, §2-5), in its exact form.
//
// The paper's loop order: for each triangle, for each receiver sample in its influence region (§3),
// backproject the triangle onto the source (§4) and OR the set of source samples inside the
// backprojection into that receiver sample's bitmask (§5, §5.1). Instead of the paper's
// nearest-texel Hough table, which disagrees with exact ray casts on 2-40% of rays once
// backprojections are about a sample wide, the set is computed exactly: per source-sample row,
// the convex backprojection gives an interval of columns, which becomes a run of set bits.
// Triangles are clipped to the slab between the patch planes first, so triangles crossing a patch
// plane are handled, and the backprojection is the projective map, so patches need not be
// parallel.
//
// Result: exact by docs/design.md §2's contract, as the Embree reference (RayCastSampler.h) is: the
// two may differ only on ties (rays within 1e-5 m of an edge or of their own end). The
// single-precision kernel answers only what it can prove and sends the rest to double
// (BitmaskRows.h); the RayCast strategy casts with the reference's exact method.
//
// A bumpy receiver (§8, ReceiverHeights.h) keeps the method exact: each receiver sample is
// backprojected from its displaced position, influence regions are projected onto the planes of
// the lowest and the highest bump ("on a plane lying behind the receiver"), and occluders that
// reach into the bump range are clipped per receiver sample at that sample's own distance.
//
// Parallelism: triangles are binned to tiles of receiver samples; tiles run on all cores (TBB),
// each owning its receiver rows, so no two threads write one bitmask.

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "visibility/HiddenSampleMap.h"
#include "visibility/HoughMaskTable.h"
#include "visibility/MaskMode.h"
#include "visibility/Patch.h"
#include "visibility/RayCastSampler.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/Scene.h"
#include "visibility/SourceJitter.h"

namespace sightline {

namespace raycast {
class ProvenRayCaster;
}
namespace bitmask {
struct InnerProxy;
}

/// How the exact CPU method splits the work.
enum class CpuStrategy {
    Auto,      ///< by predicted cost (bitmask/Strategy.h): the bitmask's setup per triangle in the
               ///< shaft and pass per (triangle, receiver sample) pair, against ray casting's cost
               ///< per ray, fitted to bench runs; where neither prediction is under
               ///< half the other, both are timed on a few tiles first. Without AVX2 in the CPU,
               ///< Hybrid when the shaft holds enough small triangles. Table mode is always Bitmask.
    Bitmask,   ///< every triangle by backprojection
    Hybrid,    ///< large triangles by backprojection, then only the still-unblocked rays are cast
               ///< against the small ones: ray casting is strong exactly where the bitmask is weak
               ///< (many tiny occluders, each touching many receiver samples)
    RayCast,   ///< every ray cast, with the reference's answer (src/raycast/ProvenRayCaster.h: Embree's
               ///< float triangles, every hit proven or tested exactly, the rays left free confirmed
               ///< by the reference; the bitmask's cost barely drops with fewer source samples, ray
               ///< casting's does)
};

struct BitmaskOptions {
    int threads = 0;                        ///< 0 = all cores
    MaskMode mode = MaskMode::Exact;
    int tableWidth = 256;                   ///< Table: angles
    int tableHeight = 128;                  ///< Table: distances
    CpuStrategy strategy = CpuStrategy::Auto;
    /// Watertight front-face culling (§7) for meshes flagged Mesh::watertight: a triangle that
    /// faces all four source corners is skipped, because a segment that enters a closed mesh
    /// through it also leaves through a back face before reaching a receiver sample outside the
    /// mesh. Applied only to instances whose bounds the receiver patch does not touch, so the
    /// answer never changes.
    bool watertightCulling = true;
    /// Hybrid: a triangle is small when its backprojection from the receiver's centre covers
    /// fewer than this many source-sample cells.
    double smallCells = 2.0;
    /// Per receiver tile, skip small triangles whose backprojection misses every source sample
    /// the tile still sees (what the large occluders already block narrows the shaft). Exact
    /// mode only.
    bool narrowShaft = true;
    /// Exact mode: meshes of many triangles, closed or closed by caps over their few holes,
    /// first answer the rays through their inside with a few hundred large faces around a region
    /// strictly inside the volume (bitmask/InnerProxy.h), by the bitmask, before the chosen
    /// strategy runs over every triangle; rays that meet a cap's box are left to the strategy.
    /// Applied only while both patches lie outside the mesh's bounds, so the answer never
    /// changes.
    bool innerProxy = true;
    /// Exact mode, where the receiver has more samples than the source but no more than a
    /// source may have (kMaxSourceSamples, at most 32 columns), no jitter and no heights: the
    /// patches swap roles, so the bitmask backprojects onto the grid with more samples (its work
    /// follows (triangle, receiver sample) pairs: 1.4-53x fewer at 32-128 source samples against a
    /// 32x32 receiver), and the map comes back transposed. A larger receiver is split into tiles
    /// of up to 32x32 samples, each swapped, where each has more samples than the source. Not
    /// with the RayCast strategy, whose answer is the reference's bit for bit. The answer never
    /// changes but for ties.
    bool swapRoles = true;
    /// Exact mode: run well-conditioned occluders (projection factors up to 16, source grids up
    /// to 32 columns) through the single-precision AVX2 kernel, eight receiver samples at a time,
    /// where the CPU has AVX2; the rest stay in double. False: double everywhere.
    bool simd = true;
    /// Decorrelated source samples per receiver sample (§6.2): each receiver sample's
    /// backprojections are shifted by its own offset. Off by default.
    SourceJitter jitter{};
    /// A bumpy receiver (§8, ReceiverHeights.h): receiver sample j at its displaced position.
    /// Null, empty or all zero: the flat patch, sampled exactly as without heights. Not owned;
    /// must outlive the call. Every strategy and both kernels honour it; the shaft culling is
    /// widened to the bumps, and the narrowed shaft tests every sample of a tile.
    const ReceiverHeights* heights = nullptr;
};

/// How a call spent its time, in detail: for the benchmarks' breakdowns, the cost model's fitting
/// (scripts/fit_auto_costs.py) and the tests that check Auto's choices. Callers that only report a
/// call need BitmaskStats' own fields.
struct BitmaskDebug {
    std::size_t smallTriangles = 0;   ///< hybrid: triangles in the shaft handled by ray casting
    std::uint64_t floatPairs = 0;     ///< pairs backprojected by the single-precision SIMD kernel
    std::uint64_t floatFallbacks = 0; ///< pairs the kernel could not prove exact, sent to double
    std::uint64_t provenHits = 0;     ///< ray casting: float hits proven crossings from Embree's numbers
    std::uint64_t exactHitTests = 0;  ///< ray casting: float hits the proof left to the double test
    std::uint64_t raysConfirmed = 0;  ///< ray casting: rays the float pass left free, cast by the reference
    double rayFloatMs = 0.0;          ///< ray casting: the float pass (traversal, proofs, double tests)
    double rayConfirmMs = 0.0;        ///< ray casting: the reference's cast of the rays left free
    bool rayPackets = false;          ///< ray casting: closest-hit packets (else occlusion queries with a filter)
    std::size_t culledFrontFaces = 0; ///< watertight front faces skipped
    std::size_t proxyFaces = 0;       ///< inner-proxy faces backprojected (BitmaskOptions::innerProxy)
    double proxyMs = 0.0;             ///< of setupMs: the inner proxies' pass and builds
    std::size_t proxiesBuilt = 0;     ///< inner proxies built by this call (kept for later calls)
    std::uint64_t narrowedAway = 0;   ///< (triangle, tile) pairs skipped by the narrowed shaft
    double tableMs = 0.0;             ///< Table: building the Hough table (0 when cached)
    std::uint64_t estimatedPairs = 0; ///< Auto: the pair estimate it chose by (0 when not estimated)
    std::uint64_t estimatedTriangles = 0;  ///< Auto: triangles in the shaft, estimated likewise
    double predictedBitmaskMs = 0.0;  ///< Auto: its cost model's predictions (0 when not estimated)
    double predictedRayMs = 0.0;
    bool probed = false;              ///< Auto: chose by timing both methods on a few tiles
    /// Auto, roles swapped, probed: the rays' whole call as the probe's samples scaled it, and
    /// the bitmask's whole call where it was timed too (0 where not); one thread's ms.
    double probeRayMs = 0.0, probeBitmaskMs = 0.0;
    bool reusedChoice = false;        ///< Auto: took an earlier call's choice, without estimating
    bool reusedTimedChoice = false;   ///< ... and that choice was timed (a probe's)
};

/// What a call did, as a caller reports it: the strategy, the time, and the work in the shaft.
struct BitmaskStats {
    const char* strategy = "";        ///< "bitmask", "hybrid" or "raycast"
    bool swappedRoles = false;        ///< sampled with the patches' roles swapped (BitmaskOptions::swapRoles);
                                      ///< the other counts are the swapped call's
    int receiverTiles = 1;            ///< receiver tiles sampled one by one, each swapped (times and counts
                                      ///< summed; "mixed" strategy where they chose differently)
    double setupMs = 0.0;             ///< clipping, influence regions, binning
    double sampleMs = 0.0;            ///< backprojection and bit setting
    double rayMs = 0.0;               ///< ray casting: hybrid's BVH build of the small triangles and
                                      ///< casts; RayCast's casts
    std::size_t trianglesInShaft = 0; ///< triangles with a non-empty influence region
    std::uint64_t pairs = 0;          ///< (triangle, receiver sample) pairs backprojected
    std::uint64_t raysCast = 0;       ///< rays cast (hybrid: against the small triangles)
    std::uint64_t proxyBlocked = 0;   ///< rays the inner proxies answered, before the strategy ran
    BitmaskDebug debug;               ///< how the time was spent, in detail
};

class CpuBitmaskSampler {
public:
    /// Keeps the world triangles and, per instance, its watertight flag and bounds.
    explicit CpuBitmaskSampler(const Scene& scene);
    /// A bare triangle soup: nothing is known to be watertight.
    explicit CpuBitmaskSampler(WorldTriangles triangles);
    ~CpuBitmaskSampler();

    /// Replaces the scene (the editor moved an object) and keeps the warm buffers (a fresh
    /// sampler's first call pays for its page faults).
    /// Not thread-safe against a concurrent sample().
    void setScene(const Scene& scene);

    /// Buffers reused between calls (private to the implementation).
    struct Workspace;

    std::size_t triangleCount() const { return triangles_.size(); }

    /// Whether this CPU runs the single-precision SIMD kernel (AVX2 and FMA).
    static bool simdAvailable();

    /// Validates the pair (validatePatchPair and, with heights, validateReceiverHeights throw
    /// sightline::Error), then samples.
    HiddenSampleMap sample(const Patch& source, const Patch& receiver, const BitmaskOptions& options = {},
                           BitmaskStats* stats = nullptr) const;

private:
    /// One sampleOriented call's steps and state.
    class OrientedCall;
    /// sample() on a validated pair, in the roles given (`swappedRoles`: the caller's receiver
    /// is `source` here, for Auto's choice).
    HiddenSampleMap sampleOriented(const Patch& source, const Patch& receiver, const BitmaskOptions& options,
                                   BitmaskStats* stats, bool swappedRoles) const;
    /// sample() on a validated pair whose receiver is split into columns x rows tiles
    /// (bitmask::receiverTilesToSwap), each sampled on its own, and the maps put together.
    HiddenSampleMap sampleByReceiverTiles(const Patch& source, const Patch& receiver, const BitmaskOptions& options,
                                          BitmaskStats* stats, int columns, int rows) const;
    /// Per instance: may watertight culling skip its front faces with this receiver? With a
    /// bumpy receiver, `displacedBox` bounds its displaced samples (null: the flat patch).
    std::vector<char> cullableInstances(const Patch& receiver, const Bounds* displacedBox = nullptr) const;
    /// The whole scene's BVH (the reference's), built on first use.
    std::shared_ptr<const RayCastScene> wholeSceneCaster() const;
    /// The whole scene's float BVH for the RayCast strategy, built on first use.
    std::shared_ptr<const raycast::ProvenRayCaster> provenCaster() const;
    /// Instance `i`'s inner proxy (bitmask/InnerProxy.h): built on first use where `build`
    /// allows, or kept from the scene before when its triangles are unchanged; null otherwise.
    /// Counts the proxies it builds in `built`.
    std::shared_ptr<const bitmask::InnerProxy> innerProxy(std::size_t i, bool build, std::size_t* built) const;
    /// Per instance: its watertight flag, bounds and triangles (for the inner proxies).
    void describeInstances(const Scene& scene);
    std::unique_ptr<Workspace> takeWorkspace() const;
    void returnWorkspace(std::unique_ptr<Workspace> work) const;

    struct InstanceInfo {
        bool watertight = false;
        Bounds bounds;
        Bounds triangleBounds;      ///< of its world triangles, exactly
        std::size_t first = 0;      ///< its triangles in triangles_ (contiguous)
        std::size_t count = 0;
    };
    WorldTriangles triangles_;
    std::vector<InstanceInfo> instances_;
    /// The last Hough table built (the editor samples the same grid many times).
    mutable std::mutex tableMutex_;
    mutable std::shared_ptr<const HoughMaskTable> table_;
    /// The whole scene's BVH, built the first time the RayCast strategy is chosen.
    mutable std::mutex rayCasterMutex_;
    mutable std::shared_ptr<const RayCastScene> rayCaster_;
    mutable std::shared_ptr<const raycast::ProvenRayCaster> provenCaster_;
    /// Inner proxies per instance (null: not built), and those of earlier scenes, kept for
    /// instances that come back unchanged.
    mutable std::mutex proxyMutex_;
    mutable std::vector<std::shared_ptr<const bitmask::InnerProxy>> proxies_;
    mutable std::vector<std::shared_ptr<const bitmask::InnerProxy>> earlierProxies_;
    /// Idle workspaces; a call takes one (or makes one) and gives it back.
    mutable std::mutex workspaceMutex_;
    mutable std::vector<std::unique_ptr<Workspace>> idleWorkspaces_;
    /// Auto's last choice between the bitmask and ray casting (estimated or measured), reused
    /// by the next calls on a similar configuration: the editor and animations sample slowly
    /// changing ones, and the estimate and probe cost 10-15% of a call. Cleared by setScene.
    struct StrategyChoiceCache;
    mutable std::mutex probeMutex_;
    mutable std::unique_ptr<StrategyChoiceCache> probeMemo_;
    /// Grid sizes (source na, nb, receiver na, nb) Auto has sampled since the scene was set: a
    /// probe on new ones is cold (bitmask/Strategy.h, probeVerdict). Guarded by probeMutex_.
    mutable std::vector<std::array<int, 4>> sampledGrids_;
};

} // namespace sightline
