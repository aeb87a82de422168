#pragma once
// Internal to the light-map layouts (TexelCharts.cpp's charts, AoTexels.cpp's per-triangle tiles):
// rectangles packed into one atlas on shelves, and the density to suggest when an atlas would not
// fit its pixel budget.

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <utility>

namespace sightline::atlas {

struct ShelfRect {
    int width = 0, height = 0;   ///< 0 wide: takes no place
    int x = 0, y = 0;            ///< set by packWithin
};

/// Rectangles of `sizes` (double, so that no density wraps an int) packed on shelves, tallest
/// first (ties in index order), a one-texel gutter, in an atlas about as wide as sqrt(1.3 x their
/// summed area) or the widest one: `rects` sized and placed, and the atlas's width and height;
/// nothing when a rectangle, their sum or the atlas would exceed maxPixels.
std::optional<std::pair<int, int>> packWithin(std::span<ShelfRect> rects, std::span<const std::pair<double, double>> sizes,
                                              std::uint64_t maxPixels);

/// Throws sightline::Error for a light map that does not fit at `density`, naming a density that
/// does (three significant digits, rounded down), or saying that none does.
[[noreturn]] void refuseDensity(double density, std::uint64_t maxPixels, const std::function<bool(double)>& fits);

} // namespace sightline::atlas
