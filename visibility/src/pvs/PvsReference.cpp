#include "visibility/pvs/PvsReference.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

#include <glm/geometric.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "base/Error.h"
#include "visibility/pvs/EdgeRays.h"
#include "visibility/pvs/FirstHitCaster.h"
#include "visibility/pvs/PvsBake.h"

namespace sightline::pvs {

namespace {
struct CellResult {
    std::uint64_t referenceVisible = 0, bakedVisible = 0, missed = 0, extra = 0, pixels = 0, wrongPixels = 0, rays = 0;
    std::uint64_t edgeVisible = 0, edgeMissed = 0, edgeRays = 0;
    std::vector<Gap> gaps;
};

double soupArea(const std::vector<glm::vec3>& soup)
{
    double area = 0.0;
    for (std::size_t t = 0; t + 2 < soup.size(); t += 3)
        area += 0.5 * glm::length(glm::cross(glm::dvec3(soup[t + 1] - soup[t]), glm::dvec3(soup[t + 2] - soup[t])));
    return area;
}

/// The gaps of a missed pair: every reference ray from the cell's points that reaches the object,
/// grouped into the openings they pass through among the other objects' triangles. `spacing`: how far apart neighbouring rays'
/// ends lie (stratified points: about a stratum and a half).
std::vector<Gap> missedPairGaps(const WorldTriangles& world, const FirstHitCaster& caster, const std::vector<std::int32_t>& objectOf,
                                std::uint32_t cell, std::uint32_t object, const std::vector<glm::vec3>& from,
                                const std::vector<glm::vec3>& targets, double spacing, std::uint64_t& rays)
{
    std::vector<suggest::OpeningRay> witnesses;
    for (std::size_t q = 0; q < targets.size(); ++q)
        for (std::size_t p = 0; p < from.size(); ++p) {
            ++rays;
            const RayHit hit = caster.cast(from[p], targets[q] - from[p], 1.0f + 1e-3f);
            if (hit.instance >= 0 && objectOf[std::size_t(hit.instance)] == std::int32_t(object))
                witnesses.push_back({glm::dvec3(from[p]), glm::dvec3(from[p] + hit.t * (targets[q] - from[p])), witnesses.size()});
        }
    // The openings are shaped by what stands between: the object's own surface, where every
    // witness ends, is left out.
    WorldTriangles blockers;
    for (std::size_t t = 0; t < world.size(); ++t)
        if (objectOf[world.instanceOf[t]] != std::int32_t(object)) {
            blockers.vertices.insert(blockers.vertices.end(), &world.vertices[3 * t], &world.vertices[3 * t] + 3);
            blockers.instanceOf.push_back(world.instanceOf[t]);
        }
    std::vector<Gap> gaps;
    for (suggest::Opening& opening : suggest::groupOpenings(blockers, witnesses, spacing)) {
        Gap gap{cell, object, {}, {}, {}, {}};
        double closest = std::numeric_limits<double>::infinity();
        for (std::uint64_t id : opening.raySample) {
            const suggest::OpeningRay& ray = witnesses[std::size_t(id)];
            if (gap.witnesses.size() < kGapWitnessSample)
                gap.witnesses.emplace_back(glm::vec3(ray.from), glm::vec3(ray.to));
            // The representative: the witness passing nearest the opening's centre.
            const glm::dvec3 d = ray.to - ray.from;
            const double t = std::clamp(glm::dot(opening.centre - ray.from, d) / std::max(glm::dot(d, d), 1e-24), 0.0, 1.0);
            const double miss = glm::length(ray.from + t * d - opening.centre);
            if (miss < closest) {
                closest = miss;
                gap.from = glm::vec3(ray.from);
                gap.to = glm::vec3(ray.to);
            }
        }
        opening.raySample.clear();
        gap.opening = std::move(opening);
        gaps.push_back(std::move(gap));
    }
    return gaps;
}

/// Panoramas from `eyes` (random points of cell c), "rendered" with first-hit rays: the pixels
/// that show an object the cell's row culls are wrong.
void countPanoramaErrors(const FirstHitCaster& caster, const std::vector<std::int32_t>& objectOf, const PvsData& pvs,
                         std::uint32_t c, const std::vector<glm::vec3>& eyes, const ReferenceSettings& settings, CellResult& r)
{
    for (const glm::vec3& eye : eyes)
        for (int y = 0; y < settings.height; ++y)
            for (int x = 0; x < settings.width; ++x) {
                const double theta = std::numbers::pi * (y + 0.5) / settings.height;
                const double phi = 2.0 * std::numbers::pi * (x + 0.5) / settings.width;
                const glm::vec3 d(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                                  float(std::sin(theta) * std::sin(phi)));
                ++r.pixels;
                ++r.rays;
                const RayHit hit = caster.cast(eye, d, 1e7f);
                if (hit.instance < 0)
                    continue;
                const std::int32_t o = objectOf[std::size_t(hit.instance)];
                if (o >= 0 && !pvs.rows.visible(c, std::size_t(o)))
                    ++r.wrongPixels;
            }
}

/// Per scene instance, the index of the PVS object that holds it (-1: none); throws where an
/// object names an instance the scene lacks.
std::vector<std::int32_t> objectOfInstances(const Scene& scene, const PvsData& pvs)
{
    const std::size_t objectCount = pvs.objects.size();
    std::vector<std::int32_t> objectOf(scene.instances.size(), -1);
    for (std::size_t o = 0; o < objectCount; ++o)
        for (std::uint32_t i : pvs.objects[o].instances) {
            if (i >= objectOf.size())
                throw Error("pvs check: object '" + pvs.objects[o].name + "' names instance " + std::to_string(i) +
                            ", the scene has " + std::to_string(objectOf.size()) + " (another scene?)");
            objectOf[i] = std::int32_t(o);
        }
    return objectOf;
}

/// The cells to check: `cells` (at least one) of the `cellCount`, drawn with `seed`, sorted.
std::vector<std::uint32_t> sampledCells(std::size_t cellCount, int cells, std::uint64_t seed)
{
    // Random cells without repeats: a seeded shuffle's first ones, then sorted.
    std::vector<std::uint32_t> order(cellCount);
    for (std::size_t c = 0; c < cellCount; ++c)
        order[c] = std::uint32_t(c);
    for (std::size_t k = cellCount; k > 1; --k)
        std::swap(order[k - 1], order[mixSeed(seed, k) % k]);
    order.resize(std::min<std::size_t>(cellCount, std::size_t(std::max(cells, 1))));
    std::sort(order.begin(), order.end());
    return order;
}

/// Per object, the points on it the reference casts toward, and how far apart they lie.
void objectTargets(const WorldTriangles& world, const std::vector<std::int32_t>& objectOf, std::size_t objectCount,
                   const ReferenceSettings& settings, std::uint64_t seed, std::vector<std::vector<glm::vec3>>& targets,
                   std::vector<double>& objectSpacing)
{
    // Targets on every object, from the reference's own seeds.
    std::vector<std::vector<glm::vec3>> soup(objectCount);
    targets.resize(objectCount);
    for (std::size_t t = 0; t < world.size(); ++t) {
        const std::int32_t o = objectOf[world.instanceOf[t]];
        if (o >= 0)
            soup[std::size_t(o)].insert(soup[std::size_t(o)].end(), &world.vertices[3 * t], &world.vertices[3 * t] + 3);
    }
    objectSpacing.resize(objectCount);
    for (std::size_t o = 0; o < objectCount; ++o) {
        targets[o] = surfacePoints(soup[o], settings.objectPoints, mixSeed(seed ^ 0x726566ull, o));
        objectSpacing[o] = 1.5 * std::sqrt(soupArea(soup[o]) / double(std::max(settings.objectPoints, 1)));
    }
}

/// Checks cell c against every object into `r`: the reference's rays from random points of the
/// cell, the edge search where they see nothing, the gaps of missed pairs, then the panoramas.
/// Returns early, leaving `r` partial, when the settings' cancel flag is set.
void checkCell(const WorldTriangles& world, const FirstHitCaster& caster, const std::vector<std::int32_t>& objectOf,
               const PvsData& pvs, const ReferenceSettings& settings, std::uint64_t seed,
               const std::vector<std::vector<glm::vec3>>& targets, const std::vector<double>& objectSpacing,
               std::uint32_t c, CellResult& r)
{
    const std::size_t objectCount = pvs.objects.size();
    const std::vector<glm::vec3> from = boxPoints(pvs.cells[c], settings.cellPoints, mixSeed(seed, c));
    const double cellSpacing = 1.5 * glm::length(glm::dvec3(pvs.cells[c].max - pvs.cells[c].min)) /
                               std::cbrt(double(std::max(settings.cellPoints, 1)));
    const std::vector<glm::vec3> edgeFrom(from.begin(), from.begin() + std::min<std::ptrdiff_t>(std::ptrdiff_t(from.size()),
                                                                                                std::max(settings.edgeCellPoints, 0)));
    std::unordered_map<std::int64_t, int> met;
    for (std::size_t o = 0; o < objectCount; ++o) {
        if (settings.cancel && settings.cancel->load())
            return;
        bool seen = false;
        met.clear();
        for (std::size_t q = 0; q < targets[o].size() && !seen; ++q)
            for (const glm::vec3& p : from) {
                ++r.rays;
                const RayHit hit = caster.cast(p, targets[o][q] - p, 1.0f + 1e-3f);
                if (hit.instance >= 0 && objectOf[std::size_t(hit.instance)] == std::int32_t(o)) {
                    seen = true;
                    break;
                }
                if (hit.triangle >= 0)
                    ++met[hit.triangle];
            }
        const bool kept = pvs.rows.visible(c, o);
        bool edgeSeen = false;
        if (!seen && settings.edgeBlockers > 0 && !met.empty()) {
            const std::vector<std::int64_t> blockers = mostMet(met, settings.edgeBlockers);
            edgeSeen = edgeWitness(world.vertices, caster, objectOf, std::int32_t(o), pvs.objects[o].bounds, edgeFrom,
                                   blockers, r.edgeRays);
            r.edgeVisible += edgeSeen;
            r.edgeMissed += edgeSeen && !kept;
        }
        r.referenceVisible += seen;
        r.bakedVisible += kept;
        if (seen && !kept) {
            ++r.missed;
            const double spacing = std::max(cellSpacing, objectSpacing[o]);
            for (Gap& gap : missedPairGaps(world, caster, objectOf, c, std::uint32_t(o), from, targets[o], spacing, r.rays))
                r.gaps.push_back(std::move(gap));
        }
        if (kept && !seen && !edgeSeen)
            ++r.extra;
    }
    countPanoramaErrors(caster, objectOf, pvs, c, boxPoints(pvs.cells[c], settings.views, mixSeed(seed ^ 0x657965ull, c)),
                        settings, r);
}

} // namespace

AccuracyReport measureAccuracy(const Scene& scene, const PvsData& pvs, const ReferenceSettings& settings)
{
    const auto start = std::chrono::steady_clock::now();
    const std::size_t cellCount = pvs.cells.size(), objectCount = pvs.objects.size();
    const std::vector<std::int32_t> objectOf = objectOfInstances(scene, pvs);
    const std::uint64_t seed = mixSeed(seedFromSha(pvs.sceneSha256), settings.seed);
    const std::vector<std::uint32_t> order = sampledCells(cellCount, settings.cells, seed);

    const WorldTriangles world = worldTriangles(scene);
    std::vector<std::vector<glm::vec3>> targets;
    std::vector<double> objectSpacing;
    objectTargets(world, objectOf, objectCount, settings, seed, targets, objectSpacing);
    const FirstHitCaster caster(scene);

    std::vector<CellResult> results(order.size());
    const int threads = settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(std::size_t(0), order.size(), [&](std::size_t k) {
            checkCell(world, caster, objectOf, pvs, settings, seed, targets, objectSpacing, order[k], results[k]);
        });
    });
    if (settings.cancel && settings.cancel->load())
        throw PvsCancelled();
    AccuracyReport report;
    report.cells = order;
    for (CellResult& r : results) {
        report.referenceVisible += r.referenceVisible;
        report.bakedVisible += r.bakedVisible;
        report.missed += r.missed;
        report.extra += r.extra;
        report.pixels += r.pixels;
        report.wrongPixels += r.wrongPixels;
        report.rays += r.rays;
        report.edgeVisible += r.edgeVisible;
        report.edgeMissed += r.edgeMissed;
        report.edgeRays += r.edgeRays;
        report.gaps.insert(report.gaps.end(), r.gaps.begin(), r.gaps.end());
    }
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace sightline::pvs
