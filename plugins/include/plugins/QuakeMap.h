#pragma once
// Quake map sources (.map, as TrenchBroom, J.A.C.K., Radiant and id's own editors write them): the
// entities with their keys and brushes, and each brush's faces as polygons. A brush is the
// intersection of the half-spaces behind its planes; each plane is given by three points whose
// order makes its normal point out of the brush (Quake's (p0 - p1) x (p2 - p1)). Standard and
// Valve 220 texture alignment are both read (what follows the texture's name is skipped up to the
// next plane), as are Quake 2's and Hexen 2's extra numbers; Quake 3's patches and brushDef blocks
// are counted and left out.

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace sightline {

struct MapPlane {
    glm::dvec3 normal{0.0};   ///< unit, out of the brush
    double dist = 0.0;
    std::string texture;
};

struct MapBrush {
    std::vector<MapPlane> planes;
    int line = 0;   ///< where it starts, for messages
};

struct MapEntity {
    std::map<std::string, std::string> keys;
    std::vector<MapBrush> brushes;
    std::string classname() const;
};

struct QuakeMap {
    std::vector<MapEntity> entities;
    std::size_t degeneratePlanes = 0;   ///< planes of three collinear points, left out (as compilers do)
    std::size_t leftOut = 0;            ///< Quake 3 patches and brushDef blocks
};

/// Parses a .map's text; `what` names it in errors. Throws sightline::Error ("e1m1.map:120: ...")
/// for a brace or parenthesis out of place, a number that is not one or not finite, a point
/// beyond kMaxMapCoordinate, a brush of more than kMaxBrushPlanes planes, or text after the last
/// entity.
inline constexpr double kMaxMapCoordinate = 1e6;
inline constexpr std::size_t kMaxBrushPlanes = 256;   ///< real brushes have a few dozen; each face is cut by every plane
QuakeMap parseQuakeMap(std::string_view text, const std::string& what);

/// One face of a brush: the part of its plane behind every other plane (a convex polygon wound
/// counter-clockwise seen from outside the brush), with the plane's texture. Planes that leave no
/// face (redundant ones) give none; a brush without volume gives none at all.
struct BrushFace {
    std::vector<glm::dvec3> polygon;
    std::string texture;
};
std::vector<BrushFace> brushFaces(const MapBrush& brush);

/// Whether `p` lies inside the brush by more than `margin` (behind every plane by more than it).
bool insideBrush(const MapBrush& brush, const glm::dvec3& p, double margin = 0.0);

} // namespace sightline
