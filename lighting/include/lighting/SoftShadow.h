#pragma once
// Soft shadows of an area light on a receiver, from the hidden-samples map (Eisemann & Décoret
// §8): the light reaching receiver sample j is the sum, over the light's colour groups, of the
// group's colour times the number of its samples j sees, divided by the sample count S:
//     L_j = (1 / S) * sum_g colour_g * popcount(M_g & ~B_j).
// The paper counts bits with a logarithmic add tree in the shader; std::popcount is the CPU's
// POPCNT instruction. Shadow intensity is 1 - L_j for a white light.
//
// The receiver may be bumpy (a height field, §8): that changes where the receiver samples are,
// which the samplers handle (visibility/ReceiverHeights.h); the shading here is the same.
// Accuracy is measured against the Embree reference with the same samples (exact) and against a
// dense reference (denseLightFraction) that approximates the true light fraction.

#include <vector>

#include <glm/vec3.hpp>

#include "lighting/AreaLight.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/ImportanceMap.h"
#include "visibility/RayCastSampler.h"

namespace sightline {

struct LightImage {
    int na = 0, nb = 0;
    std::vector<glm::vec3> rgb;   ///< per receiver sample (index b * na + a), fraction of full light
};

/// The light each receiver sample gets. Throws std::invalid_argument when the light's sample count
/// differs from the map's.
LightImage shadeReceiver(const HiddenSampleMap& map, const AreaLight& light);

/// White light: the visible fraction per receiver sample (the receiver importance map).
inline ImportanceMap lightFraction(const HiddenSampleMap& map) { return receiverImportance(map); }

/// Mean absolute difference of two maps on one grid (throws std::invalid_argument otherwise).
double meanAbsoluteError(const ImportanceMap& a, const ImportanceMap& b);

/// A dense reference for the light fraction: the source split into k x k sub-patches of 32 x 32
/// samples each (so the regular grid of 32k x 32k samples over the whole source), each cast by
/// Embree, fractions averaged. `samplesPerSide` must be a positive multiple of 32. `options`
/// (threads, heights) are passed on; jitter is not (the reference is the regular dense grid).
ImportanceMap denseLightFraction(const RayCastScene& scene, const Patch& source, const Patch& receiver,
                                 int samplesPerSide, RayCastOptions options = {});

} // namespace sightline
