#pragma once
// Internal to the CPU bitmask sampler: occluder preparation. Each triangle that can hide
// anything (in the shaft, not culled) is clipped to the slab between the patches, moved to the
// source frame, and given its influence region (§3: the receiver samples it may hide anything
// from) and the cheapest path its region allows. The GL sampler prepares its occluders the same
// way.

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "../BitmaskRows.h"
#include "Shaft.h"
#include "visibility/Scene.h"
#include "visibility/ShaftGeometry.h"

namespace sightline::bitmask {

/// A triangle clipped to the slab, ready for backprojection: vertices in source coordinates
/// (s, t, d) and the range of receiver samples its influence region covers.
struct Occluder {
    /// A triangle cut by the two slab planes has at most five vertices (the per-sample clip of
    /// the double path copies them into a ClippedPolygon, which has room for one more cut).
    static constexpr int kMaxVertices = detail::kMaxPolygon;
    std::array<glm::dvec3, kMaxVertices> vertices;
    int count = 0;
    int a0 = 0, a1 = -1, b0 = 0, b1 = -1;   ///< receiver sample range, inclusive
    double maxD = 0.0;                      ///< the largest vertex distance from the source plane
    /// Over the whole region. A flat receiver's tile may take a cheaper path over its own part
    /// (Shaft::pathFor): an object standing on a floor needs clipping only near where it stands.
    Path path = Path::Clip;
    double cells = 0.0;                     ///< backprojected area from the region, in source cells
    /// Parallel patches: every receiver sample has the same distance d_R, so each vertex's
    /// projection factor d_R / (d_R - d_X) is one number per occluder, not one per pair.
    std::array<double, kMaxVertices> factor;
};

/// Clips the triangle and bounds its influence region (§3): the projections of the clipped
/// polygon from the four source corners onto the receiver plane, as a box of receiver samples.
/// Where a vertex is not strictly closer to the receiver than a corner, the projection is
/// undefined and the whole receiver is taken (conservative). False when nothing remains.
///
/// A bumpy receiver (§8: "the projection from the light's corners has to be performed on a plane
/// lying behind the receiver"): a sample at height h is hidden through X from source point Y only
/// if it lies on line YX at height h. That point is a projective image of Y and of X with the
/// same denominator d(Y) - d(X) > 0, so for each h it lies in the hull of the corner-vertex
/// projections, and it is affine in h, so the projections onto the planes of the lowest and the
/// highest bump bound every sample between them.
bool prepareOccluder(const Shaft& shaft, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, Occluder& out);

/// Area of the backprojection from receiver point r (source coordinates, farther from the source
/// than every vertex), in source-sample cells (shoelace).
double backprojectedCells(const Shaft& shaft, const Occluder& o, const glm::dvec3& r);

/// The occluder's vertices as float pairs, and its factors for parallel patches, for the float
/// kernel (BitmaskRows.h) and the narrowing test's bounds.
detail::FloatPolygon floatPolygon(const Shaft& shaft, const Occluder& o, bool closed);

/// Which triangles of a soup can hide anything: shaft culling (instance bounds, then the
/// triangle, against the hull, before any clipping) and watertight front-face culling (§7).
struct TriangleFilter {
    const WorldTriangles* triangles = nullptr;
    const ShaftHull* hull = nullptr;
    std::vector<char> instanceOutside;   ///< per instance: bounds wholly outside the hull; empty: unknown
    std::vector<char> cullable;          ///< per instance: front faces may be culled; empty: none
    std::array<glm::dvec3, 4> sourceCorners{};

    const glm::vec3* triangle(std::size_t t) const { return &triangles->vertices[3 * t]; }
    bool outsideShaft(std::size_t t) const;
    /// A front face, seen from all four source corners, of a cullable instance.
    bool culled(std::size_t t) const;
};

/// The triangles in the shaft that culling keeps and the (occluder, receiver sample) pairs the
/// bitmask would backproject before narrowing, estimated from every 32nd triangle (Auto's cost
/// model, Strategy.h).
struct PairEstimate {
    std::uint64_t triangles = 0;
    std::uint64_t pairs = 0;
};
PairEstimate estimatePairs(const Shaft& shaft, const TriangleFilter& filter);

/// The occluders of one call, prepared in parallel and kept in triangle order whatever the
/// thread count. Storage is kept between calls (fresh multi-megabyte allocations cost page
/// faults on every call).
struct OccluderSet {
    std::vector<const Occluder*> occluders;   ///< in triangle order
    std::vector<std::uint32_t> triangleOf;    ///< each occluder's triangle
    std::size_t culledFrontFaces = 0;

    void prepare(const Shaft& shaft, const TriangleFilter& filter);

private:
    std::vector<std::vector<Occluder>> found_;   // per chunk of triangles
    std::vector<std::vector<std::uint32_t>> foundTriangle_;
};

} // namespace sightline::bitmask
