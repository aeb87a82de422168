#pragma once
// Light-map texels as AO sample points: a level's walls are large faces with few
// vertices, so per-vertex AO misses the contact shadows in a room's corners and under furniture.
// Each triangle gets a regular grid of `density` texels per metre in its own plane (axis u along
// its first edge, v perpendicular in the plane), one point per texel at the texel centre, moved to
// the nearest point of the triangle where the centre falls outside it (so edge texels sample the
// surface, and bilinear filtering in an engine sees no unlit border). The normal is the
// triangle's own (its winding's front face).
//
// Layout (a documented simple one): every triangle's grid is one rectangular tile of a single
// atlas, tiles packed in shelves (tallest first) with a one-texel gutter. Texel (s, t) of a tile
// is atlas pixel (x + s, y + t), row 0 at the top. The uv of a point p of the triangle is
// ((x + (p.u - u0) * density) / W, (y + p.v * density) / H): glTF TEXCOORD_1, origin top left.

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "lighting/ao/AoGeometry.h"

namespace sightline {

struct AoTexelTile {
    std::uint32_t triangle = 0;   ///< in AoOccluders order
    int x = 0, y = 0;             ///< atlas position of texel (0, 0)
    int width = 0, height = 0;    ///< 0 for a degenerate triangle (no texels)
    std::size_t firstPoint = 0;   ///< point index of texel (0, 0); texel (s, t) is firstPoint + t * width + s
    glm::vec3 origin{0.0f}, axisU{0.0f}, axisV{0.0f};   ///< plane frame: u0 folded into origin
};

struct AoTexelLayout {
    double density = 0.0;   ///< texels per metre
    int width = 0, height = 0;   ///< atlas size in pixels
    std::vector<AoTexelTile> tiles;   ///< one per triangle

    /// TEXCOORD_1 of triangle t's corner c (0..2).
    glm::vec2 uv(const AoOccluders& occluders, std::uint32_t t, int c) const;
};

/// The densest light map baked (`ao --texel`, `lights --texel`): 1 mm texels. Beyond it the
/// atlas of any real level exceeds the pixel limit anyway, and a huge density overflows a tile's
/// texel count.
inline constexpr double kMaxTexelDensity = 1000.0;

/// Throws sightline::Error ("--texel nan: ...") unless `density` is finite and in
/// (0, kMaxTexelDensity] texels per metre.
void checkTexelDensity(double density);

/// Texel points of every triangle at `density` texels per metre (points with status Ok, origins
/// not yet offset). Throws sightline::Error when checkTexelDensity refuses the density, or when
/// the atlas would exceed `maxPixels` (naming a density that fits, or saying that none does).
AoTexelLayout aoTexelPoints(const AoOccluders& occluders, double density, AoPoints& points,
                            std::uint64_t maxPixels = std::uint64_t(1) << 25);

} // namespace sightline
