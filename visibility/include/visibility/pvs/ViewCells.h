#pragma once
// View cells: boxes a viewer stands in. Either a grid over the walkable space, with
// floors found from the scene, or boxes the project lists.
//
// The grid: square columns of `cellSize` over the scene's x/z extent. In each column a vertical
// ray down the column's centre finds every surface that faces up (|normal.y| >= 0.7, met from
// above); a floor gets a cell [floor + lift, floor + lift + height] when the free space above it
// (to the next surface, or to the top of the scene's bounds) holds the whole cell. So ceilings'
// tops and roofs (no space above inside the scene's bounds) get no cell, and a floor under a
// table gets none either (the column centre's clearance is the table's underside). Cells are
// ordered by column (x, then z) and floor height: deterministic.

#include <string>
#include <vector>

#include "visibility/Scene.h"

namespace sightline::pvs {

class FirstHitCaster;

struct GridCellSettings {
    float cellSize = 2.0f;     ///< metres, x and z
    float height = 1.8f;       ///< metres: the box's height
    float lift = 0.1f;         ///< metres above the floor the box starts
};

/// Grid cells over the scene's floors. Throws sightline::Error for non-positive or non-finite
/// settings, or a grid of more than 1,000,000 columns.
std::vector<Bounds> gridCells(const Scene& scene, const FirstHitCaster& caster, const GridCellSettings& settings);

/// Throws sightline::Error naming the first bad cell: an empty (zero-volume) or inverted box, a
/// non-finite coordinate, one beyond docs/design.md §2's 1e6 m; and an empty list. `what` prefixes
/// the message ("level.json: pvs.cells[3]").
void validateCells(const std::vector<Bounds>& cells, const std::string& what);

} // namespace sightline::pvs
