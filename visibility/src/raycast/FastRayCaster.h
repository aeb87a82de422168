#pragma once
// The CPU sampler's ray casting: DESIGN.md §2's exact answer at the speed of a tuned float tracer.
//
// Embree traverses its own float triangles with the setup a user tuning it would pick (one flat
// BVH of triangle geometry, default build quality, not robust, rtcOccluded16 packets), in a frame
// centred on the scene. Two changes make its answer the contract's:
//
// - Every hit Embree reports goes through an occlusion filter that runs the contract's exact test
//   (ExactSegment.h, the reference's arithmetic: raycast::crossedLanes) on the file's values and
//   the double segment, and rejects it unless that test says the segment crosses the triangle. A
//   ray reported blocked is blocked.
// - Every exact crossing is among the hits Embree reports, so a ray reported free is free. Each
//   triangle is grown in its plane by a margin m (scaled about its incentre: every edge moves out
//   by m), and each segment is lengthened by at least the largest margin at both ends. Embree's
//   float hit test (Moeller-Trumbore, kernels/geometry/triangle_intersector_moeller.h), its box
//   tests and the rounding of vertices, origins and directions to float move a crossing, in the
//   triangle's plane, by at most E / sin(alpha), alpha the angle between ray and plane and
//   E = kErrorUlps * u * (|origin| + |vertex - origin| + the triangle's size), u = 2^-24 (the
//   terms are listed in FastRayCaster.cpp). So a crossing of the triangle, which lies at least m
//   inside the grown one, is reported whenever m sin(alpha) >= E.
//
// sin(alpha) is bounded per call from the patches alone: a ray through the triangle starts on
// the receiver and ends on the source, so sin(alpha) >= dist(patch, plane) / dist(patch, triangle)
// for either patch that lies wholly on one side of the plane. The triangles of a call's shaft for
// which the bound does not give m sin(alpha) >= E (seen nearly edge-on from both patches,
// slivers too thin to grow, triangles huge against the distances involved) are its close
// triangles: after the float pass, the rays still free are cast against a BVH of only them with
// the reference's method (RayCastScene), exact by construction. The tests judge the result
// against an exact brute force at production sizes (tst_Exactness).

#include <cstdint>
#include <memory>
#include <vector>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/RayCastSampler.h"
#include "visibility/Scene.h"

namespace sightline::raycast {

class FastRayCaster {
public:
    /// Builds the BVH over every triangle (the coordinates must be valid: validateCoordinates).
    /// Throws sightline::Error if Embree fails.
    explicit FastRayCaster(const WorldTriangles& triangles);
    ~FastRayCaster();
    FastRayCaster(const FastRayCaster&) = delete;
    FastRayCaster& operator=(const FastRayCaster&) = delete;

    double buildMilliseconds() const;
    /// Triangles in the float BVH (degenerate ones, which block nothing, and slivers are not).
    std::size_t floatTriangleCount() const;

    /// One source/receiver pair's rays, ready to cast, in parts if the caller wishes (Auto's probe
    /// casts a few tiles at a time): the close triangles found and their BVH built once.
    class Shaft;
    /// What becomes of the shaft's close triangles.
    enum class CloseTriangles {
        CastExactly,    ///< cast() casts the rays it leaves free against them, exactly
        LeftToCaller,   ///< cast() leaves them out; the caller must answer for them
                        ///< (Shaft::closeTriangleIndices), before or after
    };
    /// Validates the pair and the heights (sightline::Error). `options.receiverSubset` is ignored
    /// here: cast() takes the subset.
    std::unique_ptr<Shaft> prepare(const Patch& source, const Patch& receiver, const RayCastOptions& options,
                                   CloseTriangles close = CloseTriangles::CastExactly) const;

    /// Casts the rays of `shaft` not yet marked blocked in `map` from the receiver samples in
    /// `receiverSubset` (null: all) and marks those that are blocked; returns the rays cast by the
    /// float pass. Runs on the caller's task arena.
    std::uint64_t cast(const Shaft& shaft, HiddenSampleMap& map, const std::vector<int>* receiverSubset = nullptr) const;

    /// prepare() and cast() in one, for every receiver sample or `options.receiverSubset`, on
    /// `options.threads` threads (0: all).
    std::uint64_t sampleUnblocked(const Patch& source, const Patch& receiver, HiddenSampleMap& map,
                                  const RayCastOptions& options = {}) const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

class FastRayCaster::Shaft {
public:
    ~Shaft();
    /// Triangles of this shaft the float pass cannot answer for (world triangle indices,
    /// ascending).
    std::size_t closeTriangles() const;
    const std::vector<std::uint32_t>& closeTriangleIndices() const;
    /// Finding them and building their BVH.
    double prepareMilliseconds() const;

    struct Data;
    explicit Shaft(std::unique_ptr<Data> data);
    const Data& data() const { return *data_; }

private:
    std::unique_ptr<Data> data_;
};

} // namespace sightline::raycast
