#pragma once
// The PVS's objects: the scene's instances, in instance order, or grouped by name
// (every instance of one name is one object, in order of first appearance).

#include <vector>

#include "visibility/Scene.h"
#include "visibility/pvs/PvsData.h"

namespace sightline::pvs {

/// Instances with no triangles (an empty mesh) still get an object, with an empty box; the bake
/// never sees them.
std::vector<PvsObject> sceneObjects(const Scene& scene, bool groupByName);

} // namespace sightline::pvs
