#pragma once
// The exact CPU filler: all rays of one light direction d are parallel (Sattler et al. §3.2 render
// an orthographic depth map per direction for the same reason). So for each direction the
// triangles and the points' origins are projected onto the plane orthogonal to d and binned in a
// 2D grid; a point is tested only against the triangles of its cell. The test is exact in the
// projected frame: a point is blocked by a triangle when its projection lies inside the projected
// triangle (edge functions, inclusive) and the triangle's depth along d there exceeds the origin's.
//
// Watertight: the edge function of a shared edge is computed from the same two projected vertices
// with exactly negated coefficients in both triangles, so a ray through the edge is inside at
// least one of them (no leaks between the triangles of a mesh). Coordinates are relative to the
// occluders' centre, so a level far from the origin keeps its precision.
//
// Antipodal directions d and -d share the plane, the projection and the edge functions: they are
// answered in one pass over the triangles. Triangles are kept in Morton order of their centroids
// (vertices renumbered by first use), so consecutive triangles touch neighbouring cells and points
// in every projection, and the cells' points stay in cache from one triangle to the next.
//
// Parallel over directions (TBB); each direction writes a bit row over the points, transposed into
// the point-major matrix at the end of the call.

#include <limits>
#include <memory>

#include "lighting/ao/AoFiller.h"

namespace sightline {

struct AoBinnedOptions {
    int threads = 0;            ///< 0: all cores
    double cellsPerTriangle = 0.5;   ///< grid cells ~ this times the triangle count (0.25-1 measured alike)
    /// Only occluders nearer than this along a ray count (metres; infinite: the uniform sky of
    /// docs/design.md §4). An editor preview of an interior uses a few metres, as AO in engines does:
    /// under a uniform sky a closed room is dark everywhere.
    double maxDistance = std::numeric_limits<double>::infinity();

};

class AoBinnedCaster final : public AoFiller {
public:
    AoBinnedCaster(const AoOccluders& occluders, AoBinnedOptions options = {});
    ~AoBinnedCaster() override;
    std::string name() const override { return "cpu-binned"; }
    bool fill(const AoPoints& points, const AoDirectionSet& set, int first, int last, VisibilityMatrix& matrix,
              const AoFillControl& control = {}) override;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace sightline
