#include "editor/OverlayTexels.h"

#include <algorithm>
#include <cmath>

#include "base/ColourMap.h"

namespace sightline::ui {

std::uint32_t OverlayTexels::rgbaAt(int a, int b) const
{
    const std::uint8_t* p = &rgba[4 * (std::size_t(b) * std::size_t(na) + std::size_t(a))];
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | std::uint32_t(p[3]);
}

OverlayTexels importanceTexels(const ImportanceMap& map)
{
    OverlayTexels texels{map.na, map.nb, std::vector<std::uint8_t>(4 * map.values.size()), false};
    for (std::size_t k = 0; k < map.values.size(); ++k) {
        const Rgb8 c = viridis8(map.values[k]);
        std::uint8_t* p = &texels.rgba[4 * k];
        p[0] = c.r;
        p[1] = c.g;
        p[2] = c.b;
        p[3] = 255;
    }
    return texels;
}

OverlayTexels lightTexels(const LightImage& light)
{
    // Interpolated between sample centres: a soft shadow reads as one (§8); importance stays
    // nearest, one flat cell per sample, because its read-out is per sample.
    OverlayTexels texels{light.na, light.nb, std::vector<std::uint8_t>(4 * light.rgb.size()), true};
    auto channel = [](float x) { return std::uint8_t(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f)); };
    for (std::size_t k = 0; k < light.rgb.size(); ++k) {
        std::uint8_t* p = &texels.rgba[4 * k];
        p[0] = channel(light.rgb[k].r);
        p[1] = channel(light.rgb[k].g);
        p[2] = channel(light.rgb[k].b);
        p[3] = 255;
    }
    return texels;
}

} // namespace sightline::ui
