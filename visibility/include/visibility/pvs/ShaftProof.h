#pragma once
// Proofs that a bundle of segments is blocked (the PVS bake's safe answer).
//
// A sub-shaft is the set of all segments from a point of a parallelogram f (on a view cell's
// face) to a point of a parallelogram g (on a target box's face). The bake culls a pair only when
// every sub-shaft of a cover of the pair's segments is proven blocked by ONE occluder, by one of
// two arguments that hold in exact arithmetic (computed in double with stated margins):
//
//  1. Plane: a planar region R (one triangle, or coplanar axis-aligned triangles with the same
//     facing fused across shared edges, e.g. the front of a wall cut into quads, or several walls
//     in a row) whose plane P has f strictly on one side and g strictly on the other. Every
//     segment then crosses P, at a point of conv(f u g) n P, which is the convex hull of the 16
//     crossings of the corner-to-corner segments (conv(f u g) is the union of the segments
//     between f and g, and its vertices are the 8 corners). If that hull H lies inside R, every
//     segment meets a triangle of R. H lies inside R when one point of H is inside a triangle of R
//     and no boundary edge of R (an edge no other triangle of R shares) comes within 1e-6 m of H:
//     H is connected, so it cannot leave R without crossing R's boundary.
//  2. Solid: a closed, consistently wound surface K (a connected part of a mesh for which Scene.h's
//     closedAndOutward holds) and a point m of the
//     sub-shaft's central segment c_f -> c_g, at parameter t, with no triangle of K within
//     r = (1 - t) r_f + t r_g of m (r_f, r_g: the farthest corner of f, g from its centre) and m
//     inside K (winding number of K's triangles about m). The ball B(m, r) then meets no
//     triangle of K and lies inside K; every segment of the sub-shaft passes through it (its
//     point at t is within (1 - t) r_f + t r_g of m); and a segment that enters K's inside from
//     outside crosses a triangle of K. One end of each segment is outside K when the cell's box
//     or the target's box does not meet K's bounds, which the caller checks.
//
// Both are statements about triangles, so they hold for every point in the sub-shaft, not for
// samples: a pair whose cover is proven is hidden (in exact arithmetic, less the margins, which
// are conservative). Sub-shafts that neither argument proves are split (ShaftSearch.h) or, at the
// end, left unproven: the safe mode keeps such pairs visible.

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline::pvs {

/// A parallelogram corner + a u + b v, a, b in [0, 1] (world space, double).
struct Quad {
    glm::dvec3 corner{0.0}, u{0.0}, v{0.0};

    glm::dvec3 centre() const { return corner + 0.5 * (u + v); }
    glm::dvec3 at(double a, double b) const { return corner + a * u + b * v; }
    std::array<glm::dvec3, 4> corners() const { return {corner, corner + u, corner + u + v, corner + v}; }
    /// Distance from the centre to the farthest corner.
    double radius() const;
    /// Length of the longer edge.
    double extent() const;
    /// The two halves across the longer edge.
    std::pair<Quad, Quad> split() const;
    /// This quad (a half) and its twin starting at `otherCorner`.
    std::pair<Quad, Quad> splitPair(const glm::dvec3& otherCorner) const { return {*this, Quad{otherCorner, u, v}}; }
};

/// Which instances belong to the target being proven hidden (empty: none).
using OwnInstances = std::function<bool(std::uint32_t instance)>;

class ShaftProver {
public:
    /// Builds the planar regions and the closed solids of the scene's world triangles
    /// (worldTriangles order: a triangle index from FirstHitCaster's RayHit is valid here).
    explicit ShaftProver(const Scene& scene);

    std::size_t triangleCount() const { return instanceOf_.size(); }
    std::uint32_t instanceOf(std::size_t triangle) const { return instanceOf_[triangle]; }

    /// Argument 1: every segment from f to g crosses the planar region of `triangle`, at a
    /// triangle of an instance `own` does not claim (a target is never hidden by itself: its
    /// triangles in the region count as holes, and the hull must keep 1e-6 m from their edges).
    bool planeBlocks(std::size_t triangle, const Quad& f, const Quad& g, const OwnInstances& own) const;

    /// How large a blocker `triangle` can be: the diagonal of its planar region's bounds (its own
    /// longest edge alone), or of its closed solid's bounds, whichever is larger.
    double blockerSize(std::size_t triangle) const;

    /// Whether `triangle` belongs to a closed solid (a connected part of a closed instance) that
    /// argument 2 can use, and that solid's bounds.
    bool isSolid(std::size_t triangle) const;
    const Bounds& solidBounds(std::size_t triangle) const;
    /// Argument 2: the ball B(m, r) lies inside the closed solid of `triangle` and meets none of
    /// its triangles.
    bool ballInsideSolid(std::size_t triangle, const glm::dvec3& m, double r) const;

    std::size_t regionCount() const { return regions_.size(); }
    std::size_t solidCount() const;

    /// A planar region's plane, x[axis] = offset, and its bounds in the plane's coordinates
    /// (x[axis + 1], x[axis + 2], indices mod 3). Every region is axis-aligned.
    struct RegionPlane {
        int axis = 0;
        double offset = 0.0;
        glm::dvec2 lo{0.0}, hi{0.0};
    };
    RegionPlane regionPlane(std::size_t region) const;
    /// Whether every point of the closed rectangle lo..hi (the plane's coordinates, as above) is on
    /// a triangle of `region`: argument 1's containment test, with its margin.
    bool regionCovers(std::size_t region, const glm::dvec2& lo, const glm::dvec2& hi) const;
    /// The region's triangles in the plane's coordinates (as above).
    std::vector<std::array<glm::dvec2, 3>> regionTriangles(std::size_t region) const;

private:
    struct Region {
        int axis = 0;                        ///< the plane is x[axis] = offset
        double size = 0.0;                   ///< diagonal of its bounds
        double offset = 0.0;
        std::vector<std::uint32_t> triangles;
        std::vector<std::array<glm::dvec2, 2>> boundary;   ///< boundary edges, in (axis+1, axis+2)
        std::vector<std::uint32_t> instances;
        glm::dvec2 lo{0.0}, hi{0.0};
        int nx = 1, ny = 1;
        std::vector<std::uint32_t> triStart, triItems, edgeStart, edgeItems;   ///< grid cells, CSR
    };
    struct Solid {
        std::vector<glm::dvec3> vertices;   ///< 3 per triangle
        Bounds bounds;
    };

    bool regionContains(const Region& r, const std::vector<glm::dvec2>& hull, const OwnInstances& own) const;
    void addPlaneRegions(int axis, double offset, const std::vector<std::uint32_t>& triangles);
    void finishRegion(Region& r);
    void indexRegion(Region& r);
    void addClosedSolids(const Scene& scene);
    void addSolids(std::size_t firstTriangle, std::size_t count);

    std::vector<glm::vec3> vertices_;          ///< world triangles, 3 vertices each
    std::vector<std::uint32_t> instanceOf_;
    std::vector<std::int32_t> regionOf_;       ///< per triangle; -1: a non-axis-aligned triangle alone
    std::vector<Region> regions_;
    std::vector<std::int32_t> solidOf_;        ///< per triangle; -1: not part of a usable solid
    std::vector<Solid> solids_;
};

/// Convex hull of 2D points (Andrew's monotone chain), counter-clockwise, no repeated points.
std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> points);

/// Distance from p to the triangle abc (Ericson, Real-Time Collision Detection §5.1.5), double.
double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

} // namespace sightline::pvs
