#pragma once
// The CPU sampler's ray casting: the reference's answer (RayCastSampler.h), bit for bit, from a
// float tracer set up as a user tuning Embree would (the price of exactness: docs/benchmarks.md).
//
// Two passes:
// 1. Embree traverses its own float triangles with the setup a user tuning it would pick (flat
//    scene, not robust, BVH built once per scene in a frame centred on it), and every hit it
//    reports is either proven a crossing by the contract from the reported numbers alone
//    (HitProof.h: an a-priori bound on Embree's float error, no memory touched) or tested by the
//    contract's own double test, ExactSegment.h, and dropped where that test says no. A ray this
//    pass blocks is blocked by the contract, as the reference computes it.
// 2. Float traversal can miss a crossing (a ray near an edge of a triangle it sees nearly edge-on:
//    no bound holds for every angle), so the rays pass 1 leaves free are cast by the reference,
//    which is exact by construction. Few rays are left free where ray casting is the right
//    strategy (dense geometry); this pass is most of the cost only where the bitmask is cheaper.
//
// The answer is the reference's, bit for bit: pass 1 blocks only rays the reference's test blocks
// (a proven hit has margins far above double rounding), and pass 2 is the reference. Nothing but
// speed depends on the bound: hits it cannot prove, huge triangles, far-away patches and
// kilometre-long rays all go to the exact test.
//
// Traversal (docs/benchmarks.md, "Ray casting where it is the right strategy"): rays start at the
// end whose partner has the finer grid (at 32-128 source samples, the source), so a packet's 16
// rays run to 4x4 neighbouring samples and share their traversal. Two traversals, timed against
// each other on a few blocks of each call: coherent packets, whose hits are checked after the
// call (rtcIntersect16, no callback), and, where packets diverge (dense meshes at coarse receiver
// grids), Embree's incoherent occlusion traversal (rtcOccluded16: single rays below the top of
// the tree), whose filter records where each ray stopped for the proof after the call.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/RayCastSampler.h"
#include "visibility/Scene.h"

namespace sightline::raycast {

/// How pass 1 traverses.
enum class CastMode {
    Auto,      ///< Packets or Occluded, timed on the call's first blocks (ProvenRayCaster.cpp)
    Packets,   ///< rtcIntersect16 from one end to 16 neighbouring samples of the other, coherent
    Occluded,  ///< rtcOccluded16 on the same 16 rays, incoherent, the proof in an occlusion filter
};

struct ProvenCastStats {
    std::uint64_t floatRays = 0;     ///< rays cast through the float scene (pass 1)
    std::uint64_t provenHits = 0;    ///< hits proven a crossing from the reported numbers
    std::uint64_t exactTests = 0;    ///< hits the proof left to the contract's double test
    std::uint64_t confirmRays = 0;   ///< rays pass 1 left free, cast by the reference (pass 2)
    double floatMs = 0.0;            ///< pass 1
    double confirmMs = 0.0;          ///< pass 2
    bool fromSource = false;         ///< pass 1 started its rays at the source samples
    bool packets = false;            ///< pass 1 cast packets
    bool probedMode = false;         ///< CastMode::Auto timed both ways on this call
};

class ProvenRayCaster {
public:
    /// Builds the float BVH (coordinates must be valid: validateCoordinates). Throws
    /// sightline::Error if Embree fails.
    explicit ProvenRayCaster(const WorldTriangles& triangles);
    ~ProvenRayCaster();
    ProvenRayCaster(const ProvenRayCaster&) = delete;
    ProvenRayCaster& operator=(const ProvenRayCaster&) = delete;

    double buildMilliseconds() const;

    /// Casts the rays of the pair not yet blocked in `map` and marks those the scene blocks:
    /// RayCastScene::sampleUnblocked's contract and answer (jitter, heights, receiverSubset,
    /// threads), with `exact` the reference scene over the same triangles (pass 2). Returns the
    /// rays cast by pass 1.
    std::uint64_t sampleUnblocked(const Patch& source, const Patch& receiver, HiddenSampleMap& map,
                                  const RayCastOptions& options, const RayCastScene& exact, CastMode mode = CastMode::Auto,
                                  ProvenCastStats* stats = nullptr) const;

    /// Tests only: also run the double test on every proven hit, counting disagreements (a sound
    /// proof has none).
    void setVerifyProofs(bool verify) { verifyProofs_ = verify; }
    std::uint64_t proofContradictions() const { return contradictions_.load(); }

    struct Impl;

private:
    /// One sampleUnblocked call's traversals and state.
    class Call;
    std::unique_ptr<Impl> impl_;
    /// CastMode::Auto's last timed choice, serving the next calls on a similar configuration
    /// (as Auto's choice of strategy does, bitmask/Strategy.h).
    struct ModeMemo;
    mutable std::mutex memoMutex_;
    mutable std::unique_ptr<ModeMemo> memo_;
    bool verifyProofs_ = false;
    mutable std::atomic<std::uint64_t> contradictions_{0};
};

} // namespace sightline::raycast
