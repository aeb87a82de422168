#include "lighting/LightingCache.h"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <numeric>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "lights/PointTiles.h"
#include "lights/RegionShafts.h"
#include "base/Error.h"

namespace sightline {

namespace {

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
    setPlan(std::move(plan));
}

void LightingCache::setPlan(LowResolutionPlan plan)
{
    if (plan.points != points_.size())
        throw Error("the low-resolution plan covers " + std::to_string(plan.points) + " points, the cache " +
                    std::to_string(points_.size()));
    plan_ = std::move(plan);
    coarsePoints_.clear();
    coarsePoints_.reserve(plan_.coarse.size());
    for (const std::uint32_t p : plan_.coarse)
        coarsePoints_.push_back(points_.at(p));
    coarseTiling_ = coarsePoints_.empty() ? nullptr : std::make_unique<PointTiling>(coarsePoints_);
}

LightingCache::~LightingCache() = default;

void LightingCache::markStale(std::size_t index)
{
    Kept& kept = kept_[index];
    if (!kept.stale)
        kept.staleSince = frame_;
    kept.stale = true;
    kept.whole = true;
    kept.stalePoints.clear();
}

void LightingCache::markStalePoints(std::size_t index, std::vector<std::uint32_t> points)
{
    Kept& kept = kept_[index];
    if (points.empty() || (kept.stale && kept.whole))
        return;
    if (!kept.stale) {
        kept.stale = true;
        kept.whole = false;
        kept.staleSince = frame_;
        kept.stalePoints = std::move(points);
        return;
    }
    std::vector<std::uint32_t> both;
    both.reserve(kept.stalePoints.size() + points.size());
    std::set_union(kept.stalePoints.begin(), kept.stalePoints.end(), points.begin(), points.end(), std::back_inserter(both));
    kept.stalePoints = std::move(both);
}

std::size_t LightingCache::stalePointCount(std::size_t index) const
{
    const Kept& kept = kept_[index];
    return kept.whole ? points_.size() : kept.stalePoints.size();
}

void LightingCache::setLight(std::size_t index, const Light& light, bool rough)
{
    lights_.at(index) = light;
    markStale(index);
    kept_[index].roughNext = rough && coarseTiling_ != nullptr;
}

void LightingCache::sceneChanged(std::span<const Bounds> regions)
{
    if (regions.empty())
        return;
    for (std::size_t l = 0; l < lights_.size(); ++l)
        if (kept_[l].computed && !(kept_[l].stale && kept_[l].whole))
            markStalePoints(l, lights::pointsShadowedThrough(lights_[l], regions, tiling_->tiles(), points_));
}

void LightingCache::sceneChanged(std::span<const Bounds> regions, std::vector<ShadingPoint> points,
                                 std::span<const std::size_t> previous, LowResolutionPlan plan)
{
    if (previous.size() != points.size())
        throw Error("the points' previous indices number " + std::to_string(previous.size()) + ", the points " +
                    std::to_string(points.size()));
    if (plan.points != points.size())   // before anything changes: a refusal leaves the cache as it was
        throw Error("the low-resolution plan covers " + std::to_string(plan.points) + " points, the cache " +
                    std::to_string(points.size()));
    std::vector<std::uint32_t> added;
    for (std::size_t j = 0; j < previous.size(); ++j) {
        if (previous[j] == SIZE_MAX)
            added.push_back(std::uint32_t(j));
        else if (previous[j] >= points_.size())
            throw Error("point " + std::to_string(j) + "'s previous index " + std::to_string(previous[j]) + " is past the " +
                        std::to_string(points_.size()) + " points");
    }
    // Fields carried over to the new points (a new point shows nothing until refreshed); a light
    // stale at some old points is stale at the new points they became.
    std::vector<glm::dvec3> shown(points.size(), glm::dvec3(0.0));
    for (Kept& kept : kept_) {
        if (!kept.computed)
            continue;
        // Carried over, summed into the view light by light (as resum() sums) and weighed.
        std::vector<float> field(points.size(), 0.0f);
        double brightness = 0.0;
        for (std::size_t j = 0; j < points.size(); ++j)
            if (previous[j] != SIZE_MAX) {
                field[j] = kept.field[previous[j]];
                shown[j] += kept.colour * double(field[j]);
                brightness += double(field[j]);
            }
        kept.field = std::move(field);
        kept.brightness = brightness * meanColour(kept.colour);
        if (kept.stale && !kept.whole) {
            std::vector<bool> was(points_.size(), false);
            for (const std::uint32_t j : kept.stalePoints)
                was[j] = true;
            kept.stalePoints.clear();
            for (std::size_t j = 0; j < points.size(); ++j)
                if (previous[j] != SIZE_MAX && was[previous[j]])
                    kept.stalePoints.push_back(std::uint32_t(j));
            if (kept.stalePoints.empty()) {   // none of its stale points is left: fresh at the rest
                kept.stale = false;
                kept.whole = true;
            }
        }
    }
    points_ = std::move(points);
    tiling_ = std::make_unique<PointTiling>(points_);
    setPlan(std::move(plan));
    shown_ = std::move(shown);
    touched_.clear();
    touchedAll_ = false;
    for (std::size_t l = 0; l < kept_.size(); ++l)
        if (kept_[l].computed)
            markStalePoints(l, added);
    sceneChanged(regions);
}

std::size_t LightingCache::staleCount() const
{
    return std::size_t(std::count_if(kept_.begin(), kept_.end(), [](const Kept& k) { return k.stale; }));
}

void LightingCache::resumTouched()
{
    if (touchedAll_) {
        resum();
    } else {
        std::sort(touched_.begin(), touched_.end());
        touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
        for (const std::uint32_t j : touched_) {
            glm::dvec3 sum(0.0);
            for (const Kept& kept : kept_)
                if (kept.computed)
                    sum += kept.colour * double(kept.field[j]);
            shown_[j] = sum;
        }
    }
    touched_.clear();
    touchedAll_ = false;
}

void LightingCache::resum()
{
    std::fill(shown_.begin(), shown_.end(), glm::dvec3(0.0));
    for (const Kept& kept : kept_)
        if (kept.computed)
            for (std::size_t j = 0; j < points_.size(); ++j)
                shown_[j] += kept.colour * double(kept.field[j]);
}

void LightingCache::keepAt(std::size_t index, const std::vector<float>& values)
{
    Kept& kept = kept_[index];
    if (!touchedAll_) {
        touched_.insert(touched_.end(), kept.stalePoints.begin(), kept.stalePoints.end());
        if (touched_.size() >= points_.size()) {   // as dear as summing every point again
            touchedAll_ = true;
            touched_.clear();
        }
    }
    double change = 0.0;
    for (std::size_t k = 0; k < values.size(); ++k) {
        const std::uint32_t j = kept.stalePoints[k];
        shown_[j] += kept.colour * (double(values[k]) - double(kept.field[j]));
        change += double(values[k]) - double(kept.field[j]);
        kept.field[j] = values[k];
    }
    kept.brightness += change * meanColour(kept.colour);
}

void LightingCache::keep(std::size_t index, std::vector<float> field)
{
    Kept& kept = kept_[index];
    touchedAll_ = true;
    touched_.clear();
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
    options.countAllTerms = true;   // the cost panel's terms: every pair the light reaches
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
    options.countAllTerms = true;   // the cost panel's terms: every pair the light reaches
    for (const std::size_t l : order) {
        const std::uint64_t cost = std::uint64_t(lights_[l].sampleCount()) * stalePointCount(l);
        if (frame.refreshed > 0 && frame.segments + cost > budget)
            break;
        DirectLightStats stats;
        const auto began = std::chrono::steady_clock::now();
        Kept& kept = kept_[l];
        if (kept.whole) {
            const std::vector<glm::dvec3> field = directIrradiance(scene, {white(l)}, points_, options, &stats);
            std::vector<float> values(points_.size());
            for (std::size_t j = 0; j < points_.size(); ++j)
                values[j] = float(field[j].x);
            keep(l, std::move(values));
        } else {   // the points whose segments a change in the scene may cross, tiled anew
            std::vector<ShadingPoint> some;
            some.reserve(kept.stalePoints.size());
            for (const std::uint32_t j : kept.stalePoints)
                some.push_back(points_[j]);
            DirectLightOptions partial = options;
            partial.tiling = nullptr;
            const std::vector<glm::dvec3> field = directIrradiance(scene, {white(l)}, some, partial, &stats);
            std::vector<float> values(some.size());
            for (std::size_t k = 0; k < some.size(); ++k)
                values[k] = float(field[k].x);
            keepAt(l, values);
        }
        kept.cost = {.terms = stats.terms,
                     .rays = stats.segmentsCast,
                     .ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - began).count()};
        kept.stale = false;
        kept.whole = true;
        kept.stalePoints.clear();
        kept.refreshedAt = frame_;
        ++frame.refreshed;
        frame.lights.push_back(l);
        frame.segments += cost;
    }
    frame.stale = staleCount();
    frame.exact = frame.stale == 0;
    if (frame.exact && frame.refreshed > 0)
        resumTouched();   // the differences' rounding gone: the kept fields summed light by light
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
    std::vector<bool> unknown(points_.size(), false);
    for (const Kept& kept : kept_) {
        if (!kept.computed)
            continue;
        const double weight = meanColour(kept.colour);
        for (std::size_t j = 0; j < points_.size(); ++j)
            all[j] += weight * double(kept.field[j]);
        if (kept.stale && kept.whole)
            for (std::size_t j = 0; j < points_.size(); ++j)
                stale[j] += weight * double(kept.field[j]);
        else if (kept.stale)   // where a change in the scene may have moved its shadows, by how much is unknown
            for (const std::uint32_t j : kept.stalePoints)
                unknown[j] = true;
    }
    std::vector<float> share(points_.size(), 0.0f);
    for (std::size_t j = 0; j < points_.size(); ++j)
        share[j] = unknown[j] ? 1.0f : all[j] > 0.0 ? float(stale[j] / all[j]) : 0.0f;
    // A light never computed lights nothing yet: where it would, the view is wholly stale. Its
    // reach is unknown until computed, so every point is marked.
    if (std::any_of(kept_.begin(), kept_.end(), [](const Kept& k) { return k.stale && !k.computed; }))
        std::fill(share.begin(), share.end(), 1.0f);
    return share;
}

} // namespace sightline
