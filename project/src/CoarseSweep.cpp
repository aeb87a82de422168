#include "project/CoarseSweep.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

#include "project/CoarseOccluders.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"

namespace sightline {

namespace {

/// The lower median of `repeat` exact samplings after one untimed (as `bench` times).
double medianSampleMs(const CpuBitmaskSampler& sampler, const Patch& source, const Patch& receiver,
                      const BitmaskOptions& options, int repeat, HiddenSampleMap& map)
{
    map = sampler.sample(source, receiver, options);
    std::vector<double> times;
    for (int k = 0; k < std::max(repeat, 1); ++k) {
        const auto start = std::chrono::steady_clock::now();
        map = sampler.sample(source, receiver, options);
        times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(times.begin(), times.end());
    return times[(times.size() - 1) / 2];
}

/// `scene` with the meshes the request names simplified to `count` triangles.
Scene coarseLevel(const Scene& scene, std::size_t count, const std::optional<std::size_t>& instance, CoarseMeshCache& cache)
{
    Scene coarse = scene;
    CoarseOccluder spec;
    spec.triangles = count;
    if (instance) {
        spec.instance = *instance;
        applyCoarseOccluders({spec}, coarse, &cache);
        return coarse;
    }
    replaceDenseMeshes(coarse, spec);
    return coarse;
}

/// Adds to `falseBlocked` the rays only `map` blocks, to `falseFree` those only `exact` blocks.
void countDifferences(const HiddenSampleMap& exact, const HiddenSampleMap& map, std::uint64_t& falseBlocked,
                      std::uint64_t& falseFree)
{
    for (int j = 0; j < exact.receiverCount(); ++j) {
        const auto a = exact.row(j), b = map.row(j);
        for (int w = 0; w < exact.wordsPerRow(); ++w) {
            falseBlocked += std::uint64_t(std::popcount(b[std::size_t(w)] & ~a[std::size_t(w)]));
            falseFree += std::uint64_t(std::popcount(a[std::size_t(w)] & ~b[std::size_t(w)]));
        }
    }
}

BitmaskOptions sweepOptions(const ReceiverHeights* heights, int threads)
{
    BitmaskOptions options;
    options.threads = threads;
    options.heights = heights && !heights->empty() ? heights : nullptr;
    return options;
}

} // namespace

CoarseComparison compareCoarseLevel(const Scene& original, const Scene& coarse, const Patch& source, const Patch& receiver,
                                    const ReceiverHeights* heights, int threads, int repeat)
{
    validatePatchPair(source, receiver);
    const BitmaskOptions options = sweepOptions(heights, threads);
    CoarseComparison result;
    HiddenSampleMap exact, map;
    result.originalMs = medianSampleMs(CpuBitmaskSampler(original), source, receiver, options, repeat, exact);
    result.ms = medianSampleMs(CpuBitmaskSampler(coarse), source, receiver, options, repeat, map);
    result.rays = exact.rayCount();
    countDifferences(exact, map, result.falseBlocked, result.falseFree);
    return result;
}

CoarseSweep sweepCoarseOccluders(const Scene& scene, const Patch& source, const Patch& receiver,
                                 const ReceiverHeights* heights, const CoarseSweepRequest& request)
{
    validatePatchPair(source, receiver);
    if (request.instance && *request.instance >= scene.instances.size())
        throw Error("object " + std::to_string(*request.instance) + " does not exist (the scene has " +
                    std::to_string(scene.instances.size()) + " objects)");
    for (const std::size_t count : request.counts)
        if (count < 4 || count > 100'000'000)
            throw Error("a sweep's triangle counts must be in [4, 100000000], got " + std::to_string(count));
    const BitmaskOptions options = sweepOptions(heights, request.threads);
    CoarseSweep sweep;
    HiddenSampleMap exact;
    sweep.triangles = scene.triangleCount();
    sweep.ms = medianSampleMs(CpuBitmaskSampler(scene), source, receiver, options, request.repeat, exact);
    sweep.rays = exact.rayCount();
    CoarseMeshCache cache;
    for (const std::size_t count : request.counts) {
        const Scene coarse = coarseLevel(scene, count, request.instance, cache);
        HiddenSampleMap map;
        CoarseSweepPoint point;
        point.asked = count;
        point.triangles = coarse.triangleCount();
        point.ms = medianSampleMs(CpuBitmaskSampler(coarse), source, receiver, options, request.repeat, map);
        countDifferences(exact, map, point.falseBlocked, point.falseFree);
        sweep.points.push_back(point);
        if (request.progress && !request.progress(sweep))
            break;
    }
    return sweep;
}

CoarseToleranceFit fitCoarseToTolerance(const Scene& scene, const Patch& source, const Patch& receiver,
                                        const ReceiverHeights* heights, const CoarseToleranceRequest& request)
{
    validatePatchPair(source, receiver);
    if (!(request.tolerance >= 0.0 && request.tolerance <= 1.0))
        throw Error("the tolerance is a fraction of the rays in [0, 1], got " + std::to_string(request.tolerance));
    if (request.instance && *request.instance >= scene.instances.size())
        throw Error("object " + std::to_string(*request.instance) + " does not exist (the scene has " +
                    std::to_string(scene.instances.size()) + " objects)");
    std::size_t largest = 0;
    for (std::size_t i = 0; i < scene.instances.size(); ++i)
        if (!request.instance || *request.instance == i)
            largest = std::max(largest, scene.meshes[scene.instances[i].mesh].triangleCount());
    if (largest <= 8)
        throw Error(request.instance ? "the object's mesh has no more than 8 triangles: nothing to simplify"
                                     : "no mesh of the level has more than 8 triangles: nothing to simplify");
    const BitmaskOptions options = sweepOptions(heights, request.threads);
    CoarseToleranceFit fit;
    HiddenSampleMap exact;
    fit.tried.triangles = scene.triangleCount();
    fit.tried.ms = medianSampleMs(CpuBitmaskSampler(scene), source, receiver, options, 1, exact);
    fit.tried.rays = exact.rayCount();
    const auto allowed = std::uint64_t(std::floor(request.tolerance * double(exact.rayCount())));
    CoarseMeshCache cache;
    const auto measure = [&](std::size_t count) {
        const Scene coarse = coarseLevel(scene, count, request.instance, cache);
        HiddenSampleMap map;
        CoarseSweepPoint point;
        point.asked = count;
        point.triangles = coarse.triangleCount();
        point.ms = medianSampleMs(CpuBitmaskSampler(coarse), source, receiver, options, 1, map);
        countDifferences(exact, map, point.falseBlocked, point.falseFree);
        fit.tried.points.push_back(point);
        return point;
    };
    // Invariant: `hi` meets the tolerance (the full meshes, at first, answer every ray alike) and
    // `lo` does not, or is the floor.
    std::size_t lo = 4, hi = largest;
    if (const CoarseSweepPoint floor = measure(lo); floor.disagreeing() <= allowed) {
        fit.chosen = floor;
        return fit;
    }
    const double resolution = std::max(request.resolution, 1.0001);
    while (double(hi) / double(lo) > resolution && hi - lo > 1 && !(request.cancel && request.cancel->load())) {
        const auto mid = std::size_t(std::llround(std::sqrt(double(lo) * double(hi))));
        if (mid <= lo || mid >= hi)
            break;
        const CoarseSweepPoint point = measure(mid);
        if (point.disagreeing() <= allowed) {
            hi = mid;
            fit.chosen = point;
        } else {
            lo = mid;
        }
    }
    return fit;
}

std::vector<std::size_t> defaultSweepCounts(std::size_t triangles)
{
    std::vector<std::size_t> counts;
    for (std::size_t count = triangles / 2; count >= 100 && counts.size() < 8; count /= 2)
        counts.push_back(count);
    if (counts.empty() && triangles > 8)
        counts.push_back(std::max<std::size_t>(4, triangles / 2));
    return counts;
}

} // namespace sightline
