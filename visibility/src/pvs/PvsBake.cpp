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

#include "base/Error.h"
#include "visibility/pvs/FirstHitCaster.h"
#include "visibility/pvs/OpenSpace.h"
#include "visibility/pvs/ShaftProof.h"
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

/// The distance between two boxes (0 when they meet).
double boxDistance(const Bounds& a, const Bounds& b)
{
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double gap = std::max({0.0, double(a.min[k]) - double(b.max[k]), double(b.min[k]) - double(a.max[k])});
        d2 += gap * gap;
    }
    return std::sqrt(d2);
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

} // namespace

void PvsStats::add(const PvsStats& o)
{
    overlapPairs += o.overlapPairs;
    directWitnesses += o.directWitnesses;
    shaftWitnesses += o.shaftWitnesses;
    provenHidden += o.provenHidden;
    spaceHidden += o.spaceHidden;
    unknownPairs += o.unknownPairs;
    safeKept += o.safeKept;
    distanceCulled += o.distanceCulled;
    nodeTests += o.nodeTests;
    nodesCulled += o.nodesCulled;
    directCasts += o.directCasts;
    search.add(o.search);
}

std::string PvsSettings::canonical() const
{
    std::ostringstream s;
    s.precision(17);
    s << "pvs-bake-v3 coarse_shafts=" << coarseShafts << " fine_shafts=" << fineShafts << " smallest_gap=" << smallestGap
      << " coarse_gap=" << kCoarseGap << " blocks=" << kBlockCells << "x" << kBlockShafts << " residue_rays=" << residueRays << " direct=" << directCellPoints << "x"
      << directObjectPoints << " max_distance=" << maxDistance << " cell_rows=" << cellRows << " refine=" << refine
      << " safe=" << safe << " open_space=" << openSpace;
    return s.str();
}

void PvsSettings::validate() const
{
    auto range = [](const char* name, double value, double lo, double hi) {
        if (!(value >= lo && value <= hi)) {
            std::ostringstream m;
            m << "pvs: " << name << " must be in [" << lo << ", " << hi << "], got " << value;
            throw Error(m.str());
        }
    };
    range("coarse shafts", coarseShafts, 1, kMaxCoarseShafts);
    range("fine shafts", fineShafts, 1, kMaxFineShafts);
    range("smallest gap", smallestGap, 1e-4, 100.0);
    range("residue rays", residueRays, 0, kMaxResidueRays);
    range("direct cell points", directCellPoints, 1, 4096);
    range("direct object points", directObjectPoints, 1, 4096);
    range("max distance", maxDistance, 0.0, 1e7);
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
    prover_ = std::make_unique<ShaftProver>(scene);
    objectOfInstance_.assign(scene.instances.size(), -1);
    for (std::size_t o = 0; o < objects_.size(); ++o)
        for (std::uint32_t i : objects_[o].instances) {
            if (i >= objectOfInstance_.size())
                throw Error("pvs: object '" + objects_[o].name + "' names instance " + std::to_string(i) + ", the scene has " +
                            std::to_string(scene.instances.size()));
            objectOfInstance_[i] = std::int32_t(o);
        }
    search_ = std::make_unique<ShaftSearch>(*caster_, *prover_, objectOfInstance_);
    // Per object, its world triangles; then the direct rays' targets.
    const WorldTriangles world = worldTriangles(scene);
    std::vector<std::vector<glm::vec3>> soup(objects_.size());
    for (std::size_t t = 0; t < world.size(); ++t) {
        const std::int32_t o = objectOfInstance_[world.instanceOf[t]];
        if (o >= 0)
            soup[std::size_t(o)].insert(soup[std::size_t(o)].end(), &world.vertices[3 * t], &world.vertices[3 * t] + 3);
    }
    std::vector<Bounds> boxes;
    for (const PvsObject& o : objects_)
        boxes.push_back(o.bounds);
    objectTree_ = buildTree(boxes);
    cellTree_ = buildTree(cells_);
    // Blocks: the cell tree's first nodes of at most kBlockCells cells (neighbours, by the median
    // splits), which partition the cells.
    blockOf_.assign(cells_.size(), 0);
    std::vector<std::uint32_t> stack;
    if (!cellTree_.nodes.empty())
        stack.push_back(0);
    while (!stack.empty()) {
        const Node& node = cellTree_.nodes[stack.back()];
        stack.pop_back();
        if (node.end - node.begin > kBlockCells) {
            stack.push_back(node.second);
            stack.push_back(node.first);
            continue;
        }
        Block block;
        block.bounds = node.bounds;
        for (std::uint32_t k = node.begin; k < node.end; ++k) {
            block.cells.push_back(cellTree_.order[k]);
            blockOf_[cellTree_.order[k]] = blocks_.size();
        }
        std::sort(block.cells.begin(), block.cells.end());
        blocks_.push_back(std::move(block));
    }
    std::vector<Bounds> sources = cells_;
    for (const Block& block : blocks_)
        sources.push_back(block.bounds);
    if (settings_.openSpace)
        openSpace_ = std::make_unique<OpenSpace>(*prover_, scene.bounds(), soup, sources, OpenSpaceLimits{.threads = settings_.threads});
    objectPoints_.resize(objects_.size());
    smallSoups_.resize(objects_.size());
    for (std::size_t o = 0; o < objects_.size(); ++o) {
        if (soup[o].size() <= 3 * kSmallObjectTriangles)
            smallSoups_[o] = soup[o];
        objectPoints_[o] = surfacePoints(soup[o], settings_.directObjectPoints, mixSeed(seed_ ^ 0x6f626a656374ull, o * 2));
    }
}

PvsBaker::~PvsBaker() = default;

const OpenSpaceStats& PvsBaker::openSpaceStats() const
{
    static const OpenSpaceStats none;
    return openSpace_ ? openSpace_->stats() : none;
}

void PvsBaker::hideByOpenSpace(const Bounds& box, std::vector<std::uint8_t>& hidden, PvsStats& stats) const
{
    if (!openSpace_)
        return;
    const std::vector<std::uint8_t> proven = openSpace_->hiddenFrom(box);
    for (std::size_t o = 0; o < objects_.size(); ++o)
        if (((proven[o / 8] >> (o % 8)) & 1u) && !((hidden[o / 8] >> (o % 8)) & 1u) && !objects_[o].bounds.empty() &&
            !boxesMeet(box, objects_[o].bounds)) {
            hidden[o / 8] = std::uint8_t(hidden[o / 8] | (1u << (o % 8)));
            ++stats.spaceHidden;
            ++stats.provenHidden;
        }
}

std::uint64_t PvsBaker::cellSeed(std::size_t cell) const { return mixSeed(seed_, cell); }

bool PvsBaker::hitsObject(const glm::vec3& from, const glm::vec3& towards, float tfar, std::size_t object) const
{
    const RayHit hit = caster_->cast(from, towards, tfar);
    return hit.instance >= 0 && objectOfInstance_[std::size_t(hit.instance)] == std::int32_t(object);
}

bool PvsBaker::visibleByDirectRays(std::size_t cell, std::size_t object, PvsStats& stats) const
{
    const std::vector<glm::vec3>& stratified = objectPoints_[object];
    if (stratified.empty())
        return false;
    const std::vector<glm::vec3> from = boxPoints(cells_[cell], settings_.directCellPoints, mixSeed(cellSeed(cell), 1));
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
        for (const glm::vec3& p : from) {
            ++stats.directCasts;
            if (hitsObject(p, targets[q] - p, 1.0f + 1e-3f, object))
                return true;
        }
    return false;
}

namespace {

bool bit(const std::vector<std::uint8_t>& v, std::size_t o) { return (v[o / 8] >> (o % 8)) & 1u; }
void setBit(std::vector<std::uint8_t>& v, std::size_t o, bool value)
{
    v[o / 8] = std::uint8_t(value ? v[o / 8] | (1u << (o % 8)) : v[o / 8] & ~(1u << (o % 8)));
}

} // namespace

void PvsBaker::traverse(const Bounds& from, const std::function<bool(std::size_t)>& pending, const SearchLimits& limits,
                        std::uint64_t seed, const std::function<void(std::size_t)>& testObject,
                        const std::function<void(std::size_t)>& hide, PvsStats& stats) const
{
    // Groups: a node proven hidden hides all its objects at once; a node no object of which is
    // still to decide is skipped.
    const Tree& tree = objectTree_;
    std::vector<std::uint32_t> stack;
    if (!tree.nodes.empty())
        stack.push_back(0);
    while (!stack.empty()) {
        const std::uint32_t nodeIndex = stack.back();
        const Node& node = tree.nodes[nodeIndex];
        stack.pop_back();
        if (node.item >= 0) {
            if (pending(std::size_t(node.item)))
                testObject(std::size_t(node.item));
            continue;
        }
        bool any = false;
        for (std::uint32_t k = node.begin; k < node.end && !any; ++k)
            any = pending(tree.order[k]);
        if (!any)
            continue;
        if (settings_.maxDistance > 0.0 && boxDistance(from, node.bounds) > settings_.maxDistance) {
            for (std::uint32_t k = node.begin; k < node.end; ++k)
                if (pending(tree.order[k])) {
                    hide(tree.order[k]);
                    ++stats.distanceCulled;
                }
            continue;
        }
        if (!boxesMeet(from, node.bounds)) {
            ++stats.nodeTests;
            SearchTarget target;
            target.box = node.bounds;
            target.own = [&](std::uint32_t instance) {
                const std::int32_t o = objectOfInstance_[instance];
                if (o < 0)
                    return false;
                const std::uint32_t at = tree.position[std::size_t(o)];
                return at >= node.begin && at < node.end;
            };
            if (search_->search(from, target, limits, mixSeed(seed, objects_.size() + nodeIndex), &stats.search) == Reach::Hidden) {
                ++stats.nodesCulled;
                for (std::uint32_t k = node.begin; k < node.end; ++k)
                    if (pending(tree.order[k])) {
                        hide(tree.order[k]);
                        ++stats.provenHidden;
                    }
                continue;
            }
        }
        stack.push_back(node.second);
        stack.push_back(node.first);
    }
}

std::vector<std::uint8_t> PvsBaker::bakeBlock(std::size_t block, PvsStats& stats) const
{
    // The coarse pass: what no point of the block's box can see (proven), with the coarse budget
    // and no witnesses sought beyond the search's own. Valid for every cell of the block.
    const Bounds& box = blocks_[block].bounds;
    std::vector<std::uint8_t> hidden((objects_.size() + 7) / 8, 0);
    hideByOpenSpace(box, hidden, stats);
    SearchLimits limits;
    limits.maxShafts = kBlockShafts * settings_.coarseShafts;
    limits.smallestGap = std::max(kCoarseGap, settings_.smallestGap);
    const std::uint64_t seed = mixSeed(seed_ ^ 0x626c6f636bull, block);
    const auto pending = [&](std::size_t o) { return !bit(hidden, o); };
    const auto hide = [&](std::size_t o) { setBit(hidden, o, true); };
    const auto testObject = [&](std::size_t o) {
        const PvsObject& object = objects_[o];
        if (object.bounds.empty()) {
            hide(o);
            return;
        }
        if (settings_.maxDistance > 0.0 && boxDistance(box, object.bounds) > settings_.maxDistance) {
            ++stats.distanceCulled;
            hide(o);
            return;
        }
        if (boxesMeet(box, object.bounds))
            return;
        SearchTarget target;
        target.box = object.bounds;
        target.object = std::int32_t(o);
        target.own = [&](std::uint32_t instance) { return objectOfInstance_[instance] == std::int32_t(o); };
        if (search_->search(box, target, limits, mixSeed(seed, o), &stats.search) == Reach::Hidden) {
            ++stats.provenHidden;
            hide(o);
        }
    };
    traverse(box, pending, limits, seed, testObject, hide, stats);
    return hidden;
}

std::vector<std::uint8_t> PvsBaker::bakeCell(std::size_t cell, const std::vector<std::uint8_t>& blockHidden, PvsStats& stats) const
{
    // The refine pass for one cell: what its block did not prove hidden, first with the coarse
    // budget and the direct rays, then what is still Unknown with the fine budget and, in the
    // default mode, the residue rays.
    const Bounds& cellBox = cells_[cell];
    const std::size_t bytes = (objects_.size() + 7) / 8;
    std::vector<std::uint8_t> row(bytes, 0), decided = blockHidden;
    hideByOpenSpace(cellBox, decided, stats);
    const std::uint64_t seed = cellSeed(cell);
    SearchLimits coarse;
    coarse.maxShafts = settings_.coarseShafts;
    coarse.smallestGap = std::max(kCoarseGap, settings_.smallestGap);
    SearchLimits fine;
    fine.maxShafts = settings_.fineShafts;
    fine.smallestGap = settings_.smallestGap;
    fine.residueRays = settings_.safe ? 0 : settings_.residueRays;
    std::vector<std::size_t> unknown;
    const auto pending = [&](std::size_t o) { return !bit(decided, o); };
    const auto hide = [&](std::size_t o) { setBit(decided, o, true); };
    const auto show = [&](std::size_t o) {
        setBit(decided, o, true);
        setBit(row, o, true);
    };
    const auto testObject = [&](std::size_t o) {
        const PvsObject& object = objects_[o];
        if (object.bounds.empty()) {
            hide(o);
            return;
        }
        if (settings_.maxDistance > 0.0 && boxDistance(cellBox, object.bounds) > settings_.maxDistance) {
            ++stats.distanceCulled;
            hide(o);
            return;
        }
        if (boxesMeet(cellBox, object.bounds)) {
            ++stats.overlapPairs;
            show(o);
            return;
        }
        SearchTarget target;
        target.box = object.bounds;
        target.object = std::int32_t(o);
        target.own = [&](std::uint32_t instance) { return objectOfInstance_[instance] == std::int32_t(o); };
        const Reach reach = search_->search(cellBox, target, coarse, mixSeed(seed, 2 * o), &stats.search);
        if (reach == Reach::Visible) {
            ++stats.shaftWitnesses;
            show(o);
        } else if (reach == Reach::Hidden) {
            ++stats.provenHidden;
            hide(o);
        } else if (visibleByDirectRays(cell, o, stats)) {
            ++stats.directWitnesses;
            show(o);
        } else {
            hide(o);
            unknown.push_back(o);   // for the fine budget
        }
    };
    traverse(cellBox, pending, coarse, mixSeed(seed, 0x6e6f6465ull), testObject, hide, stats);
    for (std::size_t o : unknown) {
        SearchTarget target;
        target.box = objects_[o].bounds;
        target.object = std::int32_t(o);
        target.own = [&](std::uint32_t instance) { return objectOfInstance_[instance] == std::int32_t(o); };
        const Reach reach = search_->search(cellBox, target, fine, mixSeed(seed, 2 * o + 1), &stats.search);
        if (reach == Reach::Visible) {
            ++stats.shaftWitnesses;
            setBit(row, o, true);
        } else if (reach == Reach::Hidden) {
            ++stats.provenHidden;
        } else {
            ++stats.unknownPairs;
            if (settings_.safe) {
                ++stats.safeKept;
                setBit(row, o, true);
            }
            // Default: the residue rays found no witness; culled.
        }
    }
    return row;
}

PvsBaker::Tree PvsBaker::buildTree(const std::vector<Bounds>& boxes)
{
    Tree tree;
    std::vector<std::uint32_t> ids;
    for (std::size_t o = 0; o < boxes.size(); ++o)
        if (!boxes[o].empty())
            ids.push_back(std::uint32_t(o));
    tree.position.assign(boxes.size(), std::uint32_t(-1));
    if (ids.empty())
        return tree;
    // Median splits on the longest axis of the centres; ties by index: deterministic.
    struct Job {
        std::uint32_t node, begin, end;
    };
    tree.nodes.push_back({});
    std::vector<Job> jobs{{0, 0, std::uint32_t(ids.size())}};
    while (!jobs.empty()) {
        const Job job = jobs.back();
        jobs.pop_back();
        Bounds box, centres;
        for (std::uint32_t k = job.begin; k < job.end; ++k) {
            box.extend(boxes[ids[k]]);
            centres.extend(0.5f * (boxes[ids[k]].min + boxes[ids[k]].max));
        }
        tree.nodes[job.node].bounds = box;
        tree.nodes[job.node].begin = job.begin;
        tree.nodes[job.node].end = job.end;
        if (job.end - job.begin == 1) {
            tree.nodes[job.node].item = std::int32_t(ids[job.begin]);
            continue;
        }
        const glm::vec3 extent = centres.max - centres.min;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
        const std::uint32_t mid = (job.begin + job.end) / 2;
        std::nth_element(ids.begin() + job.begin, ids.begin() + mid, ids.begin() + job.end, [&](std::uint32_t a, std::uint32_t b) {
            const float ca = boxes[a].min[axis] + boxes[a].max[axis];
            const float cb = boxes[b].min[axis] + boxes[b].max[axis];
            return ca != cb ? ca < cb : a < b;
        });
        const std::uint32_t first = std::uint32_t(tree.nodes.size());
        tree.nodes.push_back({});
        tree.nodes.push_back({});
        tree.nodes[job.node].first = first;
        tree.nodes[job.node].second = first + 1;
        jobs.push_back({first + 1, mid, job.end});
        jobs.push_back({first, job.begin, mid});
    }
    for (std::size_t k = 0; k < ids.size(); ++k)
        tree.position[ids[k]] = std::uint32_t(k);
    tree.order = std::move(ids);
    return tree;
}

namespace {

/// Runs `work(k)` for k in [0, count) on `threads` threads, checking `cancel` between items.
template <class Work>
void forEachCell(int threads, std::size_t count, const std::atomic<bool>* cancel, Work&& work)
{
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t k = r.begin(); k != r.end(); ++k) {
                if (cancel && cancel->load())
                    return;
                work(k);
            }
        });
    });
    if (cancel && cancel->load())
        throw PvsCancelled();
}

std::vector<std::size_t> cellList(const std::vector<std::size_t>& cellIndices, std::size_t cellCount)
{
    std::vector<std::size_t> todo = cellIndices;
    if (todo.empty())
        for (std::size_t c = 0; c < cellCount; ++c)
            todo.push_back(c);
    for (std::size_t c : todo)
        if (c >= cellCount)
            throw Error("pvs: cell " + std::to_string(c) + " out of range (" + std::to_string(cellCount) + " cells)");
    return todo;
}

} // namespace

VisibilityRows PvsBaker::bake(const std::vector<std::size_t>& cellIndices, const PvsProgress& progress, PvsStats* stats) const
{
    const std::vector<std::size_t> todo = cellList(cellIndices, cells_.size());
    std::mutex statsMutex;
    PvsStats total;
    const int threads = settings_.threads > 0 ? settings_.threads : tbb::this_task_arena::max_concurrency();
    // The blocks these cells belong to, in order.
    std::vector<std::size_t> blocks;
    for (std::size_t c : todo)
        blocks.push_back(blockOf_[c]);
    std::sort(blocks.begin(), blocks.end());
    blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    std::vector<std::vector<std::uint8_t>> hidden(blocks_.size());
    std::vector<std::uint8_t> listed(cells_.size(), 0);
    for (std::size_t c : todo)
        listed[c] = 1;
    auto start = std::chrono::steady_clock::now();
    forEachCell(threads, blocks.size(), progress.cancel, [&](std::size_t k) {
        PvsStats local;
        const std::size_t b = blocks[k];
        hidden[b] = bakeBlock(b, local);
        if (progress.onCell) {
            // The coarse answer of each of its cells: all that the block did not prove hidden.
            std::vector<std::uint8_t> row(hidden[b].size());
            for (std::size_t i = 0; i < row.size(); ++i)
                row[i] = std::uint8_t(~hidden[b][i]);
            if (objects_.size() % 8)
                row.back() = std::uint8_t(row.back() & ((1u << (objects_.size() % 8)) - 1));
            for (std::size_t c : blocks_[b].cells)
                if (listed[c])
                    progress.onCell(PvsPass::Coarse, c, row);
        }
        const std::lock_guard lock(statsMutex);
        total.add(local);
    });
    total.coarseMs = millisecondsSince(start);
    VisibilityRows out(cells_.size(), objects_.size());
    if (!settings_.refine) {
        for (std::size_t c : todo)
            for (std::size_t o = 0; o < objects_.size(); ++o)
                out.set(c, o, !bit(hidden[blockOf_[c]], o));
    } else {
        start = std::chrono::steady_clock::now();
        forEachCell(threads, todo.size(), progress.cancel, [&](std::size_t k) {
            PvsStats local;
            const std::size_t c = todo[k];
            const std::vector<std::uint8_t> row = bakeCell(c, hidden[blockOf_[c]], local);
            std::copy(row.begin(), row.end(), out.row(c));
            if (progress.onCell)
                progress.onCell(PvsPass::Refine, c, row);
            const std::lock_guard lock(statsMutex);
            total.add(local);
        });
        total.refineMs = millisecondsSince(start);
    }
    if (stats) {
        const double cellRowsMs = stats->cellRowsMs;
        *stats = total;
        stats->cellRowsMs = cellRowsMs;
    }
    return out;
}

VisibilityRows PvsBaker::bakeCellRows(const std::vector<std::size_t>& cellIndices, const PvsProgress& progress, PvsStats* stats) const
{
    const std::vector<std::size_t> todo = cellList(cellIndices, cells_.size());
    VisibilityRows out(cells_.size(), cells_.size());
    std::mutex statsMutex;
    PvsStats total;
    const int threads = settings_.threads > 0 ? settings_.threads : tbb::this_task_arena::max_concurrency();
    const auto start = std::chrono::steady_clock::now();
    forEachCell(threads, todo.size(), progress.cancel, [&](std::size_t k) {
        const std::size_t cell = todo[k];
        const Bounds& cellBox = cells_[cell];
        PvsStats local;
        std::vector<std::uint8_t> row(out.rowBytes(), 0);
        auto set = [&](std::size_t d) { row[d / 8] = std::uint8_t(row[d / 8] | (1u << (d % 8))); };
        const std::uint64_t seed = mixSeed(cellSeed(cell), 0x63656c6cull);
        const std::vector<char> reachable = openSpace_ ? openSpace_->reachableFrom(cellBox) : std::vector<char>{};
        const auto spaceHides = [&](const Bounds& box) {
            if (!openSpace_ || boxesMeet(cellBox, box) || !openSpace_->hides(reachable, box))
                return false;
            ++local.spaceHidden;
            return true;
        };
        auto searchBox = [&](const Bounds& box, std::uint64_t id, bool lastPass) {
            SearchTarget target;
            target.box = box;
            SearchLimits limits;
            limits.maxShafts = lastPass ? settings_.fineShafts : settings_.coarseShafts;
            limits.smallestGap = lastPass ? settings_.smallestGap : std::max(kCoarseGap, settings_.smallestGap);
            if (lastPass && !settings_.safe)
                limits.residueRays = settings_.residueRays;
            return search_->search(cellBox, target, limits, mixSeed(seed, id), &local.search);
        };
        // Coarse budget first, then the fine one for what is left: the same answers as a
        // two-pass bake, in one visit.
        auto decideBox = [&](const Bounds& box, std::uint64_t id) {
            Reach reach = searchBox(box, 2 * id, false);
            if (reach == Reach::Unknown && settings_.refine)
                reach = searchBox(box, 2 * id + 1, true);
            if (reach == Reach::Unknown) {
                ++local.unknownPairs;
                return settings_.safe || !settings_.refine;
            }
            return reach == Reach::Visible;
        };
        const Tree& tree = cellTree_;
        std::vector<std::uint32_t> stack{0};
        while (!stack.empty() && !tree.nodes.empty()) {
            const std::uint32_t nodeIndex = stack.back();
            const Node& node = tree.nodes[nodeIndex];
            stack.pop_back();
            if (settings_.maxDistance > 0.0 && boxDistance(cellBox, node.bounds) > settings_.maxDistance)
                continue;
            if (node.item >= 0) {
                const std::size_t d = std::size_t(node.item);
                if (boxesMeet(cellBox, cells_[d]) || (!spaceHides(cells_[d]) && decideBox(cells_[d], d)))
                    set(d);
                continue;
            }
            if (spaceHides(node.bounds))
                continue;
            if (!boxesMeet(cellBox, node.bounds)) {
                ++local.nodeTests;
                if (searchBox(node.bounds, 2 * (cells_.size() + nodeIndex), false) == Reach::Hidden ||
                    (settings_.refine && searchBox(node.bounds, 2 * (cells_.size() + nodeIndex) + 1, true) == Reach::Hidden)) {
                    ++local.nodesCulled;
                    continue;
                }
            }
            stack.push_back(node.second);
            stack.push_back(node.first);
        }
        std::copy(row.begin(), row.end(), out.row(cell));
        if (progress.onCell)
            progress.onCell(PvsPass::Refine, cell, row);
        const std::lock_guard lock(statsMutex);
        total.add(local);
    });
    total.cellRowsMs = millisecondsSince(start);
    if (stats) {
        stats->cellRowsMs = total.cellRowsMs;
        stats->search.add(total.search);
        stats->nodeTests += total.nodeTests;
        stats->nodesCulled += total.nodesCulled;
        stats->spaceHidden += total.spaceHidden;
    }
    return out;
}

} // namespace sightline::pvs
