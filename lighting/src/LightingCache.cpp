#include "lighting/LightingCache.h"

#include <algorithm>
#include <chrono>
#include <numeric>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace sightline {

namespace {

/// Whether moving something inside `region` could change `light`'s shadows at any point: a point
/// or spot light's segments stay within its range of it, so a region out of range cannot.
bool mayAffect(const Light& light, const Bounds& region)
{
    if (region.empty())
        return false;
    if ((light.type == LightType::Point || light.type == LightType::Spot) && light.range > 0.0) {
        const glm::dvec3 nearest = glm::clamp(light.position, glm::dvec3(region.min), glm::dvec3(region.max));
        return glm::length(nearest - light.position) < light.range;
    }
    return true;
}

double meanColour(const glm::dvec3& c) { return (c.x + c.y + c.z) / 3.0; }

} // namespace

LightingCache::LightingCache(std::vector<ShadingPoint> points, std::vector<Light> lights)
    : points_(std::move(points)), tiling_(std::make_unique<PointTiling>(points_)), lights_(std::move(lights)),
      kept_(lights_.size()), shown_(points_.size(), glm::dvec3(0.0))
{
}

void LightingCache::markStale(std::size_t index)
{
    Kept& kept = kept_[index];
    if (!kept.stale)
        kept.staleSince = frame_;
    kept.stale = true;
}

void LightingCache::setLight(std::size_t index, const Light& light)
{
    lights_.at(index) = light;
    markStale(index);
}

void LightingCache::sceneChanged(const Bounds& region)
{
    for (std::size_t l = 0; l < lights_.size(); ++l)
        if (mayAffect(lights_[l], region))
            markStale(l);
}

std::size_t LightingCache::staleCount() const
{
    return std::size_t(std::count_if(kept_.begin(), kept_.end(), [](const Kept& k) { return k.stale; }));
}

void LightingCache::resum()
{
    std::fill(shown_.begin(), shown_.end(), glm::dvec3(0.0));
    for (const Kept& kept : kept_)
        if (kept.computed)
            for (std::size_t j = 0; j < points_.size(); ++j)
                shown_[j] += kept.colour * double(kept.field[j]);
}

LightingCache::Frame LightingCache::update(const LightingScene& scene, std::uint64_t budget, int threads)
{
    const auto start = std::chrono::steady_clock::now();
    ++frame_;
    Frame frame;
    std::vector<std::size_t> order;
    for (std::size_t l = 0; l < kept_.size(); ++l)
        if (kept_[l].stale)
            order.push_back(l);
    // Never computed first (their light is missing from the view), then brightness x age.
    const auto priority = [&](std::size_t l) {
        const Kept& k = kept_[l];
        return k.computed ? k.brightness * double(1 + frame_ - k.staleSince) : INFINITY;
    };
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return priority(a) > priority(b); });
    DirectLightOptions options;
    options.threads = threads;
    options.tiling = tiling_.get();
    for (const std::size_t l : order) {
        const std::uint64_t cost = std::uint64_t(lights_[l].sampleCount()) * points_.size();
        if (frame.refreshed > 0 && frame.segments + cost > budget)
            break;
        Light white = lights_[l];
        white.colour = glm::dvec3(1.0);
        const std::vector<glm::dvec3> field = directIrradiance(scene, {white}, points_, options);
        Kept& kept = kept_[l];
        kept.field.resize(points_.size(), 0.0f);   // a light never computed shows nothing: colour 0
        double brightness = 0.0;
        for (std::size_t j = 0; j < points_.size(); ++j) {
            const float value = float(field[j].x);
            shown_[j] += lights_[l].colour * double(value) - kept.colour * double(kept.field[j]);
            brightness += double(value);
            kept.field[j] = value;
        }
        kept.colour = lights_[l].colour;
        kept.brightness = brightness * meanColour(kept.colour);
        kept.computed = true;
        kept.stale = false;
        ++frame.refreshed;
        frame.lights.push_back(l);
        frame.segments += cost;
    }
    frame.stale = staleCount();
    frame.exact = frame.stale == 0;
    if (frame.exact && frame.refreshed > 0)
        resum();   // the differences' rounding gone: the kept fields summed light by light
    frame.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return frame;
}

std::vector<float> LightingCache::staleness() const
{
    std::vector<double> stale(points_.size(), 0.0), all(points_.size(), 0.0);
    for (const Kept& kept : kept_) {
        if (!kept.computed)
            continue;
        const double weight = meanColour(kept.colour);
        for (std::size_t j = 0; j < points_.size(); ++j) {
            const double value = weight * double(kept.field[j]);
            all[j] += value;
            if (kept.stale)
                stale[j] += value;
        }
    }
    std::vector<float> share(points_.size(), 0.0f);
    for (std::size_t j = 0; j < points_.size(); ++j)
        share[j] = all[j] > 0.0 ? float(stale[j] / all[j]) : 0.0f;
    // A light never computed lights nothing yet: where it would, the view is wholly stale. Its
    // reach is unknown until computed, so every point is marked.
    if (std::any_of(kept_.begin(), kept_.end(), [](const Kept& k) { return k.stale && !k.computed; }))
        std::fill(share.begin(), share.end(), 1.0f);
    return share;
}

} // namespace sightline
