#include "lighting/SoftShadow.h"

#include <bit>
#include <cmath>
#include <stdexcept>

namespace sightline {

LightImage shadeReceiver(const HiddenSampleMap& map, const AreaLight& light)
{
    if (light.sourceCount != map.sourceCount())
        throw std::invalid_argument("shadeReceiver: the light's sample count differs from the map's");
    LightImage image{map.receiverNa(), map.receiverNb(), std::vector<glm::vec3>(std::size_t(map.receiverCount()))};
    const float inverseS = 1.0f / float(map.sourceCount());
    for (int j = 0; j < map.receiverCount(); ++j) {
        const auto blocked = map.row(j);
        glm::vec3 sum(0.0f);
        for (const LightGroup& group : light.groups) {
            int seen = 0;
            for (std::size_t w = 0; w < blocked.size(); ++w)
                seen += std::popcount(group.mask[w] & ~blocked[w]);
            sum += group.colour * float(seen);
        }
        image.rgb[std::size_t(j)] = sum * inverseS;
    }
    return image;
}

double meanAbsoluteError(const ImportanceMap& a, const ImportanceMap& b)
{
    if (!a.sameGrid(b))
        throw std::invalid_argument("meanAbsoluteError: maps on different grids");
    if (a.values.empty())
        return 0.0;
    double sum = 0.0;
    for (std::size_t k = 0; k < a.values.size(); ++k)
        sum += std::abs(double(a.values[k]) - double(b.values[k]));
    return sum / double(a.values.size());
}

ImportanceMap denseLightFraction(const RayCastScene& scene, const Patch& source, const Patch& receiver,
                                 int samplesPerSide, RayCastOptions options)
{
    if (samplesPerSide < 32 || samplesPerSide % 32 != 0)
        throw std::invalid_argument("denseLightFraction: samplesPerSide must be a positive multiple of 32");
    options.jitter = {};
    const int k = samplesPerSide / 32;
    ImportanceMap sum(receiver.na, receiver.nb, 0.0f);
    std::vector<double> total(std::size_t(receiver.sampleCount()), 0.0);
    for (int sb = 0; sb < k; ++sb) {
        for (int sa = 0; sa < k; ++sa) {
            // Sub-patch (sa, sb): its 32x32 sample positions are exactly those of the dense grid.
            Patch part;
            part.corner = source.corner + double(sa) / k * source.u + double(sb) / k * source.v;
            part.u = source.u / double(k);
            part.v = source.v / double(k);
            part.na = part.nb = 32;
            const ImportanceMap fraction = receiverImportance(scene.sample(part, receiver, options));
            for (std::size_t j = 0; j < total.size(); ++j)
                total[j] += double(fraction.values[j]);
        }
    }
    for (std::size_t j = 0; j < total.size(); ++j)
        sum.values[j] = float(total[j] / double(k * k));
    return sum;
}

} // namespace sightline
