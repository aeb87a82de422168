#include "lighting/DirectLight.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "TaskArena.h"
#include "lighting/LightTree.h"
#include "base/Error.h"
#include "visibility/ExactSegment.h"
#include "lights/EdgeNeighbours.h"
#include "lights/FloatShadowRays.h"
#include "lights/PointTiles.h"
#include "lights/ShaftBlocker.h"
#include "lights/TriangleBoxTree.h"
#include "visibility/ShaftGeometry.h"

namespace sightline {

namespace {

/// Entries a tile's light cut may hold (LightTree::cut stops splitting there).
constexpr std::size_t kMaxCutEntries = 512;

/// Emitters the reference, and an area light's samples the fast path, take together over a tile
/// (its matrices: a few hundred kilobytes).
constexpr std::size_t kEmitterChunk = 1024;

/// What each task of the reference reuses between tiles.
struct Scratch {
    glm::dvec3 from{0.0};                  ///< the segments' shared start, where `starts` is empty
    std::vector<glm::dvec3> starts, ends;  ///< one cast's segments
    std::vector<std::uint32_t> point;      ///< each segment's point (or emitter), in the tile
    std::vector<std::uint8_t> answer;      ///< the cast's answer
    std::vector<double> weights;           ///< [emitter][point of the tile]
    std::vector<std::uint8_t> blocked;     ///< likewise
    std::vector<std::uint32_t> later;      ///< emitters cast from the points
    std::vector<glm::dvec3> sums;          ///< per point of the tile

    void clear()
    {
        starts.clear(), ends.clear(), point.clear();
    }
};

thread_local Scratch scratch;

/// What a task reuses between tiles of the fast path.
struct TileScratch {
    std::vector<glm::dvec3> sums, starts, ends;
    std::vector<double> weights;           ///< [point k in tile][emitter i]
    std::vector<std::uint8_t> blocked;     ///< likewise
    std::vector<std::uint32_t> index;
    std::vector<std::uint8_t> answer;
    std::vector<LightTree::Entry> cut;
    std::vector<glm::dvec3> cutEmitter;
};

thread_local TileScratch tileScratch;

struct Run {
    const LightingScene& scene;
    const std::vector<Light>& lights;
    std::span<const ShadingPoint> points;
    std::vector<glm::dvec3>& sums;
    bool countAllTerms = false;
    std::atomic<std::uint64_t> terms{0}, cast{0}, unreachedTiles{0}, provenTiles{0}, litTiles{0}, castTiles{0};
    std::atomic<std::uint64_t> cutEntries{0}, cutLights{0};

    void addTerms(std::uint64_t t, std::uint64_t c)
    {
        terms += t;
        cast += c;
    }

    /// Every emitter of every light at each point, by the contract's test, or (`embreeFloat`) as
    /// Embree's float rays alone, tile by tile (the fast path's tiles of nearby points), in
    /// coherent packets as a brute force tuned for Embree casts them, and each segment from the
    /// end the fast path casts it from (so that the two exact paths judge a tie alike): a point or
    /// spot light's segments to the tile's points together from the light, a directional light's
    /// from each point, an area light's from each sample or each point as castFromSamples says.
    /// Each point sums its terms in the emitters' order.
    void reference(const std::vector<Emitter>& emitters, const std::vector<lights::PointTile>& tiles, bool embreeFloat)
    {
        std::vector<EmitterTerm> termOf;
        for (const Light& light : lights)
            termOf.emplace_back(light);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles.size(), 1), [&](const auto& range) {
            Scratch& s = scratch;
            for (std::size_t t = range.begin(); t != range.end(); ++t) {
                const lights::PointTile& tile = tiles[t];
                s.sums.assign(tile.points.size(), glm::dvec3(0.0));
                // Emitters in chunks: the tile's matrices stay small however many lights there are.
                for (std::size_t first = 0; first < emitters.size(); first += kEmitterChunk)
                    referenceChunk(tile, std::span(emitters).subspan(first, std::min(kEmitterChunk, emitters.size() - first)),
                                   termOf, embreeFloat);
                for (std::size_t k = 0; k < tile.points.size(); ++k)
                    sums[tile.points[k]] = s.sums[k];
            }
        });
    }

    /// The reference's share of one tile from `emitters`, added to the scratch's sums in their order.
    void referenceChunk(const lights::PointTile& tile, std::span<const Emitter> emitters, const std::vector<EmitterTerm>& termOf,
                        bool embreeFloat)
    {
        Scratch& s = scratch;
        const auto castAll = [&](std::uint8_t* blocked) {
            if (!s.starts.empty())
                embreeFloat ? scene.floatRays().blocked(s.starts, s.ends, blocked) : scene.rays().segmentsBlocked(s.starts, s.ends, blocked);
            else if (!s.ends.empty())
                embreeFloat ? scene.floatRays().blocked(s.from, s.ends, blocked) : scene.rays().segmentsBlocked(s.from, s.ends, blocked);
        };
        const auto endOf = [&](const Emitter& e, const glm::dvec3& x) {
            return lights[e.light].type == LightType::Directional ? scene.reach().end(lights[e.light], x) : e.position;
        };
        const std::size_t n = tile.points.size();
        s.weights.assign(emitters.size() * n, 0.0);   // [emitter e][point k]
        s.blocked.assign(emitters.size() * n, 0);
        s.later.clear();
        std::uint64_t chunkTerms = 0;
        for (std::size_t e = 0; e < emitters.size(); ++e) {
            const Emitter& emitter = emitters[e];
            const Light& light = lights[emitter.light];
            const bool directional = light.type == LightType::Directional;
            s.clear();
            s.from = emitter.position;
            for (std::size_t k = 0; k < n; ++k) {
                const ShadingPoint& p = points[tile.points[k]];
                const double w = termOf[emitter.light](emitter.position, p.position, p.normal);
                if (!(w > 0.0))
                    continue;
                s.weights[e * n + k] = w;
                if (directional)
                    s.starts.push_back(p.position);
                s.ends.push_back(directional ? endOf(emitter, p.position) : p.position);
                s.point.push_back(std::uint32_t(k));
            }
            chunkTerms += s.ends.size();
            if (light.type == LightType::Area && !castFromSamples(light, tile)) {
                if (!s.ends.empty())
                    s.later.push_back(std::uint32_t(e));
                continue;
            }
            s.answer.resize(s.ends.size());
            castAll(s.answer.data());
            for (std::size_t i = 0; i < s.ends.size(); ++i)
                s.blocked[e * n + s.point[i]] = s.answer[i];
        }
        for (std::size_t k = 0; k < n && !s.later.empty(); ++k) {
            s.clear();
            s.from = points[tile.points[k]].position;
            for (const std::uint32_t e : s.later)
                if (s.weights[e * n + k] > 0.0) {
                    s.ends.push_back(endOf(emitters[e], s.from));
                    s.point.push_back(e);
                }
            s.answer.resize(s.ends.size());
            castAll(s.answer.data());
            for (std::size_t i = 0; i < s.ends.size(); ++i)
                s.blocked[s.point[i] * n + k] = s.answer[i];
        }
        for (std::size_t k = 0; k < n; ++k)
            for (std::size_t e = 0; e < emitters.size(); ++e)
                if (s.weights[e * n + k] > 0.0 && !s.blocked[e * n + k])
                    s.sums[k] += lights[emitters[e].light].colour * s.weights[e * n + k];
        addTerms(chunkTerms, chunkTerms);
    }

    /// The fast path over one tile: light by light, a box test, then a proof or the segments.
    /// `maps[l]`: light l's hidden-samples map over the receiver grid, or null. With a light tree,
    /// the lights it holds are shaded through the tile's cut instead, after the others.
    void tile(const lights::PointTile& t, const std::vector<std::vector<glm::dvec3>>& samples,
              const std::vector<std::unique_ptr<HiddenSampleMap>>& maps, const LightTree* tree, double cutError)
    {
        TileScratch& s = tileScratch;
        const std::size_t n = t.points.size();
        s.sums.assign(n, glm::dvec3(0.0));
        for (std::size_t l = 0; l < lights.size(); ++l)
            if (!tree || !tree->clusters(l))
                shade(lights[l], samples[l], maps[l].get(), t);
        if (tree) {
            tree->cut(t.lo, t.hi, cutError, kMaxCutEntries, s.cut);
            for (const LightTree::Entry& entry : s.cut) {
                s.cutEmitter.assign(1, entry.standIn.position);
                shade(entry.standIn, s.cutEmitter, nullptr, t);
                cutEntries += entry.count > 1;
                cutLights += entry.count;
            }
        }
        for (std::size_t k = 0; k < n; ++k)
            sums[t.points[k]] = s.sums[k];
    }

    /// One light's share of the tile, added to the scratch's sums.
    void shade(const Light& light, const std::vector<glm::dvec3>& emitters, const HiddenSampleMap* map, const lights::PointTile& t)
    {
        TileScratch& s = tileScratch;
        const std::size_t n = t.points.size();
        if (unreached(light, t)) {
            ++unreachedTiles;
            return;
        }
        const std::size_t count = light.type == LightType::Directional ? 1 : emitters.size();
        const EmitterTerm term(light);
        if (!anyTerm(light, term, emitters, count, t))
            return;
        // Shadowed whole: its terms are not weighed (as many as the rays they would have cast,
        // weighing them cost about what the proof saved), unless they are to be counted.
        const bool shadowed = !map && provenShadowed(light, emitters, t);
        if (shadowed && !countAllTerms) {
            ++provenTiles;
            return;
        }
        // Lit whole: worth its cost where a pair holds many segments.
        const bool lit = !shadowed && !map && count > 1 && provenLit(light, t);
        if (shadowed)
            ++provenTiles;
        else if (lit)
            ++litTiles;
        else if (!map)
            ++castTiles;
        // The samples in chunks: the tile's matrices stay small however many samples a light has.
        for (std::size_t first = 0; first < count; first += kEmitterChunk) {
            const std::size_t chunk = std::min(kEmitterChunk, count - first);
            const std::span<const glm::dvec3> part = std::span(emitters).subspan(first, light.type == LightType::Directional ? 1 : chunk);
            terms += weigh(light, term, part, chunk, t);
            if (shadowed)
                continue;
            s.blocked.assign(n * chunk, 0);   // lit: every segment free, `blocked` stays all zero
            if (map) {
                for (std::size_t k = 0; k < n; ++k)
                    for (std::size_t i = 0; i < chunk; ++i)
                        s.blocked[k * chunk + i] = map->blocked(int(t.points[k]), int(first + i));
            } else if (!lit) {
                cast += castTile(light, part, t, chunk);
            }
            for (std::size_t k = 0; k < n; ++k)
                for (std::size_t i = 0; i < chunk; ++i)
                    if (s.weights[k * chunk + i] > 0.0 && !s.blocked[k * chunk + i])
                        s.sums[k] += light.colour * s.weights[k * chunk + i];
        }
    }

    /// The tile's terms from the light into the scratch's weights, [point k][emitter i] (0 where
    /// none); returns how many are non-zero.
    std::uint64_t weigh(const Light& light, const EmitterTerm& term, std::span<const glm::dvec3> emitters, std::size_t count,
                        const lights::PointTile& t)
    {
        TileScratch& s = tileScratch;
        s.weights.assign(t.points.size() * count, 0.0);
        std::uint64_t nonZero = 0;
        for (std::size_t k = 0; k < t.points.size(); ++k) {
            const ShadingPoint& p = points[t.points[k]];
            for (std::size_t i = 0; i < count; ++i) {
                const double w = term(light.type == LightType::Directional ? p.position : emitters[i], p.position, p.normal);
                if (w > 0.0)
                    s.weights[k * count + i] = w, ++nonZero;
            }
        }
        return nonZero;
    }

    /// Whether some point of the tile gets a non-zero term from the light (the first found ends
    /// the search, so a tile the light reaches costs about one term).
    bool anyTerm(const Light& light, const EmitterTerm& term, const std::vector<glm::dvec3>& emitters, std::size_t count,
                 const lights::PointTile& t) const
    {
        for (const std::uint32_t j : t.points) {
            const ShadingPoint& p = points[j];
            for (std::size_t i = 0; i < count; ++i)
                if (term(light.type == LightType::Directional ? p.position : emitters[i], p.position, p.normal) > 0.0)
                    return true;
        }
        return false;
    }

    TileClass classify(const Light& light, const std::vector<glm::dvec3>& emitters, const lights::PointTile& t) const
    {
        if (unreached(light, t))
            return TileClass::Unreached;
        if (provenShadowed(light, emitters, t))
            return TileClass::Shadowed;
        return provenLit(light, t) ? TileClass::Lit : TileClass::Partial;
    }

    /// Whether no point of the tile's box can get light: beyond a point or spot light's range, or
    /// behind (or in) a one-sided area light's plane.
    static bool unreached(const Light& light, const lights::PointTile& t)
    {
        if ((light.type == LightType::Point || light.type == LightType::Spot) && light.range > 0.0) {
            const glm::dvec3 nearest = glm::clamp(light.position, t.lo, t.hi);
            return glm::length(nearest - light.position) >= light.range;
        }
        if (light.type == LightType::Area && !light.twoSided) {
            const glm::dvec3 m = glm::cross(light.area.u, light.area.v);
            double most = -1.0;   // the largest m.(x - corner) over the box's corners
            for (int c = 0; c < 8; ++c)
                most = std::max(most, glm::dot(m, boxCorner(t, c) - light.area.corner));
            return most <= 0.0;
        }
        return false;
    }

    static glm::dvec3 boxCorner(const lights::PointTile& t, int c)
    {
        return {(c & 1) ? t.hi.x : t.lo.x, (c & 2) ? t.hi.y : t.lo.y, (c & 4) ? t.hi.z : t.lo.z};
    }

    /// Whether one triangle, a fused pair or a coplanar region shadows the whole tile from the
    /// light (lights/ShaftBlocker.h), trying the first triangles met from the light's centre towards
    /// the tile's centre and back.
    bool provenShadowed(const Light& light, const std::vector<glm::dvec3>& emitters, const lights::PointTile& t) const
    {
        glm::dvec3 corners[8];
        for (int c = 0; c < 8; ++c)
            corners[c] = boxCorner(t, c);
        const glm::dvec3 centre = 0.5 * (t.lo + t.hi);
        const auto vertex = [&](std::int64_t triangle, int k) {
            return glm::dvec3(scene.triangles().vertices[3 * std::size_t(triangle) + std::size_t(k)]);
        };
        if (light.type == LightType::Directional) {
            glm::dvec3 ends[8];
            for (int c = 0; c < 8; ++c)
                ends[c] = scene.reach().end(light, corners[c]);
            const glm::dvec3 far = scene.reach().end(light, centre);
            const pvs::RayHit hit = scene.firstHits().cast(glm::vec3(centre), glm::vec3(far - centre), 1.0f);
            return hit.triangle >= 0 &&
                   lights::triangleBlocksParallel(vertex(hit.triangle, 0), vertex(hit.triangle, 1), vertex(hit.triangle, 2), corners, ends);
        }
        glm::dvec3 from[4];
        std::size_t fromCount = 1;
        glm::dvec3 origin = emitters[0];
        if (light.type == LightType::Area) {
            for (int c = 0; c < 4; ++c)
                from[c] = light.area.cornerPoint(c);
            fromCount = 4;
            origin = light.area.centre();
        } else {
            from[0] = light.position;
        }
        const std::span<const glm::dvec3> fromSpan(from, fromCount), toSpan(corners, 8);
        // Candidates: the first triangles met from the light's centre towards the tile's centre,
        // and back. Rays to the tile's corners as well find few more blockers than these two and
        // cost more than they save (docs/lights.md).
        std::int64_t tried[2];
        int triedCount = 0;
        const auto attempt = [&](const glm::dvec3& rayFrom, const glm::dvec3& rayTo) {
            const std::int64_t triangle = scene.firstHits().cast(glm::vec3(rayFrom), glm::vec3(rayTo - rayFrom), 1.0f).triangle;
            if (triangle < 0 || std::find(tried, tried + triedCount, triangle) != tried + triedCount)
                return false;
            tried[triedCount++] = triangle;
            const glm::dvec3 v[3] = {vertex(triangle, 0), vertex(triangle, 1), vertex(triangle, 2)};
            if (lights::triangleBlocksShaft(v[0], v[1], v[2], fromSpan, toSpan))
                return true;
            // Fused with the triangle across an edge (a wall face's other half).
            for (int e = 0; e < 3; ++e) {
                const std::int64_t other = scene.neighbours()[std::size_t(triangle)][std::size_t(e)];
                if (other < 0)
                    continue;
                const glm::dvec3& b = v[e];
                const glm::dvec3& c = v[(e + 1) % 3];
                const glm::dvec3& a = v[(e + 2) % 3];
                glm::dvec3 d = vertex(other, 0);   // the neighbour's vertex off the shared edge
                for (int k = 1; k < 3; ++k)
                    if (d == b || d == c)
                        d = vertex(other, k);
                if (lights::quadBlocksShaft(a, b, c, d, fromSpan, toSpan))
                    return true;
            }
            // With every coplanar triangle joined to it (a wall's bands between its openings).
            return lights::coplanarRegionBlocksShaft(scene.triangles(), scene.neighbours(), triangle, fromSpan, toSpan);
        };
        return attempt(origin, centre) || attempt(centre, origin);
    }

    /// Whether no triangle enters the shaft between the light's extent and the tile's box (the
    /// hull of their corners; a directional light's segments run to beyond the scene): every
    /// segment is free (lights/TriangleBoxTree.h).
    bool provenLit(const Light& light, const lights::PointTile& t) const
    {
        // A flat or single-point tile's box gets a micrometre of thickness: the hull needs volume.
        const glm::dvec3 pad = glm::dvec3(1e-6) * glm::dvec3(glm::lessThan(t.hi - t.lo, glm::dvec3(1e-6)));
        lights::PointTile box = t;
        box.lo -= pad, box.hi += pad;
        std::vector<glm::dvec3> hullPoints;
        for (int c = 0; c < 8; ++c)
            hullPoints.push_back(boxCorner(box, c));
        if (light.type == LightType::Directional)
            for (int c = 0; c < 8; ++c)
                hullPoints.push_back(scene.reach().end(light, boxCorner(box, c)));
        else if (light.type == LightType::Area)
            for (int c = 0; c < 4; ++c)
                hullPoints.push_back(light.area.cornerPoint(c));
        else
            hullPoints.push_back(light.position);
        glm::dvec3 lo = hullPoints[0], hi = hullPoints[0];
        for (const glm::dvec3& p : hullPoints)
            lo = glm::min(lo, p), hi = glm::max(hi, p);
        const ShaftHull hull(hullPoints);
        return !scene.boxTree().anyInside(hull, lo, hi);
    }

    /// Whether an area light's segments to the tile go in packets from each sample (to a quarter
    /// of the tile's points, Morton-compact) rather than from each point (to the light's samples):
    /// where the quarter is the smaller of the two, so the packets are the narrower. Both paths
    /// cast from the same end, so that they judge a tie alike.
    static bool castFromSamples(const Light& light, const lights::PointTile& t)
    {
        const double lightSize = std::max(glm::length(light.area.u + light.area.v), glm::length(light.area.u - light.area.v));
        return 0.5 * glm::length(t.hi - t.lo) < lightSize;
    }

    /// The tile's segments with non-zero terms, cast in packets sharing the emitter's end (a
    /// directional light's from each point); fills the scratch's `blocked`. Returns the count.
    std::uint64_t castTile(const Light& light, std::span<const glm::dvec3> emitters, const lights::PointTile& t, std::size_t count)
    {
        TileScratch& s = tileScratch;
        const std::size_t n = t.points.size();
        if (light.type == LightType::Directional) {
            s.starts.clear(), s.ends.clear(), s.index.clear();
            for (std::size_t k = 0; k < n; ++k)
                if (s.weights[k] > 0.0) {
                    const glm::dvec3& x = points[t.points[k]].position;
                    s.starts.push_back(x);
                    s.ends.push_back(scene.reach().end(light, x));
                    s.index.push_back(std::uint32_t(k));
                }
            s.answer.resize(s.ends.size());
            scene.rays().segmentsBlocked(s.starts, s.ends, s.answer.data());
            for (std::size_t e = 0; e < s.ends.size(); ++e)
                s.blocked[s.index[e]] = s.answer[e];
            return s.ends.size();
        }
        if (light.type != LightType::Area) {   // a point or spot light: packets from the light to the tile's points
            s.ends.clear(), s.index.clear();
            for (std::size_t k = 0; k < n; ++k)
                if (s.weights[k] > 0.0) {
                    s.ends.push_back(points[t.points[k]].position);
                    s.index.push_back(std::uint32_t(k));
                }
            s.answer.resize(s.ends.size());
            scene.rays().segmentsBlocked(emitters[0], s.ends, s.answer.data());
            for (std::size_t e = 0; e < s.ends.size(); ++e)
                s.blocked[s.index[e]] = s.answer[e];
            return s.ends.size();
        }
        // An area light: packets towards the smaller end (narrower packets), from each sample to
        // the tile's points it lights, or from each point to the samples that light it.
        std::uint64_t total = 0;
        const bool fromSamples = castFromSamples(light, t);
        for (std::size_t a = 0; a < (fromSamples ? count : n); ++a) {
            s.ends.clear(), s.index.clear();
            for (std::size_t b = 0; b < (fromSamples ? n : count); ++b) {
                const std::size_t k = fromSamples ? b : a, i = fromSamples ? a : b;
                if (s.weights[k * count + i] > 0.0) {
                    s.ends.push_back(fromSamples ? points[t.points[k]].position : emitters[i]);
                    s.index.push_back(std::uint32_t(k * count + i));
                }
            }
            s.answer.resize(s.ends.size());
            scene.rays().segmentsBlocked(fromSamples ? emitters[a] : points[t.points[a]].position, s.ends, s.answer.data());
            for (std::size_t e = 0; e < s.ends.size(); ++e)
                s.blocked[s.index[e]] = s.answer[e];
            total += s.ends.size();
        }
        return total;
    }

    /// An area light over the receiver grid the points are (Eisemann & Décoret §8): the bitmask
    /// sampler's hidden-samples map. Null when the light and the grid do not form a valid pair,
    /// or face away from each other (the tiles then cast, or find every term zero).
    std::unique_ptr<HiddenSampleMap> areaMap(const Light& light, const Patch& grid, int threads) const
    {
        if (light.area.sampleCount() > kMaxSourceSamples || grid.na > kMaxReceiverSide || grid.nb > kMaxReceiverSide)
            return nullptr;
        try {
            validatePatchPair(light.area, grid);
        } catch (const Error&) {
            return nullptr;
        }
        // The pair is valid, so each lies wholly on one side of the other's plane: on a back side
        // every term is zero.
        const glm::dvec3 between = grid.centre() - light.area.centre();
        if ((!light.twoSided && glm::dot(light.area.normal(), between) <= 0.0) || glm::dot(grid.normal(), between) >= 0.0)
            return nullptr;
        BitmaskOptions options;
        options.threads = threads;
        return std::make_unique<HiddenSampleMap>(scene.bitmask().sample(light.area, grid, options));
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
    : scene_(scene), triangles_(worldTriangles(scene)), neighbours_(lights::edgeNeighbours(triangles_)), rays_(std::make_unique<RayCastScene>(triangles_)),
      firstHits_(std::make_unique<pvs::FirstHitCaster>(scene)),
      boxTree_(std::make_unique<lights::TriangleBoxTree>(triangles_)), reach_(scene.bounds())
{
    if (std::any_of(scene.meshes.begin(), scene.meshes.end(), [](const Mesh& mesh) { return !mesh.albedo.empty(); })) {
        // World triangles run instance by instance, each over its mesh's triangles in order.
        std::size_t first = 0;
        for (const Instance& instance : scene.instances) {
            instanceFirst_.push_back(first);
            first += scene.meshes[instance.mesh].triangleCount();
        }
    }
}

glm::dvec3 LightingScene::albedo(std::int64_t triangle, double fallback) const
{
    if (instanceFirst_.empty() || triangle < 0 || std::size_t(triangle) >= triangles_.size())
        return glm::dvec3(fallback);
    const std::uint32_t instance = triangles_.instanceOf[std::size_t(triangle)];
    const Mesh& mesh = scene_.meshes[scene_.instances[instance].mesh];
    if (mesh.albedo.empty())
        return glm::dvec3(fallback);
    const glm::vec3 own = mesh.albedo.at(std::size_t(triangle) - instanceFirst_[instance]);
    return own == kUnknownAlbedo ? glm::dvec3(fallback) : glm::dvec3(own);
}

LightingScene::~LightingScene() = default;

const CpuBitmaskSampler& LightingScene::bitmask() const
{
    std::call_once(bitmaskOnce_, [&] { bitmask_ = std::make_unique<CpuBitmaskSampler>(scene_); });
    return *bitmask_;
}

const lights::FloatShadowRays& LightingScene::floatRays() const
{
    std::call_once(floatOnce_, [&] { floatRays_ = std::make_unique<lights::FloatShadowRays>(triangles_); });
    return *floatRays_;
}

std::vector<glm::dvec3> directIrradiance(const LightingScene& scene, const std::vector<Light>& lights,
                                         std::span<const ShadingPoint> points, const DirectLightOptions& options,
                                         DirectLightStats* stats)
{
    const auto start = std::chrono::steady_clock::now();
    std::vector<glm::dvec3> sums(points.size(), glm::dvec3(0.0));
    Run run{scene, lights, points, sums, options.countAllTerms};
    std::size_t bitmaskLights = 0;
    std::uint64_t bitmaskRays = 0;
    if (options.receiverGrid && std::size_t(options.receiverGrid->sampleCount()) != points.size())
        throw Error("directIrradiance: the receiver grid's samples and the points differ in number");
    if (!(options.lightCutError >= 0.0) || !std::isfinite(options.lightCutError))
        throw Error("directIrradiance: the light cut's error must be a finite number >= 0");
    if (options.tiling && options.tiling->pointCount() != points.size())
        throw Error("directIrradiance: the tiling was built for other points");
    inArena(options.threads, [&] {
        std::vector<lights::PointTile> own;
        if (!options.tiling)
            own = lights::makePointTiles(points);
        const std::vector<lights::PointTile>& tiles = options.tiling ? options.tiling->tiles() : own;
        if (options.path != LightingPath::Fast) {
            run.reference(lightEmitters(lights), tiles, options.path == LightingPath::EmbreeFloat);
            return;
        }
        std::vector<std::unique_ptr<HiddenSampleMap>> maps(lights.size());
        std::vector<std::vector<glm::dvec3>> samples(lights.size());
        for (std::size_t l = 0; l < lights.size(); ++l) {
            const Light& light = lights[l];
            if (light.type == LightType::Area) {
                for (int i = 0; i < light.area.sampleCount(); ++i)
                    samples[l].push_back(light.area.sample(i));
                if (options.receiverGrid && options.bitmaskAreaLights)
                    maps[l] = run.areaMap(light, *options.receiverGrid, options.threads);
                if (maps[l]) {
                    ++bitmaskLights;
                    bitmaskRays += std::uint64_t(light.area.sampleCount()) * points.size();
                }
            } else {
                samples[l].push_back(light.position);
            }
        }
        std::unique_ptr<LightTree> tree;
        if (options.lightCutError > 0.0)
            tree = std::make_unique<LightTree>(lights);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles.size(), 1), [&](const auto& range) {
            for (std::size_t t = range.begin(); t != range.end(); ++t)
                run.tile(tiles[t], samples, maps, tree.get(), options.lightCutError);
        });
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
        stats->tilesUnreached = run.unreachedTiles.load();
        stats->tilesProvenShadowed = run.provenTiles.load();
        stats->tilesProvenLit = run.litTiles.load();
        stats->tilesCast = run.castTiles.load();
        stats->cutClusters = run.cutEntries.load();
        stats->cutLights = run.cutLights.load();
        stats->ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
    return sums;
}

TileClasses classifyTiles(const LightingScene& scene, const std::vector<Light>& lights, std::span<const ShadingPoint> points,
                          int threads)
{
    const auto start = std::chrono::steady_clock::now();
    std::vector<glm::dvec3> unused;
    Run run{scene, lights, points, unused};
    const std::vector<lights::PointTile> tiles = lights::makePointTiles(points);
    std::vector<std::vector<glm::dvec3>> samples(lights.size());
    for (std::size_t l = 0; l < lights.size(); ++l) {
        if (lights[l].type == LightType::Area)
            for (int i = 0; i < lights[l].area.sampleCount(); ++i)
                samples[l].push_back(lights[l].area.sample(i));
        else
            samples[l].push_back(lights[l].position);
    }
    TileClasses out;
    out.tiles = tiles.size();
    out.lights = lights.size();
    out.tileOf.assign(points.size(), 0);
    out.classes.assign(tiles.size() * lights.size(), TileClass::Partial);
    inArena(threads, [&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles.size(), 1), [&](const auto& range) {
            for (std::size_t t = range.begin(); t != range.end(); ++t) {
                for (std::uint32_t j : tiles[t].points)
                    out.tileOf[j] = std::uint32_t(t);
                for (std::size_t l = 0; l < lights.size(); ++l)
                    out.classes[t * lights.size() + l] = run.classify(lights[l], samples[l], tiles[t]);
            }
        });
    });
    out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return out;
}

PointTiling::PointTiling(std::span<const ShadingPoint> points)
    : tiles_(std::make_unique<std::vector<lights::PointTile>>(lights::makePointTiles(points))), points_(points.size())
{
}

PointTiling::~PointTiling() = default;

std::vector<ShadingPoint> patchShadingPoints(const Patch& patch)
{
    std::vector<ShadingPoint> points(std::size_t(patch.sampleCount()));
    const glm::dvec3 normal = patch.normal();
    for (int j = 0; j < patch.sampleCount(); ++j)
        points[std::size_t(j)] = {patch.sample(j), normal};
    return points;
}

} // namespace sightline
