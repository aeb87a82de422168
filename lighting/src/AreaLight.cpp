#include "lighting/AreaLight.h"

#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include <glm/common.hpp>

#include "base/Error.h"

namespace sightline {

AreaLight AreaLight::white(int sourceCount)
{
    return fromSampleColours(std::vector<glm::vec3>(std::size_t(sourceCount), glm::vec3(1.0f)));
}

AreaLight AreaLight::fromSampleColours(const std::vector<glm::vec3>& colours)
{
    if (colours.empty() || colours.size() > std::size_t(kMaxSourceSamples))
        throw Error("a light needs 1 to " + std::to_string(kMaxSourceSamples) + " samples");
    AreaLight light;
    light.sourceCount = int(colours.size());
    const std::size_t words = (colours.size() + 63) / 64;
    std::map<std::tuple<float, float, float>, std::size_t> groupOf;
    for (std::size_t i = 0; i < colours.size(); ++i) {
        const glm::vec3 c = colours[i];
        if (!std::isfinite(c.r) || !std::isfinite(c.g) || !std::isfinite(c.b) || c.r < 0 || c.g < 0 || c.b < 0)
            throw Error("light sample " + std::to_string(i) + " has a negative or non-finite colour");
        if (c == glm::vec3(0.0f))
            continue;
        auto [it, inserted] = groupOf.try_emplace({c.r, c.g, c.b}, light.groups.size());
        if (inserted) {
            if (light.groups.size() == std::size_t(kMaxLightGroups))
                throw Error("the light has more than " + std::to_string(kMaxLightGroups) +
                            " distinct colours; quantise its texture");
            light.groups.push_back({c, std::vector<std::uint64_t>(words, 0), 0});
        }
        LightGroup& group = light.groups[it->second];
        group.mask[i / 64] |= std::uint64_t(1) << (i % 64);
        ++group.count;
    }
    return light;
}

AreaLight AreaLight::fromTexture(const RgbImage& texture, const Patch& source, int levels)
{
    const float steps = float(std::max(levels, 1));
    std::vector<glm::vec3> colours(std::size_t(source.sampleCount()));
    for (int b = 0; b < source.nb; ++b) {
        for (int a = 0; a < source.na; ++a) {
            const glm::vec3 c = texture.nearest((a + 0.5) / source.na, (b + 0.5) / source.nb);
            colours[std::size_t(b * source.na + a)] = glm::round(c * steps) / steps;
        }
    }
    return fromSampleColours(colours);
}

glm::vec3 AreaLight::unoccluded() const
{
    glm::vec3 sum(0.0f);
    for (const LightGroup& group : groups)
        sum += group.colour * float(group.count);
    return sourceCount ? sum / float(sourceCount) : sum;
}

} // namespace sightline
