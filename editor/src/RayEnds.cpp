#include "editor/RayEnds.h"

namespace sightline::ui {

std::vector<float> drawnRayEnds(const pvs::FirstHitCaster& caster, const HiddenSampleMap& map, const Patch& source,
                                const Patch& receiver, const RaySubset& subset)
{
    std::vector<float> ends(std::size_t(subset.count()), 1.0f);
    for (std::uint32_t k = 0; k < std::uint32_t(ends.size()); ++k) {
        const auto [j, i] = subsetRay(subset, k);
        if (map.blocked(int(j), int(i)))
            ends[k] = segmentFirstHit(caster, source.sample(int(i)), receiver.sample(int(j)));
    }
    return ends;
}

} // namespace sightline::ui
