#include "TextureMean.h"

#include <algorithm>
#include <cmath>

#include <glm/vec3.hpp>

#include "base/Error.h"

namespace sightline::texture {

namespace {

/// A coordinate brought into [0, 1] as the wrap mode repeats, mirrors or clamps the image.
double wrapped(double u, int mode)
{
    if (mode == kWrapClamp)
        return std::clamp(u, 0.0, 1.0);
    if (mode == kWrapMirror) {
        const double m = u - 2.0 * std::floor(0.5 * u);   // [0, 2)
        return m <= 1.0 ? m : 2.0 - m;
    }
    return u - std::floor(u);
}

/// A texel index one step outside the image, brought back in: the far side when repeating, the
/// edge texel otherwise (a mirror's neighbour across its edge is that edge texel itself).
int texelIndex(int i, int size, int mode)
{
    if (mode == kWrapRepeat)
        return (i % size + size) % size;
    return std::clamp(i, 0, size - 1);
}

glm::vec3 bilinear(const RgbImage& image, double u, double v, Wrap wrap)
{
    const double x = wrapped(u, wrap.s) * image.width - 0.5, y = wrapped(v, wrap.t) * image.height - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const int x0 = int(fx), y0 = int(fy);
    const float wx = float(x - fx), wy = float(y - fy);
    const auto at = [&](int i, int j) {
        return image.pixels[std::size_t(texelIndex(j, image.height, wrap.t)) * std::size_t(image.width) +
                            std::size_t(texelIndex(i, image.width, wrap.s))];
    };
    return (1.0f - wy) * ((1.0f - wx) * at(x0, y0) + wx * at(x0 + 1, y0)) + wy * ((1.0f - wx) * at(x0, y0 + 1) + wx * at(x0 + 1, y0 + 1));
}

} // namespace

float srgbToLinear(float c)
{
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

std::vector<RgbImage> linearMips(RgbImage image)
{
    for (glm::vec3& p : image.pixels)
        p = {srgbToLinear(p.x), srgbToLinear(p.y), srgbToLinear(p.z)};
    std::vector<RgbImage> chain = mipChain(std::move(image));
    std::size_t first = 0;
    while (std::max(chain[first].width, chain[first].height) > kMaxKeptSide)
        ++first;
    chain.erase(chain.begin(), chain.begin() + std::ptrdiff_t(first));
    return chain;
}

const std::vector<RgbImage>* DecodedTextures::get(const std::string& key, const std::function<RgbImage()>& decode,
                                                  std::vector<std::string>& warnings)
{
    if (const auto at = kept_.find(key); at != kept_.end())
        return &at->second;
    if (failed_.count(key))
        return nullptr;
    std::vector<RgbImage> chain;
    try {
        chain = linearMips(decode());
    } catch (const Error& e) {
        failed_.insert(key);
        warnings.push_back(std::string(e.what()) + "; the materials it colours keep unknown albedos");
        return nullptr;
    }
    std::size_t bytes = 0;
    for (const RgbImage& level : chain)
        bytes += level.pixels.size() * sizeof(glm::vec3);
    if (bytes_ + bytes > budget_)
        kept_.clear(), bytes_ = 0;
    bytes_ += bytes;
    return &kept_.emplace(key, std::move(chain)).first->second;
}

std::vector<RgbImage> mipChain(RgbImage image)
{
    std::vector<RgbImage> chain;
    chain.push_back(std::move(image));
    while (chain.back().width > 1 || chain.back().height > 1) {
        const RgbImage& fine = chain.back();
        RgbImage coarse;
        coarse.width = (fine.width + 1) / 2, coarse.height = (fine.height + 1) / 2;
        coarse.pixels.resize(std::size_t(coarse.width) * std::size_t(coarse.height));
        const auto at = [&](int x, int y) {
            return fine.pixels[std::size_t(std::min(y, fine.height - 1)) * std::size_t(fine.width) + std::size_t(std::min(x, fine.width - 1))];
        };
        for (int y = 0; y < coarse.height; ++y)
            for (int x = 0; x < coarse.width; ++x)
                coarse.pixels[std::size_t(y) * std::size_t(coarse.width) + std::size_t(x)] =
                    0.25f * (at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) + at(2 * x + 1, 2 * y + 1));
        chain.push_back(std::move(coarse));
    }
    return chain;
}

glm::vec3 meanOverTriangle(const std::vector<RgbImage>& mips, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c,
                           Wrap wrap)
{
    const glm::dvec2 e1 = b - a, e2 = c - a;
    const double side = std::sqrt(0.5 * std::abs(e1.x * e2.y - e1.y * e2.x) * double(mips[0].width) * double(mips[0].height));
    if (!std::isfinite(side))   // a triangle over more repeats than a double counts: the whole image's mean
        return mips.back().pixels[0];
    const int n = int(std::clamp(std::ceil(2.0 * side), 1.0, 16.0));
    // Level L's texels are 2^L of level 0's; the samples lie about side / n level-0 texels apart.
    const double level = std::ceil(std::log2(std::max(1.0, 2.0 * side / n)));
    const RgbImage& image = mips[std::size_t(std::min(level, double(mips.size() - 1)))];
    // The n x n subdivision's n(n+1)/2 upright and n(n-1)/2 inverted triangles, all of one area.
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; i + j < n; ++j)
            for (const double offset : {1.0 / 3.0, 2.0 / 3.0}) {
                if (offset > 0.5 && i + j > n - 2)
                    continue;
                const glm::dvec2 p = a + (double(i) + offset) / n * e1 + (double(j) + offset) / n * e2;
                sum += glm::dvec3(bilinear(image, p.x, p.y, wrap));
            }
    return glm::vec3(sum / double(n * n));
}

} // namespace sightline::texture
