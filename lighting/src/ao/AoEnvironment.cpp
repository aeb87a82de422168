#include "lighting/ao/AoEnvironment.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <stb/stb_image.h>

#include "base/ImageCheck.h"
#include "base/ImageFile.h"
#include "base/Error.h"
#include "base/InputFile.h"

namespace sightline {

namespace {

constexpr double kPi = std::numbers::pi;

glm::dvec3 directionOf(double u, double v)   // u, v in [0, 1]: column and row fractions
{
    const double phi = (u - 0.5) * 2.0 * kPi, theta = v * kPi;
    return {std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi)};
}

void texelOf(const glm::dvec3& l, double& u, double& v)
{
    u = 0.5 + std::atan2(l.x, l.z) / (2.0 * kPi);
    v = std::acos(std::clamp(l.y, -1.0, 1.0)) / kPi;
}

} // namespace

AoEnvironment AoEnvironment::uniform(const glm::vec3& radiance)
{
    return fromPixels(2, 1, {radiance, radiance});
}

AoEnvironment AoEnvironment::fromPixels(int width, int height, std::vector<glm::vec3> pixels)
{
    AoEnvironment env;
    env.width_ = width;
    env.height_ = height;
    env.pixels_ = std::move(pixels);
    // Area average down to at most 128 x 64 (each pixel weighted by its solid angle, sin theta).
    env.smallW_ = std::min(width, 128);
    env.smallH_ = std::min(height, 64);
    env.small_.assign(std::size_t(env.smallW_) * std::size_t(env.smallH_), glm::vec3(0.0f));
    std::vector<double> weight(env.small_.size(), 0.0);
    std::vector<glm::dvec3> sum(env.small_.size(), glm::dvec3(0.0));
    for (int y = 0; y < height; ++y) {
        const double w = std::sin((y + 0.5) / height * kPi);
        const int sy = y * env.smallH_ / height;
        for (int x = 0; x < width; ++x) {
            const std::size_t s = std::size_t(sy) * std::size_t(env.smallW_) + std::size_t(x * env.smallW_ / width);
            sum[s] += w * glm::dvec3(env.pixels_[std::size_t(y) * std::size_t(width) + std::size_t(x)]);
            weight[s] += w;
        }
    }
    for (std::size_t s = 0; s < env.small_.size(); ++s)
        env.small_[s] = weight[s] > 0 ? glm::vec3(sum[s] / weight[s]) : glm::vec3(0.0f);
    return env;
}

AoEnvironment AoEnvironment::load(const std::filesystem::path& file)
{
    // Read whole, checked, then decoded from these very bytes: stb's HDR decoder trusts the header
    // and loops forever on some run-length data (ImageCheck.h).
    const std::string name = file.string();
    const std::string bytes = readInputFile(file, "environment", kMaxImageFileBytes);
    if (!image::isRadianceHdr(bytes))
        throw Error(name + ": not a Radiance HDR image (.hdr, RGBE); environments must be high dynamic range lat-long maps");
    int width = 0, height = 0, channels = 0;
    image::checkRadianceHdr(bytes, name, width, height);
    if (width < 2)
        throw Error(name + ": a Radiance HDR environment needs at least 2 pixels a row");
    const double aspect = double(width) / double(height);
    if (aspect < 2.0 / 1.5 || aspect > 2.0 * 1.5)
        throw Error(name + ": " + std::to_string(width) + "x" + std::to_string(height) +
                    " is not a latitude-longitude map (width should be twice the height)");
    float* data = stbi_loadf_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &width, &height,
                                         &channels, 3);
    if (!data)
        throw Error(name + ": cannot decode Radiance HDR: " + stbi_failure_reason());
    std::vector<glm::vec3> pixels(std::size_t(width) * std::size_t(height));
    for (std::size_t k = 0; k < pixels.size(); ++k) {
        const glm::vec3 p(data[3 * k], data[3 * k + 1], data[3 * k + 2]);
        pixels[k] = std::isfinite(p.r) && std::isfinite(p.g) && std::isfinite(p.b) ? glm::max(p, glm::vec3(0.0f)) : glm::vec3(0.0f);
    }
    stbi_image_free(data);
    return fromPixels(width, height, std::move(pixels));
}

glm::vec3 AoEnvironment::radiance(const glm::vec3& l) const
{
    double u = 0, v = 0;
    texelOf(glm::normalize(glm::dvec3(l)), u, v);
    const int x = std::clamp(int(u * width_), 0, width_ - 1), y = std::clamp(int(v * height_), 0, height_ - 1);
    return pixels_[std::size_t(y) * std::size_t(width_) + std::size_t(x)];
}

const std::vector<glm::vec3>& AoEnvironment::filtered(int k) const
{
    std::lock_guard lock(cache_->mutex);
    auto found = cache_->filtered.find(k);
    if (found != cache_->filtered.end())
        return found->second;
    // Cone filter with half-angle 2 / sqrt(k) (a cell's radius: pi r^2 = 4 pi / k) on the small map.
    const double half = std::min(kPi, 2.0 / std::sqrt(double(k)));
    const double cosHalf = std::cos(half);
    const int w = smallW_, h = smallH_;
    std::vector<glm::dvec3> dirs(std::size_t(w) * std::size_t(h));
    std::vector<double> area(dirs.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            dirs[std::size_t(y) * std::size_t(w) + std::size_t(x)] = directionOf((x + 0.5) / w, (y + 0.5) / h);
            area[std::size_t(y) * std::size_t(w) + std::size_t(x)] = std::sin((y + 0.5) / h * kPi);
        }
    std::vector<glm::vec3> out(dirs.size());
    const int band = int(std::ceil(half / kPi * h)) + 1;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::dvec3 c = dirs[std::size_t(y) * std::size_t(w) + std::size_t(x)];
            glm::dvec3 sum(0.0);
            double total = 0.0;
            for (int yy = std::max(0, y - band); yy <= std::min(h - 1, y + band); ++yy)
                for (int xx = 0; xx < w; ++xx) {
                    const std::size_t s = std::size_t(yy) * std::size_t(w) + std::size_t(xx);
                    if (glm::dot(dirs[s], c) < cosHalf)
                        continue;
                    sum += area[s] * glm::dvec3(small_[s]);
                    total += area[s];
                }
            out[std::size_t(y) * std::size_t(w) + std::size_t(x)] =
                total > 0 ? glm::vec3(sum / total) : small_[std::size_t(y) * std::size_t(w) + std::size_t(x)];
        }
    return cache_->filtered.emplace(k, std::move(out)).first->second;
}

std::vector<glm::vec3> AoEnvironment::directionRadiance(const AoDirectionSet& set, double rotationDegrees, double exposureEv) const
{
    const std::vector<glm::vec3>& map = filtered(set.k);
    const double angle = -rotationDegrees * kPi / 180.0;   // look up the unrotated map at R^-1 l
    const double c = std::cos(angle), s = std::sin(angle);
    const float scale = float(std::exp2(exposureEv));
    const int w = smallW_, h = smallH_;
    std::vector<glm::vec3> out;
    out.reserve(set.directions.size());
    for (const glm::vec3& d : set.directions) {
        const glm::dvec3 l(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
        double u = 0, v = 0;
        texelOf(l, u, v);
        // Bilinear between texel centres; wraps in u, clamps in v.
        const double fx = u * w - 0.5, fy = std::clamp(v * h - 0.5, 0.0, double(h - 1));
        const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
        const float tx = float(fx - x0), ty = float(fy - y0);
        auto at = [&](int x, int y) {
            x = ((x % w) + w) % w;
            y = std::clamp(y, 0, h - 1);
            return map[std::size_t(y) * std::size_t(w) + std::size_t(x)];
        };
        const glm::vec3 value = (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) +
                                ty * ((1 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1));
        out.push_back(value * scale);
    }
    return out;
}

} // namespace sightline
