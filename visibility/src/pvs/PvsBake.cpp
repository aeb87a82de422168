#include "visibility/pvs/PvsBake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "visibility/CpuBitmaskSampler.h"
#include "visibility/Error.h"
#include "visibility/Patch.h"
#include "visibility/pvs/FirstHitCaster.h"
#include "visibility/pvs/ViewCells.h"

namespace sightline::pvs {

std::uint64_t mixSeed(std::uint64_t a, std::uint64_t b)
{
    std::uint64_t z = a + 0x9e3779b97f4a7c15ull * (b + 1);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

std::uint64_t seedFromSha(const std::string& sha256Hex)
{
    std::uint64_t seed = 0;
    for (std::size_t k = 0; k < std::min<std::size_t>(16, sha256Hex.size()); ++k) {
        const char c = sha256Hex[k];
        const int digit = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : 0;
        seed = seed * 16 + std::uint64_t(digit);
    }
    return seed;
}

namespace {

/// A uniform number in [0, 1) from a counter-based stream: the same on every machine.
struct Stream {
    std::uint64_t state;
    double next()
    {
        state = mixSeed(state, 0x5851f42d4c957f2dull);
        return double(state >> 11) * (1.0 / 9007199254740992.0);
    }
};

double millisecondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// An axis-aligned rectangle: a box that is flat on `axis`.
struct Rect {
    Bounds box;
    int axis = 0;
};

/// The face of `box` on `axis`, on its max side when `positive`.
Rect face(const Bounds& box, int axis, bool positive)
{
    Rect r{box, axis};
    r.box.min[axis] = r.box.max[axis] = positive ? box.max[axis] : box.min[axis];
    return r;
}

/// The patch of a rectangle with `n` x `n` samples (DESIGN.md §2 layout).
Patch patchOf(const Rect& r, int n)
{
    const int b = (r.axis + 1) % 3, c = (r.axis + 2) % 3;
    Patch p;
    p.corner = glm::dvec3(r.box.min);
    p.u = glm::dvec3(0.0);
    p.v = glm::dvec3(0.0);
    p.u[b] = double(r.box.max[b]) - r.box.min[b];
    p.v[c] = double(r.box.max[c]) - r.box.min[c];
    p.na = p.nb = n;
    return p;
}

/// Clips `r` (not flat on `axis` ... or flat) to the side of the plane x[axis] = plane given by
/// `sign` (+1: x > plane + margin). False when nothing of positive extent is left.
bool clipToSide(Rect& r, int axis, float plane, int sign, float margin)
{
    if (r.axis == axis) {
        const float x = r.box.min[axis];
        return sign > 0 ? x > plane + margin : x < plane - margin;
    }
    if (sign > 0)
        r.box.min[axis] = std::max(r.box.min[axis], plane + margin);
    else
        r.box.max[axis] = std::min(r.box.max[axis], plane - margin);
    return r.box.max[axis] - r.box.min[axis] > margin;
}

bool overlaps(const Bounds& a, const Bounds& b)
{
    for (int k = 0; k < 3; ++k)
        if (a.max[k] < b.min[k] || b.max[k] < a.min[k])
            return false;
    return true;
}

/// Exit parameter of the ray origin + t d from `box` (t in units of d), or 0 if it misses.
float exitParameter(const Bounds& box, const glm::vec3& origin, const glm::vec3& d)
{
    float t0 = 0.0f, t1 = INFINITY;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0f) {
            if (origin[k] < box.min[k] || origin[k] > box.max[k])
                return 0.0f;
            continue;
        }
        float a = (box.min[k] - origin[k]) / d[k], b = (box.max[k] - origin[k]) / d[k];
        if (a > b)
            std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    return t1 >= t0 ? t1 : 0.0f;
}

constexpr std::size_t kSmallObjectTriangles = 64;   // nearest-point targets for objects this small

/// The point of triangle abc nearest p (Ericson, Real-Time Collision Detection §5.1.5).
glm::vec3 closestPointOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c)
{
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f)
        return a;
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3)
        return b;
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f)
        return a + (d1 / (d1 - d3)) * ab;
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6)
        return c;
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f)
        return a + (d2 / (d2 - d6)) * ac;
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
        return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    const float denom = 1.0f / (va + vb + vc);
    if (!std::isfinite(denom))
        return a;   // a degenerate triangle
    return a + ab * (vb * denom) + ac * (vc * denom);
}

constexpr float kFaceMargin = 1e-3f;   // metres: keeps clipped pairs strictly valid (DESIGN.md §2)

} // namespace

std::string PvsSettings::canonical() const
{
    std::ostringstream s;
    s << "pvs-bake-v1 coarse=" << coarseSamples << " fine=" << fineSamples << " direct=" << directCellPoints << "x"
      << directObjectPoints << " witness=" << witnessTries << " refine=" << refine << " safe=" << safe;
    return s.str();
}

void PvsSettings::validate() const
{
    auto range = [](const char* name, int value, int lo, int hi) {
        if (value < lo || value > hi)
            throw Error(std::string("pvs: ") + name + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                        "], got " + std::to_string(value));
    };
    range("coarse samples", coarseSamples, 1, 32);
    range("fine samples", fineSamples, 1, 32);
    range("direct cell points", directCellPoints, 1, 4096);
    range("direct object points", directObjectPoints, 1, 4096);
    range("witness tries", witnessTries, 1, 1024);
    if (safe && !refine)
        throw Error("pvs: safe mode works in the refine pass; it cannot go with --no-refine");
    range("threads", threads, 0, 1024);
}

std::vector<glm::vec3> boxPoints(const Bounds& box, int count, std::uint64_t seed)
{
    int k = 1;
    while (k * k * k < count)
        ++k;
    const int total = k * k * k;
    std::vector<glm::vec3> out;
    out.reserve(std::size_t(count));
    Stream random{seed};
    for (int i = 0; i < count; ++i) {
        const int cellIndex = int((std::int64_t(i) * total) / count);
        const int ix = cellIndex % k, iy = (cellIndex / k) % k, iz = cellIndex / (k * k);
        const glm::dvec3 f{(ix + random.next()) / k, (iy + random.next()) / k, (iz + random.next()) / k};
        const glm::dvec3 lo(box.min), hi(box.max);
        out.push_back(glm::vec3(lo + f * (hi - lo)));
    }
    return out;
}

std::vector<glm::vec3> surfacePoints(const std::vector<glm::vec3>& v, int count, std::uint64_t seed)
{
    std::vector<double> cumulative;
    double total = 0.0;
    for (std::size_t t = 0; t + 2 < v.size(); t += 3) {
        total += 0.5 * glm::length(glm::cross(glm::dvec3(v[t + 1] - v[t]), glm::dvec3(v[t + 2] - v[t])));
        cumulative.push_back(total);
    }
    std::vector<glm::vec3> out;
    if (!(total > 0.0))
        return out;
    Stream random{seed};
    for (int i = 0; i < count; ++i) {
        const double u = (i + random.next()) / count * total;
        const std::size_t t = std::min<std::size_t>(
            std::size_t(std::lower_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin()), cumulative.size() - 1);
        double r1 = std::sqrt(random.next()), r2 = random.next();
        const glm::dvec3 a(v[3 * t]), b(v[3 * t + 1]), c(v[3 * t + 2]);
        out.push_back(glm::vec3((1.0 - r1) * a + r1 * (1.0 - r2) * b + r1 * r2 * c));
    }
    return out;
}

PvsBaker::PvsBaker(const Scene& scene, std::vector<Bounds> cells, std::vector<PvsObject> objects, std::string sceneSha256,
                   PvsSettings settings)
    : cells_(std::move(cells)), objects_(std::move(objects)), seed_(seedFromSha(sceneSha256)), settings_(settings)
{
    settings_.validate();
    validateCells(cells_, "pvs cells");
    caster_ = std::make_unique<FirstHitCaster>(scene);
    sampler_ = std::make_unique<CpuBitmaskSampler>(scene);
    objectOfInstance_.assign(scene.instances.size(), -1);
    for (std::size_t o = 0; o < objects_.size(); ++o)
        for (std::uint32_t i : objects_[o].instances) {
            if (i >= objectOfInstance_.size())
                throw Error("pvs: object '" + objects_[o].name + "' names instance " + std::to_string(i) + ", the scene has " +
                            std::to_string(scene.instances.size()));
            objectOfInstance_[i] = std::int32_t(o);
        }
    // Per object, its world triangles; then the direct rays' targets for each pass.
    const WorldTriangles world = worldTriangles(scene);
    std::vector<std::vector<glm::vec3>> soup(objects_.size());
    for (std::size_t t = 0; t < world.size(); ++t) {
        const std::int32_t o = objectOfInstance_[world.instanceOf[t]];
        if (o >= 0)
            soup[std::size_t(o)].insert(soup[std::size_t(o)].end(), &world.vertices[3 * t], &world.vertices[3 * t] + 3);
    }
    buildObjectTree();
    const int counts[2] = {settings_.directObjectPoints, 4 * settings_.directObjectPoints};
    objectPoints_.resize(2 * objects_.size());
    smallSoups_.resize(objects_.size());
    for (std::size_t o = 0; o < objects_.size(); ++o)
        if (soup[o].size() <= 3 * kSmallObjectTriangles)
            smallSoups_[o] = soup[o];
    for (std::size_t o = 0; o < objects_.size(); ++o)
        for (int pass = 0; pass < 2; ++pass)
            objectPoints_[2 * o + std::size_t(pass)] =
                surfacePoints(soup[o], counts[pass], mixSeed(seed_ ^ 0x6f626a656374ull, o * 2 + std::size_t(pass)));
}

PvsBaker::~PvsBaker() = default;

bool PvsBaker::hitsObject(const glm::vec3& from, const glm::vec3& towards, float tfar, std::size_t object) const
{
    const RayHit hit = caster_->cast(from, towards, tfar);
    return hit.instance >= 0 && objectOfInstance_[std::size_t(hit.instance)] == std::int32_t(object);
}

bool PvsBaker::visibleByOverlap(std::size_t cell, std::size_t object) const
{
    return !objects_[object].bounds.empty() && overlaps(cells_[cell], objects_[object].bounds);
}

bool PvsBaker::visibleByDirectRays(std::size_t cell, std::size_t object, int cellPoints, int objectPointsIndex,
                                   std::uint32_t salt) const
{
    const std::vector<glm::vec3>& stratified = objectPoints_[2 * object + std::size_t(objectPointsIndex)];
    if (stratified.empty())
        return false;
    const std::vector<glm::vec3> from = boxPoints(cells_[cell], cellPoints, mixSeed(mixSeed(seed_, cell), salt));
    // Large objects (a floor, a long wall) are sampled coarsely by area: their points are mostly
    // in other rooms. The point of each of their triangles nearest the cell's centre is aimed at
    // first (objects of few triangles only).
    std::vector<glm::vec3> targets;
    const Bounds& box = cells_[cell];
    const glm::vec3 centre = 0.5f * (box.min + box.max);
    for (std::size_t t = 0; t + 2 < smallSoups_[object].size(); t += 3)
        targets.push_back(closestPointOnTriangle(centre, smallSoups_[object][t], smallSoups_[object][t + 1],
                                                 smallSoups_[object][t + 2]));
    targets.insert(targets.end(), stratified.begin(), stratified.end());
    // Targets outer, origins inner: consecutive rays spread over the object first.
    for (std::size_t q = 0; q < targets.size(); ++q)
        for (const glm::vec3& p : from)
            if (hitsObject(p, targets[q] - p, 1.0f + 1e-3f, object))
                return true;
    return false;
}

namespace {

/// A receiver grid side for a face `extent` long: `n`, or more up to 32 so that its spacing is
/// no coarser than `spacing` (node boxes are larger than cells), at most 32.
int sideFor(double extent, double spacing, int n, bool dense)
{
    if (!dense || spacing <= 0.0)
        return n;
    return std::clamp(int(std::ceil(extent / spacing)), n, 32);
}

} // namespace

std::vector<std::pair<Patch, Patch>> PvsBaker::facePairs(const Bounds& cellBox, const Bounds& targetBox, int samples,
                                                         bool denseTarget) const
{
    std::vector<std::pair<Patch, Patch>> out;
    for (int fa = 0; fa < 3; ++fa)
        for (int fs = 0; fs < 2; ++fs)
            for (int ga = 0; ga < 3; ++ga)
                for (int gs = 0; gs < 2; ++gs) {
                    const int cellSign = fs ? 1 : -1, objectSign = gs ? 1 : -1;
                    Rect cellFace = face(cellBox, fa, fs != 0);
                    Rect objectFace = face(targetBox, ga, gs != 0);
                    if (targetBox.max[(ga + 1) % 3] - targetBox.min[(ga + 1) % 3] <= kFaceMargin ||
                        targetBox.max[(ga + 2) % 3] - targetBox.min[(ga + 2) % 3] <= kFaceMargin)
                        continue;   // a degenerate face of a flat box
                    // The object's face beyond the cell face's plane, the cell face beyond the
                    // object face's plane (on its outer side).
                    if (!clipToSide(objectFace, fa, cellFace.box.min[fa], cellSign, kFaceMargin))
                        continue;
                    if (!clipToSide(cellFace, ga, objectFace.box.min[ga], objectSign, kFaceMargin))
                        continue;
                    const Patch source = patchOf(cellFace, samples);
                    Patch receiver = patchOf(objectFace, samples);
                    const double spacing = std::max(glm::length(source.u), glm::length(source.v)) / samples;
                    receiver.na = sideFor(glm::length(receiver.u), spacing, samples, denseTarget);
                    receiver.nb = sideFor(glm::length(receiver.v), spacing, samples, denseTarget);
                    out.emplace_back(source, receiver);
                }
    return out;
}

HiddenSampleMap PvsBaker::sampleShaft(const Patch& source, const Patch& receiver, PvsStats* stats) const
{
    BitmaskOptions options;
    options.threads = 1;   // cells run in parallel; one call, one thread
    // Fixed, never Auto: its timed choice could differ between runs and flip ties. The sampler's
    // exact ray-cast strategy: for grids this small the bitmask's per-call shaft set-up dominates
    // (demo coarse pass: 56 s with CpuStrategy::Bitmask, 2.3 s with RayCast, identical rows).
    options.strategy = CpuStrategy::RayCast;
    HiddenSampleMap map;
    try {
        map = sampler_->sample(source, receiver, options);
    } catch (const Error&) {
        return map;   // a sliver pair the sampler refuses: the direct rays cover it
    }
    if (stats) {
        ++stats->shaftPairs;
        stats->shaftRays += map.rayCount();
    }
    return map;
}

bool PvsBaker::boxReachable(std::size_t cell, const Bounds& box, int samples, PvsStats* stats) const
{
    if (overlaps(cells_[cell], box))
        return true;
    for (const auto& [source, receiver] : facePairs(cells_[cell], box, samples, true)) {
        const HiddenSampleMap map = sampleShaft(source, receiver, stats);
        if (map.receiverCount() && map.blockedCount() < map.rayCount())
            return true;
    }
    return false;
}

bool PvsBaker::visibleThroughShafts(std::size_t cell, std::size_t object, int samples, int witnessTries, PvsStats* stats,
                                    bool* boxSeen) const
{
    const Bounds& objectBox = objects_[object].bounds;
    if (objectBox.empty())
        return false;
    for (const auto& [source, receiver] : facePairs(cells_[cell], objectBox, samples, false)) {
        const HiddenSampleMap map = sampleShaft(source, receiver, stats);
        const std::uint64_t rays = map.rayCount();
        if (rays == 0)
            continue;
        const std::uint64_t unblocked = rays - map.blockedCount();
        if (unblocked == 0)
            continue;
        if (boxSeen)
            *boxSeen = true;
        // Continue a few unblocked rays, spread evenly over the unblocked ones.
        const std::uint64_t tries = std::min<std::uint64_t>(unblocked, std::uint64_t(witnessTries));
        std::uint64_t rank = 0, nextPick = 0, picked = 0;
        for (int j = 0; j < map.receiverCount() && picked < tries; ++j)
            for (int i = 0; i < map.sourceCount() && picked < tries; ++i) {
                if (map.blocked(j, i))
                    continue;
                if (rank++ != nextPick)
                    continue;
                ++picked;
                nextPick = (picked * unblocked) / tries;
                const glm::vec3 from(source.sample(i)), to(receiver.sample(j));
                const glm::vec3 d = to - from;
                const float tfar = exitParameter(objectBox, from, d);
                if (stats)
                    ++stats->witnessCasts;
                if (tfar > 0.0f && hitsObject(from, d, tfar * (1.0f + 1e-5f), object))
                    return true;
            }
    }
    return false;
}

void PvsBaker::bakeCell(std::size_t cell, PvsPass pass, std::vector<std::uint8_t>& row, PvsStats* stats) const
{
    const std::size_t bytes = (objects_.size() + 7) / 8;
    if (row.size() != bytes)
        row.assign(bytes, 0);
    PvsStats local;
    auto isVisible = [&](std::size_t o) { return (row[o / 8] >> (o % 8)) & 1u; };
    auto testObject = [&](std::size_t o) {
        if (isVisible(o))
            return;   // proven visible by an earlier pass
        bool visible = false;
        if (pass == PvsPass::Coarse) {
            if (visibleByOverlap(cell, o)) {
                visible = true;
                ++local.overlapPairs;
            } else if (visibleByDirectRays(cell, o, settings_.directCellPoints, 0, 1)) {
                visible = true;
                ++local.directWitnesses;
            } else if (visibleThroughShafts(cell, o, settings_.coarseSamples, settings_.witnessTries, &local, nullptr)) {
                visible = true;
                ++local.shaftWitnesses;
            }
        } else {
            if (visibleByDirectRays(cell, o, 4 * settings_.directCellPoints, 1, 2)) {
                visible = true;
                ++local.directWitnesses;
            } else {
                bool boxSeen = false;
                if (visibleThroughShafts(cell, o, settings_.fineSamples, 8 * settings_.witnessTries, &local, &boxSeen)) {
                    visible = true;
                    ++local.shaftWitnesses;
                } else if (settings_.safe && boxSeen) {
                    // Safe: an unblocked ray reached the object's bounds, and no continuation of
                    // it was seen to hit the object; kept anyway (a conservative box answer).
                    visible = true;
                    ++local.safeWitnesses;
                }
            }
        }
        if (visible)
            row[o / 8] = std::uint8_t(row[o / 8] | (1u << (o % 8)));
    };
    // Objects grouped by bounds (a BVH over their boxes): a node no unblocked shaft ray reaches
    // hides all of its objects (at this pass's sample spacing, node faces sampled as densely as
    // the cell's), so rooms behind walls cost one test instead of one per object.
    const int samples = pass == PvsPass::Coarse ? settings_.coarseSamples : settings_.fineSamples;
    std::vector<std::uint32_t> stack;
    if (!nodes_.empty())
        stack.push_back(0);
    while (!stack.empty()) {
        const ObjectNode& node = nodes_[stack.back()];
        stack.pop_back();
        if (node.object >= 0) {
            testObject(std::size_t(node.object));
            continue;
        }
        bool allKnown = true;   // every object below already proven visible: nothing to learn
        for (std::uint32_t k = node.begin; k < node.end && allKnown; ++k)
            allKnown = isVisible(treeObjects_[k]);
        if (allKnown)
            continue;
        ++local.nodeTests;
        if (!boxReachable(cell, node.bounds, samples, &local)) {
            ++local.nodesCulled;
            continue;
        }
        stack.push_back(node.second);
        stack.push_back(node.first);
    }
    if (stats) {
        stats->overlapPairs += local.overlapPairs;
        stats->directWitnesses += local.directWitnesses;
        stats->shaftWitnesses += local.shaftWitnesses;
        stats->safeWitnesses += local.safeWitnesses;
        stats->shaftPairs += local.shaftPairs;
        stats->shaftRays += local.shaftRays;
        stats->witnessCasts += local.witnessCasts;
        stats->nodeTests += local.nodeTests;
        stats->nodesCulled += local.nodesCulled;
    }
}

void PvsBaker::buildObjectTree()
{
    std::vector<std::uint32_t> ids;
    for (std::size_t o = 0; o < objects_.size(); ++o)
        if (!objects_[o].bounds.empty())
            ids.push_back(std::uint32_t(o));
    if (ids.empty())
        return;
    // Median splits on the longest axis of the centres; ties by index: deterministic.
    struct Job {
        std::uint32_t node, begin, end;
    };
    nodes_.push_back({});
    std::vector<Job> jobs{{0, 0, std::uint32_t(ids.size())}};
    while (!jobs.empty()) {
        const Job job = jobs.back();
        jobs.pop_back();
        Bounds box, centres;
        for (std::uint32_t k = job.begin; k < job.end; ++k) {
            box.extend(objects_[ids[k]].bounds);
            centres.extend(0.5f * (objects_[ids[k]].bounds.min + objects_[ids[k]].bounds.max));
        }
        nodes_[job.node].bounds = box;
        nodes_[job.node].begin = job.begin;
        nodes_[job.node].end = job.end;
        if (job.end - job.begin == 1) {
            nodes_[job.node].object = std::int32_t(ids[job.begin]);
            continue;
        }
        const glm::vec3 extent = centres.max - centres.min;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
        const std::uint32_t mid = (job.begin + job.end) / 2;
        std::nth_element(ids.begin() + job.begin, ids.begin() + mid, ids.begin() + job.end, [&](std::uint32_t a, std::uint32_t b) {
            const float ca = objects_[a].bounds.min[axis] + objects_[a].bounds.max[axis];
            const float cb = objects_[b].bounds.min[axis] + objects_[b].bounds.max[axis];
            return ca != cb ? ca < cb : a < b;
        });
        const std::uint32_t first = std::uint32_t(nodes_.size());
        nodes_.push_back({});
        nodes_.push_back({});
        nodes_[job.node].first = first;
        nodes_[job.node].second = first + 1;
        jobs.push_back({first + 1, mid, job.end});
        jobs.push_back({first, job.begin, mid});
    }
    treeObjects_ = std::move(ids);
}

VisibilityRows PvsBaker::bake(const std::vector<std::size_t>& cellIndices, const PvsProgress& progress, PvsStats* stats) const
{
    std::vector<std::size_t> todo = cellIndices;
    if (todo.empty())
        for (std::size_t c = 0; c < cells_.size(); ++c)
            todo.push_back(c);
    for (std::size_t c : todo)
        if (c >= cells_.size())
            throw Error("pvs: cell " + std::to_string(c) + " out of range (" + std::to_string(cells_.size()) + " cells)");
    std::vector<std::vector<std::uint8_t>> rows(cells_.size());
    std::mutex statsMutex;
    PvsStats total;
    const int threads = settings_.threads > 0 ? settings_.threads : tbb::this_task_arena::max_concurrency();
    tbb::task_arena arena(threads);
    auto runPass = [&](PvsPass pass) {
        const auto start = std::chrono::steady_clock::now();
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, todo.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t k = r.begin(); k != r.end(); ++k) {
                    if (progress.cancel && progress.cancel->load())
                        return;
                    PvsStats local;
                    bakeCell(todo[k], pass, rows[todo[k]], &local);
                    if (progress.onCell)
                        progress.onCell(pass, todo[k], rows[todo[k]]);
                    const std::lock_guard lock(statsMutex);
                    total.overlapPairs += local.overlapPairs;
                    total.directWitnesses += local.directWitnesses;
                    total.shaftWitnesses += local.shaftWitnesses;
                    total.safeWitnesses += local.safeWitnesses;
                    total.shaftPairs += local.shaftPairs;
                    total.shaftRays += local.shaftRays;
                    total.witnessCasts += local.witnessCasts;
                    total.nodeTests += local.nodeTests;
                    total.nodesCulled += local.nodesCulled;
                }
            });
        });
        if (progress.cancel && progress.cancel->load())
            throw PvsCancelled();
        const double ms = millisecondsSince(start);
        (pass == PvsPass::Coarse ? total.coarseMs : total.refineMs) = ms;
    };
    runPass(PvsPass::Coarse);
    if (settings_.refine)
        runPass(PvsPass::Refine);
    VisibilityRows out(cells_.size(), objects_.size());
    for (std::size_t c = 0; c < cells_.size(); ++c)
        if (!rows[c].empty())
            std::copy(rows[c].begin(), rows[c].end(), out.row(c));
    if (stats)
        *stats = total;
    return out;
}

} // namespace sightline::pvs
