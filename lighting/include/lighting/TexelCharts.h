#pragma once
// Light-map charts: connected coplanar faces share one texel grid, as light-map bakers lay them
// out, so a flat floor of many triangles has no seam along its triangles' shared edges (a grid per
// triangle leaves each side of a diagonal its own texels, and the two disagree).
//
// A chart is a set of triangles joined through shared edges (equal float end points) whose planes
// agree (unit normals within kChartCosine, the neighbour's far vertex within kChartPlaneMetres of
// the plane). It gets a frame in its plane (u along the longest edge of its largest triangle), a
// rectangle of `density` texels per metre covering it with a one-texel border, and a tile in one
// atlas (shelves, tallest first, a one-texel gutter). Texel (s, t) of a chart is atlas pixel
// (x + s, y + t), row 0 at the top; its centre is origin + (s + 0.5) / density u + (t + 0.5) /
// density v. A vertex p's uv is ((x + (p - origin).u density) / W, (y + (p - origin).v density) / H).
//
// Every texel of a chart's rectangle is a point: a texel whose centre lies in one of the chart's
// triangles samples the surface there (a triangle holding no texel centre, smaller than a texel,
// takes the texel under its centroid); a texel next to one (8-neighbours) samples the nearest
// point of that triangle (so bilinear filtering at an edge reads the surface, not a gutter); the
// rest (outside an L-shaped chart, in a doorway's hole) are marked NoFace and sample nothing.

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "lighting/ao/AoGeometry.h"

namespace sightline {

inline constexpr double kChartCosine = 1.0 - 1e-6;
inline constexpr double kChartPlaneMetres = 1e-4;

struct TexelChart {
    std::vector<std::uint32_t> triangles;   ///< in AoOccluders order
    glm::dvec3 origin{0.0}, axisU{0.0}, axisV{0.0}, normal{0.0};
    int x = 0, y = 0, width = 0, height = 0;
    std::size_t firstPoint = 0;             ///< texel (s, t) is point firstPoint + t * width + s
};

struct ChartLayout {
    double density = 0.0;
    int width = 0, height = 0;
    std::vector<TexelChart> charts;
    std::vector<std::int32_t> chartOf;      ///< per triangle; -1 for a degenerate one (no texels)

    /// TEXCOORD_1 of triangle t's corner c (0 for a degenerate triangle).
    glm::vec2 uv(const AoOccluders& occluders, std::uint32_t t, int c) const;
};

/// Charts over every triangle at `density` texels per metre, their texel points appended to
/// `points`. Throws sightline::Error when checkTexelDensity (lighting/ao/AoTexels.h) refuses the
/// density, or when the
/// atlas would exceed `maxPixels` (naming a density that fits, or saying that none does).
ChartLayout chartTexelPoints(const AoOccluders& occluders, double density, AoPoints& points,
                             std::uint64_t maxPixels = std::uint64_t(1) << 25);

/// Dilates an atlas image into the pixels no texel fills (gutters, the empty space between
/// charts, texels off a chart's surface), `passes` pixels deep: each pass gives every unfilled
/// pixel with a filled 8-neighbour the mean of those neighbours, so that an engine's mip maps of
/// the atlas, which average a chart's edge with what lies around it, do not darken the edge.
/// `filled` (width x height, row-major, like `pixels`) is updated.
void dilateAtlas(int width, int height, std::vector<glm::vec3>& pixels, std::vector<std::uint8_t>& filled, int passes);

} // namespace sightline
