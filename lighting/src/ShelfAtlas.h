#pragma once
// Internal to the light-map layouts (TexelCharts.cpp's charts, AoTexels.cpp's per-triangle tiles):
// rectangles packed into one atlas on shelves, and the density to suggest when an atlas would not
// fit its pixel budget.

#include <cstdint>
#include <functional>
#include <span>
#include <utility>

namespace sightline::atlas {

struct ShelfRect {
    int width = 0, height = 0;   ///< 0 wide: takes no place
    int x = 0, y = 0;            ///< set by packShelves
};

/// Shelf packing, tallest first (ties in index order), a one-texel gutter, in an atlas about as
/// wide as sqrt(1.3 x `texels`) (the rectangles' summed area) or the widest rectangle. Returns
/// the atlas's width and height.
std::pair<int, int> packShelves(std::span<ShelfRect> rects, std::uint64_t texels);

/// Whether rectangles of `sizes` (double: any density) pack into at most maxPixels pixels.
bool fitsAtlas(std::span<ShelfRect> rects, std::span<const std::pair<double, double>> sizes, std::uint64_t maxPixels);

/// The largest density below `density` at which `fits` holds, within 0.1% (bisection; fits must
/// be monotone), or 0 when none does, not even a billionth of `density`.
double largestFittingDensity(double density, const std::function<bool(double)>& fits);

/// Throws sightline::Error for a light map that does not fit at `density`, naming a density that
/// does (three significant digits, rounded down), or saying that none does.
[[noreturn]] void refuseDensity(double density, std::uint64_t maxPixels, const std::function<bool(double)>& fits);

} // namespace sightline::atlas
