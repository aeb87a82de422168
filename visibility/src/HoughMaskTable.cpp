#include "visibility/HoughMaskTable.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <numbers>

#include "base/Error.h"

namespace sightline {

namespace {
constexpr double kPi = std::numbers::pi;
const double kMaxDistance = std::sqrt(0.5);
} // namespace

HoughMaskTable::HoughMaskTable(int na, int nb, int width, int height)
    : na_(na), nb_(nb), width_(width), height_(height), words_((na * nb + 63) / 64)
{
    checkResolution(width, height);
    if (na < 1 || nb < 1 || na * nb > kMaxSourceSamples)
        throw Error("Hough table: unsupported sample grid " + std::to_string(na) + "x" + std::to_string(nb));
    checkBudget(na * nb, width, height);
    masks_.assign(std::size_t(width) * std::size_t(height) * std::size_t(words_), 0);
    for (int k = 0; k < height; ++k)
        for (int i = 0; i < width; ++i) {
            const double nx = std::cos(theta(i)), ny = std::sin(theta(i)), r = distance(k);
            std::uint64_t* mask = &masks_[(std::size_t(k) * std::size_t(width) + std::size_t(i)) * std::size_t(words_)];
            for (int b = 0; b < nb; ++b)
                for (int a = 0; a < na; ++a) {
                    const double x = (a + 0.5) / na - 0.5, y = (b + 0.5) / nb - 0.5;
                    if (nx * x + ny * y > r) {
                        const int bit = b * na + a;
                        mask[bit >> 6] |= std::uint64_t(1) << (bit & 63);
                    }
                }
        }
}

void HoughMaskTable::checkResolution(int width, int height)
{
    if (width < 4 || height < 2 || width > 8192 || height > 8192)
        throw Error("Hough table resolution must be between 4x2 and 8192x8192, got " + std::to_string(width) + "x" +
                    std::to_string(height));
}

std::uint64_t HoughMaskTable::bytesFor(int sampleCount, int width, int height)
{
    const std::uint64_t words = (std::uint64_t(std::max(sampleCount, 0)) + 63) / 64;
    return std::uint64_t(std::max(width, 0)) * std::uint64_t(std::max(height, 0)) * words * sizeof(std::uint64_t);
}

void HoughMaskTable::checkBudget(int sampleCount, int width, int height)
{
    const std::uint64_t bytes = bytesFor(sampleCount, width, height);
    if (bytes <= kMaxBytes)
        return;
    const auto gib = [](std::uint64_t b) {
        char text[32];
        std::snprintf(text, sizeof text, "%.1f GiB", double(b) / double(std::uint64_t(1) << 30));
        return std::string(text);
    };
    throw Error("a " + std::to_string(width) + "x" + std::to_string(height) + " Hough table for " +
                std::to_string(sampleCount) + " source samples would take " + gib(bytes) + ", more than the limit of " +
                gib(kMaxBytes) + "; use a smaller table or fewer source samples");
}

double HoughMaskTable::theta(int i) const { return -kPi + (i + 0.5) * (2.0 * kPi / width_); }
double HoughMaskTable::distance(int k) const { return -kMaxDistance + (k + 0.5) * (2.0 * kMaxDistance / height_); }

const std::uint64_t* HoughMaskTable::lookup(double ps, double pt, double qs, double qt) const
{
    // Left normal of the direction q - p.
    const double dx = qs - ps, dy = qt - pt;
    const double length = std::hypot(dx, dy);
    const double nx = -dy / length, ny = dx / length;
    const double r = nx * (ps - 0.5) + ny * (pt - 0.5);
    const double angle = std::atan2(ny, nx);   // [-pi, pi]
    int i = int(std::floor((angle + kPi) / (2.0 * kPi) * width_)) % width_;   // nearest: texel containing it
    if (i < 0)
        i += width_;
    const int k = std::clamp(int(std::floor((r + kMaxDistance) / (2.0 * kMaxDistance) * height_)), 0, height_ - 1);
    return texel(i, k);
}

} // namespace sightline
