#pragma once
// A project's PVS set-up, an optional key kept on save like any other:
//
//   "pvs": {
//     "cell_size": 2.0, "cell_height": 1.8, "cell_lift": 0.1,     grid cells over the floors, or
//     "cells": [{"min": [x,y,z], "max": [x,y,z]}, ...],            boxes listed (then no grid)
//     "group_by_name": false,                                      one object per instance name
//     "coarse_shafts": 16, "fine_shafts": 1024,                    bake settings (PvsBake.h)
//     "smallest_gap": 0.02, "residue_rays": 256, "safe": false,
//     "max_distance": 0,                                           distance cut-off, metres (0: none)
//     "cell_rows": false,                                          also bake cell-to-cell rows
//     "overrides": [{"object": "lamp", "visible": "always"},       or "never"; by object name
//                   {"instance": 12, "visible": "never", "cells": [0, 3]}]   or by instance index,
//   }                                                              optionally in some cells only
//
// Overrides are the designer's word over the bake (the editor's PVS debugger writes them) and are
// applied after it; they are part of the settings hash, so a part baked without them is refused.

#include <string>
#include <vector>

#include "project/Project.h"
#include "visibility/pvs/PvsBake.h"
#include "visibility/pvs/PvsData.h"
#include "visibility/pvs/ViewCells.h"

namespace sightline {

struct PvsOverride {
    std::size_t object = 0;            ///< index into the objects
    bool visible = true;               ///< always (true) or never (false)
    std::vector<std::size_t> cells;    ///< empty: every cell
};

struct PvsSetup {
    bool gridCells = true;             ///< cells from the grid (else listed)
    pvs::GridCellSettings grid;
    std::vector<Bounds> cells;         ///< listed cells, or the grid's once built
    bool groupByName = false;
    pvs::PvsSettings settings;
    nlohmann::json overridesJson = nlohmann::json::array();   ///< resolved against objects later
};

/// Reads project.extra["pvs"] (defaults without it). Throws sightline::Error naming the key:
/// "level.json: pvs.cells[2]: inverted box ...".
PvsSetup parsePvsSetup(const Project& project, const std::string& what);

/// Resolves the overrides against the objects and cell count. Throws sightline::Error for an
/// unknown object name or instance, a bad "visible" value or a cell out of range.
std::vector<PvsOverride> resolvePvsOverrides(const nlohmann::json& overrides, const std::vector<pvs::PvsObject>& objects,
                                             std::size_t cellCount, const std::string& what);

void applyPvsOverrides(const std::vector<PvsOverride>& overrides, pvs::VisibilityRows& rows);

} // namespace sightline
