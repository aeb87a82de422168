#pragma once
// A lumpy closed blob standing in for a scanned statue (internal): a cube-sphere (six n x n grids
// with equal-angle spacing, so cells differ in size by well under 2x) pushed out radially by
// smooth random bumps, large ones for the figure and small ones for scan noise, then stretched to
// an ellipsoid. 12 n^2 triangles sharing their vertices (an indexed mesh like an imported scan).

#include <cstddef>
#include <optional>
#include <string>

#include "demo/LevelParts.h"

namespace sightline::demo::bench {

using namespace parts;

struct StatueShape {
    vec3 radii{1.0f};        ///< of the ellipsoid before the bumps, metres
    int resolution = 64;     ///< cells along each cube-face edge
    int bumps = 8;           ///< large bumps and dents
    float amplitude = 0.15f; ///< their largest height, relative to the radius
    /// Drops the triangles lying wholly below this height (object space): a statue scanned standing
    /// on a plinth has no underside. The mesh is then open (not watertight); without it, closed
    /// and outward.
    std::optional<float> cutBelow;
};

/// In object space, centred on the origin. `rng` supplies the bumps.
Mesh scannedStatue(const std::string& name, const StatueShape& shape, Rng& rng);

/// Triangles `scannedStatue` makes at `resolution` before a base is cut away.
inline std::size_t statueTriangles(int resolution) { return 12u * std::size_t(resolution) * std::size_t(resolution); }

} // namespace sightline::demo::bench
