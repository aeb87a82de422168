#include "visibility/suggest/ViewGaps.h"

#include <algorithm>

#include <glm/geometric.hpp>

#include "base/Error.h"

namespace sightline::suggest {

std::vector<Opening> findViewGaps(const WorldTriangles& triangles, const Patch& source, const Patch& receiver,
                                  const ReceiverHeights& heights, const HiddenSampleMap& map, const OpeningSettings& settings)
{
    const std::uint64_t unblocked = map.rayCount() - map.blockedCount();
    if (unblocked > kMaxGapRays)
        throw Error("openings are found among at most " + std::to_string(kMaxGapRays) + " unblocked rays, and this pair has " +
                    std::to_string(unblocked) + ": use fewer samples on the patches");
    const int sources = source.sampleCount(), receivers = receiver.sampleCount();
    std::vector<OpeningRay> rays;
    rays.reserve(std::size_t(unblocked));
    for (int j = 0; j < receivers; ++j) {
        const glm::dvec3 r = displacedReceiverSample(source, receiver, heights, j);
        for (int i = 0; i < sources; ++i)
            if (!map.blocked(j, i))
                rays.push_back({source.sample(i), r, std::uint64_t(j) * std::uint64_t(sources) + std::uint64_t(i)});
    }
    // Neighbouring rays start and end a sample apart on either patch.
    double spacing = 0.0;
    for (const Patch* patch : {&source, &receiver})
        spacing = std::max({spacing, glm::length(patch->u) / patch->na, glm::length(patch->v) / patch->nb});
    return groupOpenings(triangles, rays, spacing, settings);
}

} // namespace sightline::suggest
