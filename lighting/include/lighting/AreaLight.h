#pragma once
// The source patch as an area light (Eisemann & Décoret §8). Its samples may carry colours (a
// colour-textured light, or a neon sign whose tubes are the only lit samples): the paper passes
// the shader "the number of different colors, an array of color values, and an array of bitmasks
// indicating which samples are associated to each color", then counts bits per group. Samples of
// one colour form one group here too; a black sample emits nothing and belongs to no group.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "base/ImageFile.h"
#include "visibility/Patch.h"

namespace sightline {

struct LightGroup {
    glm::vec3 colour{1.0f};
    std::vector<std::uint64_t> mask;   ///< source bit i set when sample i has this colour
    int count = 0;                     ///< samples in the group
};

struct AreaLight {
    int sourceCount = 0;
    std::vector<LightGroup> groups;

    /// Every sample white: the light fraction of a receiver sample is its visible fraction.
    static AreaLight white(int sourceCount);
    /// Groups per-sample colours (index = source bit index) by exact equality; black samples are
    /// left out. Throws sightline::Error for non-finite or negative colours, or more than
    /// kMaxLightGroups distinct colours (a photo as a light texture: quantise it first).
    static AreaLight fromSampleColours(const std::vector<glm::vec3>& colours);
    /// Each source sample takes the texel under it (nearest; docs/design.md §2 sample positions,
    /// texture v up), quantised to `levels` steps per channel so that a photo makes few groups.
    static AreaLight fromTexture(const RgbImage& texture, const Patch& source, int levels = 8);

    /// The unoccluded light: the mean colour over all samples (white light: 1).
    glm::vec3 unoccluded() const;
};

inline constexpr int kMaxLightGroups = 256;

} // namespace sightline
