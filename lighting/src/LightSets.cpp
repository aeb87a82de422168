#include "lighting/LightSets.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "TaskArena.h"

namespace sightline {

namespace {

/// How near a segment's end a float first hit is taken for the end's own surface (the sampled
/// point lies on its triangle; an area light may lie on a ceiling).
constexpr double kEndSlackMetres = 1e-4;

struct SurfacePoints {
    std::vector<glm::dvec3> positions;
    std::vector<std::size_t> first;   ///< per instance, its points' range [first[i], first[i + 1])
};

/// Each triangle split into n x n similar triangles (n from the spacing, n^2 <= the cap), one
/// point at each one's centroid, grouped by instance.
SurfacePoints surfacePoints(const WorldTriangles& triangles, std::size_t instances, double spacing)
{
    std::vector<std::vector<glm::dvec3>> byInstance(instances);
    const int maxSide = int(std::sqrt(double(kMaxPointsPerTriangle)));
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::dvec3 a(triangles.vertices[3 * t]), b(triangles.vertices[3 * t + 1]), c(triangles.vertices[3 * t + 2]);
        const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        const int n = std::clamp(int(std::ceil(longest / spacing)), 1, maxSide);
        std::vector<glm::dvec3>& out = byInstance[triangles.instanceOf[t]];
        const auto at = [&](double u, double v) { return a + u * (b - a) + v * (c - a); };
        for (int i = 0; i < n; ++i)
            for (int j = 0; i + j < n; ++j) {
                out.push_back(at((i + 1.0 / 3.0) / n, (j + 1.0 / 3.0) / n));
                if (i + j < n - 1)
                    out.push_back(at((i + 2.0 / 3.0) / n, (j + 2.0 / 3.0) / n));
            }
    }
    SurfacePoints points;
    for (std::vector<glm::dvec3>& list : byInstance) {
        points.first.push_back(points.positions.size());
        points.positions.insert(points.positions.end(), list.begin(), list.end());
    }
    points.first.push_back(points.positions.size());
    return points;
}

/// The light's emitters that reach x within its range and cone (the receiver's own facing
/// ignored), and the far end of each one's segment.
void reachingEnds(const LightingScene& lighting, const Light& light, const std::vector<glm::dvec3>& emitters,
                  const glm::dvec3& x, std::vector<glm::dvec3>& ends)
{
    ends.clear();
    if (light.type == LightType::Directional) {
        ends.push_back(lighting.reach().end(light, x));
        return;
    }
    for (const glm::dvec3& s : emitters) {
        const glm::dvec3 to = s - x;
        const double d = glm::length(to);
        if (d > 0.0 && emitterTerm(light, s, x, to / d) > 0.0)
            ends.push_back(s);
    }
}


} // namespace

std::vector<LightSets> lightSets(const LightingScene& lighting, const Scene& scene, const std::vector<Light>& lights,
                                 const std::vector<std::uint32_t>& visible, const LightSetOptions& options)
{
    const WorldTriangles& triangles = lighting.triangles();
    const std::size_t instances = scene.instances.size();
    const SurfacePoints points = surfacePoints(triangles, instances, options.spacing);
    std::vector<std::uint32_t> V = visible;
    std::sort(V.begin(), V.end());
    V.erase(std::unique(V.begin(), V.end()), V.end());

    std::vector<LightSets> sets(lights.size());
    inArena(options.threads, [&] {
        for (std::size_t l = 0; l < lights.size(); ++l) {
            const Light& light = lights[l];
            std::vector<glm::dvec3> emitters;
            if (light.type == LightType::Area)
                for (int i = 0; i < light.area.sampleCount(); ++i)
                    emitters.push_back(light.area.sample(i));
            else
                emitters.push_back(light.position);

            // L: an instance is reached when one of its points has a free segment to the light;
            // with a PVS row for the light, only the row's instances are tried.
            std::vector<std::uint32_t> tried;
            if (l < options.restricted.size() && options.restricted[l]) {
                for (std::uint32_t i : options.candidates.at(l))
                    if (i < instances)
                        tried.push_back(i);
            } else {
                for (std::size_t i = 0; i < instances; ++i)
                    tried.push_back(std::uint32_t(i));
            }
            std::vector<char> reached(instances, 0);
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tried.size(), 1), [&](const auto& range) {
                std::vector<glm::dvec3> ends;
                std::vector<std::uint8_t> blocked;
                for (std::size_t r = range.begin(); r != range.end(); ++r)
                    for (std::size_t i = tried[r], k = points.first[i]; k < points.first[i + 1] && !reached[i]; ++k) {
                        reachingEnds(lighting, light, emitters, points.positions[k], ends);
                        blocked.resize(ends.size());
                        lighting.rays().segmentsBlocked(points.positions[k], ends, blocked.data());
                        reached[i] = std::find(blocked.begin(), blocked.end(), std::uint8_t(0)) != blocked.end();
                    }
            });
            LightSets& out = sets[l];
            out.V = V;
            for (std::size_t i = 0; i < instances; ++i)
                if (reached[i])
                    out.L.push_back(std::uint32_t(i));
            std::set_intersection(V.begin(), V.end(), out.L.begin(), out.L.end(), std::back_inserter(out.I));

            // S: every instance a segment from the light to a point of I crosses, found by walking
            // each segment's float first hits from the point towards the light.
            std::vector<char> casts(instances, 0);
            std::mutex merge;
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.I.size(), 1), [&](const auto& range) {
                std::vector<char> local(instances, 0);
                std::vector<glm::dvec3> ends;
                for (std::size_t r = range.begin(); r != range.end(); ++r) {
                    const std::uint32_t i = out.I[r];
                    for (std::size_t k = points.first[i]; k < points.first[i + 1]; ++k) {
                        const glm::dvec3& x = points.positions[k];
                        reachingEnds(lighting, light, emitters, x, ends);
                        for (const glm::dvec3& s : ends) {
                            const double length = glm::length(s - x);
                            float t = float(kEndSlackMetres / length);
                            for (int hits = 0; hits < 64; ++hits) {
                                const pvs::RayHit hit = lighting.firstHits().cast(glm::vec3(x), glm::vec3(s - x), t, 1.0f);
                                if (hit.instance < 0 || (1.0 - double(hit.t)) * length < kEndSlackMetres)
                                    break;
                                local[std::size_t(hit.instance)] = 1;
                                t = std::nextafter(hit.t, 2.0f);
                            }
                        }
                    }
                }
                std::lock_guard lock(merge);
                for (std::size_t i = 0; i < instances; ++i)
                    casts[i] = casts[i] || local[i];
            });
            for (std::size_t i = 0; i < instances; ++i)
                if (casts[i])
                    out.S.push_back(std::uint32_t(i));
        }
    });
    return sets;
}

std::optional<std::vector<std::uint32_t>> pvsReach(const std::vector<Bounds>& cells, const pvs::VisibilityRows& rows,
                                                   const std::vector<pvs::PvsObject>& objects, const Light& light)
{
    std::vector<glm::dvec3> at;
    if (light.type == LightType::Point || light.type == LightType::Spot) {
        at.push_back(light.position);
    } else if (light.type == LightType::Area) {
        for (int c = 0; c < 4; ++c)
            at.push_back(light.area.cornerPoint(c));
        for (int i = 0; i < light.area.sampleCount(); ++i)
            at.push_back(light.area.sample(i));
    }
    if (at.empty())
        return std::nullopt;
    std::vector<std::size_t> standsIn;
    for (const glm::dvec3& p : at) {
        const std::optional<std::size_t> cell = pvs::cellAt(cells, p);
        if (!cell || *cell >= rows.cellCount())
            return std::nullopt;
        standsIn.push_back(*cell);
    }
    std::sort(standsIn.begin(), standsIn.end());
    standsIn.erase(std::unique(standsIn.begin(), standsIn.end()), standsIn.end());
    std::vector<std::uint32_t> reach;
    for (std::size_t cell : standsIn) {
        const std::vector<std::uint32_t> more = pvs::instancesVisibleFrom(rows, objects, cell);
        reach.insert(reach.end(), more.begin(), more.end());
    }
    std::sort(reach.begin(), reach.end());
    reach.erase(std::unique(reach.begin(), reach.end()), reach.end());
    return reach;
}

} // namespace sightline
