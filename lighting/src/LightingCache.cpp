#include "lighting/LightingCache.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "visibility/Error.h"

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

/// The light at low resolution: an area light's sample grid halved each way (its samples share
/// the area, so the unshadowed sum stays close: LightEmission.h).
Light roughLight(Light light)
{
    if (light.type == LightType::Area) {
        light.area.na = (light.area.na + 1) / 2;
        light.area.nb = (light.area.nb + 1) / 2;
    }
    return light;
}

} // namespace

LightingCache::LightingCache(std::vector<ShadingPoint> points, std::vector<Light> lights)
    : points_(std::move(points)), tiling_(std::make_unique<PointTiling>(points_)), lights_(std::move(lights)),
      kept_(lights_.size()), shown_(points_.size(), glm::dvec3(0.0))
{
}

LightingCache::LightingCache(std::vector<ShadingPoint> points, std::vector<Light> lights, LowResolutionPlan plan)
    : LightingCache(std::move(points), std::move(lights))
{
    if (plan.points != points_.size())
        throw Error("the low-resolution plan covers " + std::to_string(plan.points) + " points, the cache " +
                    std::to_string(points_.size()));
    plan_ = std::move(plan);
    coarsePoints_.reserve(plan_.coarse.size());
    for (const std::uint32_t p : plan_.coarse)
        coarsePoints_.push_back(points_.at(p));
    if (!coarsePoints_.empty())
        coarseTiling_ = std::make_unique<PointTiling>(coarsePoints_);
}

LightingCache::~LightingCache() = default;

void LightingCache::markStale(std::size_t index)
{
    Kept& kept = kept_[index];
    if (!kept.stale)
        kept.staleSince = frame_;
    kept.stale = true;
}

void LightingCache::setLight(std::size_t index, const Light& light, bool rough)
{
    lights_.at(index) = light;
    markStale(index);
    kept_[index].roughNext = rough && coarseTiling_ != nullptr;
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

void LightingCache::keep(std::size_t index, std::vector<float> field)
{
    Kept& kept = kept_[index];
    kept.field.resize(points_.size(), 0.0f);   // a light never computed shows nothing: colour 0
    double brightness = 0.0;
    const glm::dvec3 colour = lights_[index].colour;
    for (std::size_t j = 0; j < points_.size(); ++j) {
        shown_[j] += colour * double(field[j]) - kept.colour * double(kept.field[j]);
        brightness += double(field[j]);
    }
    kept.field = std::move(field);
    kept.colour = colour;
    kept.brightness = brightness * meanColour(colour);
    kept.computed = true;
}

std::vector<float> LightingCache::roughField(const LightingScene& scene, const Light& exactLight, int threads,
                                             std::uint64_t& segments, DirectLightStats& stats) const
{
    const Light light = roughLight(exactLight);
    DirectLightOptions options;
    options.threads = threads;
    options.tiling = coarseTiling_.get();
    std::vector<float> field(points_.size(), 0.0f);
    const std::vector<glm::dvec3> coarse = directIrradiance(scene, {light}, coarsePoints_, options, &stats);
    for (std::size_t k = 0; k < coarse.size(); ++k)
        field[plan_.coarse[k]] = float(coarse[k].x);
    // Edge refinement: blocks whose corners disagree are computed exactly, the rest interpolated.
    std::vector<ShadingPoint> refine;
    std::vector<std::uint32_t> refined;
    for (const LowResolutionPlan::Block& block : plan_.blocks) {
        std::array<float, 4> corner{};
        for (std::size_t c = 0; c < 4; ++c)
            corner[c] = field[block.corners[c]];
        const bool exact = cornersDisagree(corner);
        for (std::uint32_t k = block.first; k < block.first + block.count; ++k) {
            const LowResolutionPlan::Fine& fine = plan_.fine[k];
            if (exact) {
                refine.push_back(points_[fine.point]);
                refined.push_back(fine.point);
            } else {
                field[fine.point] = std::max(0.0f, fine.weights[0] * corner[0] + fine.weights[1] * corner[1] +
                                                       fine.weights[2] * corner[2] + fine.weights[3] * corner[3]);
            }
        }
    }
    if (!refine.empty()) {
        options.tiling = nullptr;
        DirectLightStats more;
        const std::vector<glm::dvec3> exact = directIrradiance(scene, {light}, refine, options, &more);
        stats.terms += more.terms;
        stats.segmentsCast += more.segmentsCast;
        for (std::size_t k = 0; k < exact.size(); ++k)
            field[refined[k]] = float(exact[k].x);
    }
    segments = std::uint64_t(light.sampleCount()) * (coarsePoints_.size() + refine.size());
    return field;
}

LightingCache::Frame LightingCache::update(const LightingScene& scene, std::uint64_t budget, int threads)
{
    const auto start = std::chrono::steady_clock::now();
    ++frame_;
    Frame frame;
    const auto white = [&](std::size_t l) {
        Light light = lights_[l];
        light.colour = glm::dvec3(1.0);
        return light;
    };
    // The lights being dragged first, at low resolution: they stay stale for the exact refresh.
    std::vector<bool> roughNow(kept_.size(), false);
    for (std::size_t l = 0; l < kept_.size(); ++l) {
        if (!kept_[l].roughNext)
            continue;
        std::uint64_t segments = 0;
        DirectLightStats stats;
        const auto began = std::chrono::steady_clock::now();
        keep(l, roughField(scene, white(l), threads, segments, stats));
        kept_[l].cost = {.terms = stats.terms,
                         .rays = stats.segmentsCast,
                         .ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - began).count(),
                         .rough = true};
        kept_[l].roughNext = false;
        roughNow[l] = true;
        ++frame.refreshed;
        ++frame.rough;
        frame.lights.push_back(l);
        frame.segments += segments;
    }
    std::vector<std::size_t> order;
    for (std::size_t l = 0; l < kept_.size(); ++l)
        if (kept_[l].stale && !roughNow[l])
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
        DirectLightStats stats;
        const auto began = std::chrono::steady_clock::now();
        const std::vector<glm::dvec3> field = directIrradiance(scene, {white(l)}, points_, options, &stats);
        std::vector<float> values(points_.size());
        for (std::size_t j = 0; j < points_.size(); ++j)
            values[j] = float(field[j].x);
        keep(l, std::move(values));
        kept_[l].cost = {.terms = stats.terms,
                         .rays = stats.segmentsCast,
                         .ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - began).count()};
        kept_[l].stale = false;
        kept_[l].refreshedAt = frame_;
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

LightingCache::LightCost LightingCache::cost(std::size_t index) const
{
    const Kept& kept = kept_.at(index);
    LightCost cost = kept.cost;
    cost.samples = lights_[index].sampleCount();
    cost.stale = kept.stale;
    cost.age = kept.computed ? frame_ - kept.refreshedAt : 0;
    return cost;
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
