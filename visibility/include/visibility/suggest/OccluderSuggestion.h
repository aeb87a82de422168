#pragma once
// The occluder that cuts a view (docs/design.md §4, `sightline-cli suggest`): the smallest convex
// polygon or rectangle on a plane between the patches that blocks a chosen share of the rays
// the hidden-samples map leaves unblocked.
//
// The plane passes through the point at fraction `depth` of the way from the source's centre to
// the receiver's, perpendicular to that line. An unblocked ray can be blocked by something on
// the plane only if it crosses the plane strictly between its ends; an occluder blocks it when
// the crossing lies inside. So the smallest convex occluder blocking every crossing ray is their
// crossings' convex hull, and the smallest rectangle is the hull's smallest enclosing rectangle
// (ConvexHull2.h); for a share below one, ShareTrimming.h chooses the crossings to leave out.
//
// Exactness (docs/design.md §2): a crossing on the polygon's boundary is a tie, which an exact
// method may answer either way. The polygon is therefore grown by a margin that puts every kept
// crossing farther than the tie distance from its edges, measured across the ray, after the
// corners are rounded to float32 where the scene stores them. The caller checks the promise by
// the exact sampler with the occluder inserted (project/SuggestedOccluder.h).

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/Scene.h"
#include "visibility/suggest/ConvexHull2.h"

namespace sightline::suggest {

enum class Shape { Convex, Rect };
/// "convex" or "rect"; throws sightline::Error naming both for anything else.
Shape parseShape(const std::string& name);
const char* shapeName(Shape shape);

/// The plane an occluder is suggested on, with an orthonormal frame: a point X of the plane has
/// coordinates (axisU . (X - origin), axisV . (X - origin)); normal = axisU x axisV points from
/// the source's side to the receiver's.
struct SuggestPlane {
    glm::dvec3 origin{0.0};
    glm::dvec3 normal{0.0, 0.0, 1.0};
    glm::dvec3 axisU{1.0, 0.0, 0.0};
    glm::dvec3 axisV{0.0, 1.0, 0.0};
    glm::dvec3 world(Point2 p) const { return origin + p.x * axisU + p.y * axisV; }
};

/// Throws sightline::Error unless depth is in (0, 1) and the patches' centres differ.
SuggestPlane suggestPlane(const Patch& source, const Patch& receiver, double depth);

/// A surface the designer picked (a doorway's frame, a window's wall): a point on it and its normal.
struct PickedSurface {
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0.0};
};

/// The plane of a picked surface, its normal turned to point from the source's side to the
/// receiver's. Throws sightline::Error for a non-finite point or a zero normal, or when the plane
/// does not pass between the patches' centres (no ray from one to the other would cross it there).
SuggestPlane surfacePlane(const Patch& source, const Patch& receiver, const PickedSurface& surface);

/// Where the unblocked rays of a map cross a plane.
struct RayCrossings {
    std::vector<Point2> points;          ///< in the plane's coordinates, one per crossing ray
    std::vector<float> cosines;          ///< |cos| between each ray and the plane's normal
    std::vector<std::uint64_t> rays;     ///< each crossing's ray: receiver * sourceCount + source
    std::uint64_t unblocked = 0;         ///< every unblocked ray, crossing or not
};

/// The crossings of every unblocked ray of `map` (between `source` and `receiver`, the receiver
/// displaced by `heights`) with `plane`. A ray crosses when its ends lie strictly on opposite
/// sides, each more than the tie distance from the plane along the ray.
RayCrossings crossUnblockedRays(const Patch& source, const Patch& receiver, const ReceiverHeights& heights,
                                const HiddenSampleMap& map, const SuggestPlane& plane);

struct Request {
    double depth = 0.5;    ///< in (0, 1); the plane's place unless `surface` is set
    std::optional<PickedSurface> surface;   ///< the plane of a picked surface instead
    /// Per source sample, the light it carries (>= 0, finite): below share 1, the share is of the
    /// unblocked rays' summed weight, the light reaching the receiver, instead of their count.
    /// Empty: every ray counts alike.
    std::vector<double> sourceWeights;
    double share = 1.0;    ///< in (0, 1]: the share of the unblocked rays to block
    Shape shape = Shape::Convex;
    double marginScale = 1.0;   ///< the exactness margin times this (a caller's retry grows it)
};

/// Throws sightline::Error for a depth outside (0, 1) (when no surface is picked), a picked
/// surface with a non-finite point or a zero normal, or a share outside (0, 1] (NaN included):
/// what a command checks before it loads anything.
void validateRequest(const Request& request);

struct Suggestion {
    SuggestPlane plane;
    Shape shape = Shape::Convex;
    std::vector<Point2> polygon;   ///< counter-clockwise in the plane, the margin included
    Rect2 rect;                    ///< Shape::Rect: the rectangle (polygon holds its corners)
    double area = 0.0;             ///< of `polygon`, m^2
    double margin = 0.0;           ///< how far it was grown beyond the crossings, m in the plane
    std::uint64_t unblockedBefore = 0;
    std::uint64_t crossing = 0;    ///< unblocked rays that cross the plane
    std::uint64_t required = 0;    ///< rays it must block: ceil(share * unblockedBefore)
    std::uint64_t promised = 0;    ///< the most rays it may leave unblocked
    std::uint64_t enclosed = 0;    ///< crossings it was built around, each well inside (>= required)
    /// With sourceWeights below share 1: the unblocked rays' light before, the light it must block
    /// (share x before) and the light of the crossings it was built around (>= required).
    /// `required` and `promised` then count the rays it was built around.
    bool weighted = false;
    double lightBefore = 0.0, lightRequired = 0.0, lightEnclosed = 0.0;

    std::vector<glm::dvec3> worldPolygon() const;
};

/// Throws sightline::Error when nothing is unblocked, or the plane cannot meet the share (the
/// message says how many rays miss the plane and the largest share it can block), or a share
/// below 1 is asked of more than 2^24 unblocked rays (share 1 takes any number: its crossings are
/// reduced to their hull as they come).
Suggestion suggestOccluder(const Patch& source, const Patch& receiver, const ReceiverHeights& heights,
                           const HiddenSampleMap& map, const Request& request);

/// The summed weight of the unblocked rays of `map` (weights per source sample, as sourceWeights).
double unblockedLight(const HiddenSampleMap& map, std::span<const double> sourceWeights);

/// The polygon's centroid, rounded to float32: where its mesh is placed (suggestionMesh).
glm::dvec3 suggestionCentre(const Suggestion& suggestion);

/// The suggestion as a mesh around `origin` (its vertices are the world corners less `origin`,
/// placed back by a translation to it): two fans over the polygon (one from its centroid, one
/// from its first corner), so that a ray through an inner edge of one fan is well inside a
/// triangle of the other. Vertices as float32, as a scene stores them.
Mesh suggestionMesh(const Suggestion& suggestion, const std::string& name, glm::dvec3 origin = glm::dvec3(0.0));

} // namespace sightline::suggest
