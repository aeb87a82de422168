#include "lighting/DirectLight.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "visibility/Error.h"
#include "visibility/ExactSegment.h"

namespace sightline {

namespace {

constexpr std::size_t kPointGrain = 64;   ///< points per task: a few packets each

/// Runs `body` in an arena of `threads` (0: the default arena).
template <typename Body>
void inArena(int threads, Body&& body)
{
    if (threads > 0) {
        tbb::task_arena arena(threads);
        arena.execute(body);
    } else {
        body();
    }
}

/// What each task reuses between calls.
struct Scratch {
    std::vector<glm::dvec3> starts, ends;
    std::vector<double> weights;
    std::vector<std::uint32_t> index;
    std::vector<std::uint8_t> blocked;

    void clear()
    {
        starts.clear(), ends.clear(), weights.clear(), index.clear();
    }
};

thread_local Scratch scratch;

struct Run {
    const LightingScene& scene;
    const std::vector<Light>& lights;
    std::span<const ShadingPoint> points;
    std::vector<glm::dvec3>& sums;
    std::atomic<std::uint64_t> terms{0}, cast{0};

    void addTerms(std::uint64_t t, std::uint64_t c)
    {
        terms += t;
        cast += c;
    }

    /// Every emitter of every light at each point, cast from the point.
    void reference(const std::vector<Emitter>& emitters)
    {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 16), [&](const auto& range) {
            Scratch& s = scratch;
            for (std::size_t j = range.begin(); j != range.end(); ++j) {
                const ShadingPoint& p = points[j];
                s.clear();
                for (const Emitter& e : emitters) {
                    const Light& light = lights[e.light];
                    const double w = emitterTerm(light, e.position, p.position, p.normal);
                    if (!(w > 0.0))
                        continue;
                    s.ends.push_back(light.type == LightType::Directional ? scene.reach().end(light, p.position) : e.position);
                    s.weights.push_back(w);
                    s.index.push_back(e.light);
                }
                s.blocked.resize(s.ends.size());
                scene.rays().segmentsBlocked(p.position, s.ends, s.blocked.data());
                glm::dvec3 sum(0.0);
                for (std::size_t k = 0; k < s.ends.size(); ++k)
                    if (!s.blocked[k])
                        sum += lights[s.index[k]].colour * s.weights[k];
                sums[j] = sum;
                addTerms(s.ends.size(), s.ends.size());
            }
        });
    }

    /// A point or spot light: from the light to every point it reaches.
    void fromLight(const Light& light)
    {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), kPointGrain), [&](const auto& range) {
            Scratch& s = scratch;
            s.clear();
            for (std::size_t j = range.begin(); j != range.end(); ++j) {
                const double w = emitterTerm(light, light.position, points[j].position, points[j].normal);
                if (!(w > 0.0))
                    continue;
                s.ends.push_back(points[j].position);
                s.weights.push_back(w);
                s.index.push_back(std::uint32_t(j));
            }
            s.blocked.resize(s.ends.size());
            scene.rays().segmentsBlocked(light.position, s.ends, s.blocked.data());
            for (std::size_t k = 0; k < s.ends.size(); ++k)
                if (!s.blocked[k])
                    sums[s.index[k]] += light.colour * s.weights[k];
            addTerms(s.ends.size(), s.ends.size());
        });
    }

    /// A directional light: parallel segments from the points.
    void directional(const Light& light)
    {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), kPointGrain), [&](const auto& range) {
            Scratch& s = scratch;
            s.clear();
            for (std::size_t j = range.begin(); j != range.end(); ++j) {
                const double w = emitterTerm(light, light.position, points[j].position, points[j].normal);
                if (!(w > 0.0))
                    continue;
                s.starts.push_back(points[j].position);
                s.ends.push_back(scene.reach().end(light, points[j].position));
                s.weights.push_back(w);
                s.index.push_back(std::uint32_t(j));
            }
            s.blocked.resize(s.ends.size());
            scene.rays().segmentsBlocked(s.starts, s.ends, s.blocked.data());
            for (std::size_t k = 0; k < s.ends.size(); ++k)
                if (!s.blocked[k])
                    sums[s.index[k]] += light.colour * s.weights[k];
            addTerms(s.ends.size(), s.ends.size());
        });
    }

    /// An area light by rays: each point casts to the samples that light it.
    void areaByRays(const Light& light)
    {
        const int count = light.area.sampleCount();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4), [&](const auto& range) {
            Scratch& s = scratch;
            for (std::size_t j = range.begin(); j != range.end(); ++j) {
                const ShadingPoint& p = points[j];
                s.clear();
                for (int i = 0; i < count; ++i) {
                    const glm::dvec3 sample = light.area.sample(i);
                    const double w = emitterTerm(light, sample, p.position, p.normal);
                    if (!(w > 0.0))
                        continue;
                    s.ends.push_back(sample);
                    s.weights.push_back(w);
                }
                s.blocked.resize(s.ends.size());
                scene.rays().segmentsBlocked(p.position, s.ends, s.blocked.data());
                for (std::size_t k = 0; k < s.ends.size(); ++k)
                    if (!s.blocked[k])
                        sums[j] += light.colour * s.weights[k];
                addTerms(s.ends.size(), s.ends.size());
            }
        });
    }

    /// An area light over the receiver grid the points are (Eisemann & Décoret §8): the bitmask
    /// sampler's hidden-samples map, then the terms of the samples each point sees. False when the
    /// light and the grid do not form a valid pair (the caller casts rays instead).
    bool areaByBitmask(const Light& light, const Patch& grid, int threads, std::uint64_t& rays)
    {
        if (light.area.sampleCount() > kMaxSourceSamples || grid.na > kMaxReceiverSide || grid.nb > kMaxReceiverSide)
            return false;
        try {
            validatePatchPair(light.area, grid);
        } catch (const Error&) {
            return false;
        }
        // The pair is valid, so each lies wholly on one side of the other's plane: on a back side
        // every term is zero.
        const glm::dvec3 between = grid.centre() - light.area.centre();
        if ((!light.twoSided && glm::dot(light.area.normal(), between) <= 0.0) || glm::dot(grid.normal(), between) >= 0.0)
            return true;
        BitmaskOptions options;
        options.threads = threads;
        const HiddenSampleMap map = scene.bitmask().sample(light.area, grid, options);
        const int count = light.area.sampleCount();
        std::vector<glm::dvec3> samples(static_cast<std::size_t>(count));
        for (int i = 0; i < count; ++i)
            samples[std::size_t(i)] = light.area.sample(i);
        std::atomic<std::uint64_t> nonZero{0};
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 16), [&](const auto& range) {
            std::uint64_t local = 0;
            for (std::size_t j = range.begin(); j != range.end(); ++j) {
                const ShadingPoint& p = points[j];
                for (int i = 0; i < count; ++i) {
                    const double w = emitterTerm(light, samples[std::size_t(i)], p.position, p.normal);
                    if (!(w > 0.0))
                        continue;
                    ++local;
                    if (!map.blocked(int(j), i))
                        sums[j] += light.colour * w;
                }
            }
            nonZero += local;
        });
        terms += nonZero.load();
        rays = std::uint64_t(count) * points.size();
        return true;
    }
};

} // namespace

void validateShadingPoints(std::span<ShadingPoint> points, const std::string& what)
{
    for (std::size_t j = 0; j < points.size(); ++j) {
        ShadingPoint& p = points[j];
        const auto finite = [](const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
        const std::string where = what + ": point " + std::to_string(j);
        if (!finite(p.position) || !finite(p.normal))
            throw Error(where + " has a non-finite coordinate");
        if (std::abs(p.position.x) > kMaxCoordinateMetres || std::abs(p.position.y) > kMaxCoordinateMetres ||
            std::abs(p.position.z) > kMaxCoordinateMetres)
            throw Error(where + " lies beyond 1e6 m from the origin");
        const double length = glm::length(p.normal);
        if (!(length > 0.0) || !std::isfinite(length))
            throw Error(where + " has a zero normal");
        p.normal /= length;
    }
}

LightingScene::LightingScene(const Scene& scene)
    : rays_(std::make_unique<RayCastScene>(scene)), bitmask_(std::make_unique<CpuBitmaskSampler>(scene)),
      reach_(scene.bounds())
{
}

std::vector<glm::dvec3> directIrradiance(const LightingScene& scene, const std::vector<Light>& lights,
                                         std::span<const ShadingPoint> points, const DirectLightOptions& options,
                                         DirectLightStats* stats)
{
    const auto start = std::chrono::steady_clock::now();
    std::vector<glm::dvec3> sums(points.size(), glm::dvec3(0.0));
    Run run{scene, lights, points, sums};
    std::size_t bitmaskLights = 0;
    std::uint64_t bitmaskRays = 0;
    if (options.receiverGrid && std::size_t(options.receiverGrid->sampleCount()) != points.size())
        throw Error("directIrradiance: the receiver grid's samples and the points differ in number");
    inArena(options.threads, [&] {
        if (options.path == LightingPath::Reference) {
            run.reference(lightEmitters(lights));
            return;
        }
        for (const Light& light : lights) {
            switch (light.type) {
            case LightType::Point:
            case LightType::Spot: run.fromLight(light); break;
            case LightType::Directional: run.directional(light); break;
            case LightType::Area: {
                std::uint64_t rays = 0;
                if (options.receiverGrid && run.areaByBitmask(light, *options.receiverGrid, options.threads, rays)) {
                    bitmaskLights += rays > 0;   // none where the pair faces away
                    bitmaskRays += rays;
                } else {
                    run.areaByRays(light);
                }
                break;
            }
            }
        }
    });
    if (stats) {
        stats->lights = lights.size();
        stats->lightSamples = 0;
        for (const Light& light : lights)
            stats->lightSamples += std::size_t(light.sampleCount());
        stats->points = points.size();
        stats->terms = run.terms.load();
        stats->segmentsCast = run.cast.load();
        stats->bitmaskLights = bitmaskLights;
        stats->bitmaskRays = bitmaskRays;
        stats->ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
    return sums;
}

std::vector<ShadingPoint> patchShadingPoints(const Patch& patch)
{
    std::vector<ShadingPoint> points(std::size_t(patch.sampleCount()));
    const glm::dvec3 normal = patch.normal();
    for (int j = 0; j < patch.sampleCount(); ++j)
        points[std::size_t(j)] = {patch.sample(j), normal};
    return points;
}

} // namespace sightline
