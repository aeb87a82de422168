#pragma once
// Where each drawn ray ends on screen (a blocked ray is drawn only up to where it is
// first stopped, with a mark there). For drawn ray k of a subset (subsetRay), the fraction of the
// way from its source sample to its receiver sample: 1 for a free ray, the first hit for a blocked
// one. The map says which rays are blocked (exact); the caster only says where (segmentFirstHit).

#include <vector>

#include "editor/ViewportRenderer.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/pvs/FirstHitCaster.h"

namespace sightline::ui {

std::vector<float> drawnRayEnds(const pvs::FirstHitCaster& caster, const HiddenSampleMap& map, const Patch& source,
                                const Patch& receiver, const RaySubset& subset);

} // namespace sightline::ui
