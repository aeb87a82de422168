#pragma once
// Geometry shared by the bitmask samplers: patch-relative coordinates, the shaft slab, and the
// clipping of triangles against it (Eisemann & Décoret §3-4, made exact).
//
// Each patch gets affine coordinates (s, t, d): s, t in [0, 1] across the patch (X = c + s u + t v
// + ...), d the signed distance from its plane, positive towards the other patch. Because the maps
// are affine, the backprojection of a point X from a receiver point R onto the source plane is,
// in source coordinates,
//     s(Y) = s(R) + (s(X) - s(R)) * d(R) / (d(R) - d(X))       (same for t),
// one division per vertex, valid for 0 <= d(X) < d(R).
//
// Every segment between a source and a receiver sample lies, apart from its ends, strictly inside
// the slab {d_source > 0} ∩ {d_receiver > 0}, so a triangle can be clipped to that slab once
// (triangles crossing a patch plane are clipped, never dropped) without changing any answer.

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline {

/// Affine coordinates relative to a patch; `towards` orients d.
struct PatchFrame {
    glm::dvec3 origin{0.0};
    glm::dvec3 sAxis{0.0}, tAxis{0.0}, dAxis{0.0};   ///< dual basis: s = dot(X - origin, sAxis) ...

    PatchFrame() = default;
    PatchFrame(const Patch& patch, const glm::dvec3& towards);

    glm::dvec3 coordinates(const glm::dvec3& x) const
    {
        const glm::dvec3 r = x - origin;
        return {r.x * sAxis.x + r.y * sAxis.y + r.z * sAxis.z, r.x * tAxis.x + r.y * tAxis.y + r.z * tAxis.z,
                r.x * dAxis.x + r.y * dAxis.y + r.z * dAxis.z};
    }
};

/// A convex polygon of at most 8 vertices (a triangle clipped by up to 5 planes).
struct ClippedPolygon {
    static constexpr int kMaxVertices = 8;
    std::array<glm::dvec3, kMaxVertices> vertices{};
    int count = 0;
};

/// Keeps the part of `polygon` where dot(X, normal) > offset (Sutherland-Hodgman, one plane).
/// Works in any affine coordinates. A cut edge is interpolated from its inside end, so polygons
/// sharing an edge get bit-identical cut points.
void clipPolygon(ClippedPolygon& polygon, const glm::dvec3& normal, double offset);

/// The shaft between a valid patch pair: both frames, and the end margin of docs/design.md §2
/// (kEndMarginMetres, ExactSegment.h) as the distance the slab keeps from each patch's plane.
struct ShaftFrames {
    PatchFrame source;     ///< d > 0 towards the receiver
    PatchFrame receiver;   ///< d > 0 towards the source
    double sourceMargin = 0.0;     ///< clip at d_source > sourceMargin
    double receiverMargin = 0.0;   ///< clip at d_receiver > receiverMargin

    ShaftFrames(const Patch& sourcePatch, const Patch& receiverPatch);

    /// The triangle clipped to the slab, in world coordinates. Empty (count 0) if nothing remains.
    ClippedPolygon clipToSlab(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const;
};

/// The shaft's convex hull (of the two patches' eight corners) as planes, for culling whole
/// instances by their bounds and triangles by their vertices before any clipping: every segment
/// between the patches lies inside it. On the demo, 83k triangles of which 12k meet the shaft.
class ShaftHull {
public:
    ShaftHull(const Patch& source, const Patch& receiver);
    /// The hull of any points (at least 4, not coplanar): a bumpy receiver's shaft is the hull of
    /// the source's corners and the receiver's prism between its lowest and highest bump.
    explicit ShaftHull(const std::vector<glm::dvec3>& points);

    /// True when all points lie outside one hull plane by more than a tolerance far above
    /// rounding, so nothing they span can meet a segment of the shaft.
    bool excludes(const glm::dvec3* points, int count) const;
    bool excludes(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const;
    /// The box [lo, hi].
    bool excludesBox(const glm::vec3& lo, const glm::vec3& hi) const;

    std::size_t planeCount() const { return planes_.size(); }

private:
    struct Plane {
        glm::dvec3 normal;   ///< unit, outward
        double offset;       ///< inside: dot(normal, x) <= offset
    };
    std::vector<Plane> planes_;
    double tolerance_ = 0.0;
};

/// Watertight front-face culling (§7) is safe for an instance only when no receiver sample can
/// lie inside it: the receiver patch must not touch the instance's bounds (a receiver inside a
/// closed mesh sees its front faces block). Shared by the CPU and GL samplers.
bool receiverApartFrom(const Bounds& instanceBounds, const Patch& receiver);

} // namespace sightline
