#pragma once
// The reference sampler: every receiver-sample -> source-sample segment against the scene, exact
// by docs/design.md §2's contract wherever the scene sits.
//
// This is the oracle every faster method is compared with, so its answer is the contract's own
// test: segmentCrossesTriangle (ExactSegment.h), in double precision on the files' float values
// and the patches' double sample positions. Embree 3 only finds the candidates: its BVH is built
// over user primitives whose boxes are each triangle's box widened by how far the float ray
// Embree traverses can stray from the exact segment (a few float ulps of the coordinates:
// 1.4e-4 m at 1 km ... 0.12 m at 1000 km), and traversal is robust (conservative box tests), so
// no triangle the exact segment crosses is ever skipped, and every candidate is decided exactly.
// Float rays on float triangles do not have this property: 1 km from the origin Embree's own
// triangle test disagreed with the exact answer on 160 non-tie rays per million, and it reports
// hits on triangles seen exactly edge-on by rays that miss them by centimetres.
//
// Rays from one receiver sample share their origin, so they go in packets of 16 (rtcOccluded16),
// receiver samples spread over all cores with TBB. The BVH is built once per RayCastScene and
// reused by every sample() call (the editor re-samples on every patch move); a call whose patches
// lie so far out that the boxes' widening would not cover its rays rebuilds it, wider, first.
//
// The CPU sampler's RayCast strategy (src/raycast/ProvenRayCaster.h) casts through Embree's own
// float triangles, proves or tests every hit, and confirms with this class the rays it leaves
// free, so that it answers as this class does, bit for bit.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/Scene.h"
#include "visibility/SourceJitter.h"

namespace sightline {

struct RayCastOptions {
    bool packets = true;   ///< rtcOccluded16 packets; false casts single rays (rtcOccluded1)
    int threads = 0;       ///< 0 = all cores
    SourceJitter jitter{}; ///< decorrelated source samples per receiver sample (§6.2); off by default
    /// A bumpy receiver (§8, ReceiverHeights.h): rays start at the displaced receiver samples.
    /// Null or empty: the flat patch. Not owned; must outlive the call.
    const ReceiverHeights* heights = nullptr;
    /// sampleUnblocked only: cast from these receiver samples (bit indices) and leave the other
    /// rows alone. Null: every receiver sample. Not owned.
    const std::vector<int>* receiverSubset = nullptr;
    /// Packets start at a source sample and run to a block of 4x4 neighbouring receiver samples
    /// instead of from a receiver sample to 16 source samples: coherent packets where the
    /// receiver grid is the finer one. The same answer, bit for bit (every candidate is still
    /// tested from its receiver end).
    bool fromSource = false;
};

class RayCastScene {
public:
    /// Builds the BVH over every world triangle of `scene`. Throws sightline::Error if Embree
    /// fails or a coordinate lies beyond docs/design.md §2's range (validateCoordinates).
    explicit RayCastScene(const Scene& scene);
    /// `fastBuild` trades traversal speed for build time (a per-call BVH of a few thousand
    /// triangles).
    explicit RayCastScene(const WorldTriangles& triangles, bool fastBuild = false);
    ~RayCastScene();
    RayCastScene(const RayCastScene&) = delete;
    RayCastScene& operator=(const RayCastScene&) = delete;

    std::size_t triangleCount() const;
    double buildMilliseconds() const;

    /// The hidden-samples map for the pair; validates it first (validatePatchPair and, with
    /// heights, validateReceiverHeights throw sightline::Error — never a wrong answer).
    HiddenSampleMap sample(const Patch& source, const Patch& receiver, const RayCastOptions& options = {}) const;

    /// Casts only the rays not yet marked blocked in `map` (dimensions must match the pair, which
    /// must be valid; heights are validated) and marks those this scene blocks. Returns the number
    /// of rays cast.
    std::uint64_t sampleUnblocked(const Patch& source, const Patch& receiver, HiddenSampleMap& map,
                                  const RayCastOptions& options = {}) const;

    /// Segments from `start` to each of `ends`: blocked[k] is 1 where the contract's test
    /// (segmentCrossesTriangle, ExactSegment.h) finds a triangle that start -> ends[k] crosses
    /// strictly between its ends, else 0. Packets of 16 lanes sharing their start (a shaded point
    /// and its light samples, or a light and the points it shines on). Thread-safe. Coordinates
    /// must be finite and within docs/design.md §2's range (callers validate them).
    void segmentsBlocked(const glm::dvec3& start, std::span<const glm::dvec3> ends, std::uint8_t* blocked) const;
    /// The same for segments starts[k] -> ends[k] (the spans must have one size).
    void segmentsBlocked(std::span<const glm::dvec3> starts, std::span<const glm::dvec3> ends,
                         std::uint8_t* blocked) const;

private:
    struct Embree;
    struct UnblockedCall;
    std::unique_ptr<Embree> embree_;
};

} // namespace sightline
