#pragma once
// The baseline the samplers' speed is measured against: the Embree tracer a user would tune for
// this job, not our exact reference. Built-in triangles in a flat scene at Embree's default build
// quality, not robust; every segment as a ray (t in [1e-6, 1 - 1e-6]) in packets of 16
// (rtcOccluded16) sharing one end, their other ends 4x4 neighbouring samples where the grid allows
// (faster than 16 along a row on every bench scene), over all cores. `bench` times each traversal
// (TunedTraversal) and reports the fastest, as a user tuning it for the scene at hand would.
// Its answers are float ray casts: `bench` reports their disagreements with the exact reference
// like any method's, but it is there for its speed. The BVH build is excluded from its timings.

#include <memory>
#include <string>
#include <vector>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline::bench {

/// The two knobs of a tuned tracer that move its speed most on our scenes, both left to the
/// caller: which end the rays start at (a packet shares its origin, its 16 rays run to 4x4
/// neighbouring samples of the other patch), and Embree's traversal hint: coherent (packet
/// traversal to the leaves) or incoherent (Embree's default: the packet splits into single rays
/// once some lanes leave it: faster where packets diverge, on dense meshes, and slower on sparse
/// interiors, where they stay together; docs/benchmarks.md has the figures).
struct TunedTraversal {
    bool fromSource = false;
    bool coherent = true;
    std::string name() const;
};

/// Every traversal `bench` times; it reports the fastest (what a user tuning it would keep).
std::vector<TunedTraversal> tunedTraversals();

class TunedEmbree {
public:
    explicit TunedEmbree(const WorldTriangles& triangles);
    ~TunedEmbree();
    TunedEmbree(const TunedEmbree&) = delete;
    TunedEmbree& operator=(const TunedEmbree&) = delete;

    HiddenSampleMap sample(const Patch& source, const Patch& receiver, int threads = 0, TunedTraversal traversal = {}) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace sightline::bench
