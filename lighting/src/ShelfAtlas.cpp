#include "ShelfAtlas.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include "base/Error.h"

namespace sightline::atlas {

namespace {

/// Shelf packing as packWithin describes it, for rectangles already sized; `texels`: their area.
std::pair<int, int> packShelves(std::span<ShelfRect> rects, std::uint64_t texels)
{
    std::vector<std::size_t> order(rects.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) {
        return rects[l].height != rects[r].height ? rects[l].height > rects[r].height : l < r;
    });
    int widest = 1;
    for (const ShelfRect& rect : rects)
        widest = std::max(widest, rect.width + 1);
    const int atlasWidth = std::max(widest, int(std::ceil(std::sqrt(double(texels) * 1.3))) + 1);
    int x = 0, y = 0, shelf = 0;
    for (const std::size_t k : order) {
        ShelfRect& rect = rects[k];
        if (rect.width == 0)
            continue;
        if (x + rect.width + 1 > atlasWidth) {
            x = 0;
            y += shelf + 1;
            shelf = 0;
        }
        rect.x = x, rect.y = y;
        x += rect.width + 1;
        shelf = std::max(shelf, rect.height);
    }
    return {atlasWidth, std::max(1, y + shelf)};
}

/// The largest density below `density` at which `fits` holds, within 0.1% (bisection; fits must
/// be monotone), or 0 when none does, not even a billionth of `density`.
double largestFittingDensity(double density, const std::function<bool(double)>& fits)
{
    double low = density * 1e-9, high = density;
    if (!fits(low))
        return 0.0;
    while (high - low > 1e-3 * low) {
        const double mid = 0.5 * (low + high);
        (fits(mid) ? low : high) = mid;
    }
    return low;
}

} // namespace

std::optional<std::pair<int, int>> packWithin(std::span<ShelfRect> rects, std::span<const std::pair<double, double>> sizes,
                                              std::uint64_t maxPixels)
{
    double texels = 0.0;
    for (std::size_t k = 0; k < rects.size(); ++k) {
        const auto [width, height] = sizes[k];
        if (!(width * height <= double(maxPixels)))
            return std::nullopt;
        texels += width * height;
        if (texels > double(maxPixels))
            return std::nullopt;
        rects[k].width = int(width), rects[k].height = int(height);
    }
    const std::pair<int, int> atlas = packShelves(rects, std::uint64_t(texels));
    if (std::uint64_t(atlas.first) * std::uint64_t(atlas.second) > maxPixels)
        return std::nullopt;
    return atlas;
}

void refuseDensity(double density, std::uint64_t maxPixels, const std::function<bool(double)>& fits)
{
    const std::string start = "--texel " + std::to_string(density) + ": the light map would need more than " +
                              std::to_string(maxPixels >> 20) + " Mpixels; ";
    const double fit = largestFittingDensity(density, fits);
    if (fit <= 0.0)
        throw Error(start + "the level has too many surfaces for that at any density");
    // Three significant digits, rounded down; the suggestion itself must fit (shelf packing is
    // not strictly monotone, so it is checked, and lowered a step at a time if need be).
    const double step = std::pow(10.0, std::floor(std::log10(fit)) - 2.0);
    double suggested = std::floor(fit / step) * step;
    for (int k = 0; k < 100 && suggested > step && !fits(suggested); ++k)
        suggested -= step;
    char suggestion[32];
    std::snprintf(suggestion, sizeof suggestion, "%.3g", suggested);
    throw Error(start + "try --texel " + suggestion + " or less");
}

} // namespace sightline::atlas
