#include "visibility/CpuBitmaskSampler.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <ctime>
#include <limits>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <tbb/task_arena.h>

#include "BitmaskRows.h"
#include "bitmask/InnerProxy.h"
#include "bitmask/Occluders.h"
#include "bitmask/Shaft.h"
#include "bitmask/Strategy.h"
#include "bitmask/TilePass.h"
#include "raycast/ProvenRayCaster.h"
#include "visibility/RayCastSampler.h"
#include "visibility/ShaftGeometry.h"

// The sampler's parts, one concept each, in visibility/src/bitmask/: the shaft (Shaft.h),
// occluder preparation (Occluders.h), the double-precision path (DoubleBackprojection.h) and table mode
// (TableMode.h), the narrowed shaft (Narrowing.h), the tile pass (TilePass.h), meshes' inner
// proxies (InnerProxy.h) and Auto's choice (Strategy.h); the float kernel in
// BitmaskRows.h. This file runs one call through them.

namespace sightline {

using namespace bitmask;

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

/// This thread's processor time, in milliseconds.
double threadMs()
{
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return double(now.tv_sec) * 1e3 + double(now.tv_nsec) * 1e-6;
}

/// Below this many small triangles in the shaft, Auto keeps to the plain bitmask (a BVH build and
/// a ray pass cost more than they save).
constexpr std::size_t kHybridMinSmallTriangles = 500;

/// Voxels along a proxied mesh's longest side (InnerProxy.h). On dense-mesh-2, -4 and -6 at 1024
/// x 32², 24 or 32 left 8-18% fewer rays to cast than 16, for two to four times the proxies'
/// pass, and were no faster overall; 12 left 17% more (dense-mesh-2, 128 x 32²). README,
/// docs/benchmarks.md.
constexpr int kProxyResolution = 16;

} // namespace

/// Buffers kept between calls: the editor samples many times a second, and fresh multi-megabyte
/// allocations cost page faults every time.
struct CpuBitmaskSampler::Workspace {
    OccluderSet occluders;
    std::vector<char> small;   // per occluder: left to the hybrid's ray pass
    TileBins bins;
};

/// Auto's last measured choice (Strategy.h).
struct CpuBitmaskSampler::StrategyChoiceCache {
    ProbeMemo memo;
};

CpuBitmaskSampler::CpuBitmaskSampler(const Scene& scene) : triangles_(worldTriangles(scene))
{
    validateCoordinates(triangles_, "scene");
    describeInstances(scene);
}

void CpuBitmaskSampler::describeInstances(const Scene& scene)
{
    instances_.clear();
    for (const Instance& instance : scene.instances) {
        InstanceInfo info;
        info.watertight = scene.meshes[instance.mesh].watertight;
        info.bounds = scene.instanceBounds(instance);
        instances_.push_back(info);
    }
    // worldTriangles writes each instance's triangles together, in instance order.
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
        InstanceInfo& info = instances_[triangles_.instanceOf[t]];
        if (info.count == 0)
            info.first = t;
        ++info.count;
        for (int k = 0; k < 3; ++k)
            info.triangleBounds.extend(triangles_.vertices[3 * t + std::size_t(k)]);
    }
}

CpuBitmaskSampler::CpuBitmaskSampler(WorldTriangles triangles) : triangles_(std::move(triangles))
{
    validateCoordinates(triangles_, "scene");
}

CpuBitmaskSampler::~CpuBitmaskSampler() = default;

void CpuBitmaskSampler::setScene(const Scene& scene)
{
    WorldTriangles triangles = worldTriangles(scene);
    validateCoordinates(triangles, "scene");
    triangles_ = std::move(triangles);
    describeInstances(scene);
    {
        std::lock_guard lock(rayCasterMutex_);
        rayCaster_.reset();   // built again, for the new triangles, when RayCast is next chosen
        provenCaster_.reset();
    }
    {
        // Proxies stay at hand for instances that come back unchanged (the editor moved another
        // object): a dense statue's costs several small calls to build. Each holds a copy of its
        // mesh, so those kept hold at most as many triangles as the new scene has.
        std::lock_guard lock(proxyMutex_);
        for (std::shared_ptr<const InnerProxy>& proxy : proxies_)
            if (proxy)
                earlierProxies_.insert(earlierProxies_.begin(), std::move(proxy));
        std::size_t kept = 0, vertices = 0;
        while (kept < earlierProxies_.size() && vertices + earlierProxies_[kept]->builtFrom.size() <= triangles_.vertices.size())
            vertices += earlierProxies_[kept++]->builtFrom.size();
        earlierProxies_.resize(kept);
        proxies_.assign(instances_.size(), nullptr);
    }
    std::lock_guard lock(probeMutex_);
    probeMemo_.reset();
    sampledGrids_.clear();   // the float BVH is new: its first rays pay first-touch faults again
}

std::vector<char> CpuBitmaskSampler::cullableInstances(const Patch& receiver, const Bounds* displacedBox) const
{
    std::vector<char> cullable(instances_.size(), 0);
    for (std::size_t i = 0; i < instances_.size(); ++i) {
        if (!instances_[i].watertight)
            continue;
        if (!displacedBox) {
            cullable[i] = receiverApartFrom(instances_[i].bounds, receiver);
            continue;
        }
        // A bumpy receiver: no displaced sample may lie inside the mesh. receiverApartFrom's
        // test, on the box of the displaced samples.
        const Bounds& r = *displacedBox;
        const Bounds& b = instances_[i].bounds;
        const float pad = 1e-4f * (1.0f + glm::length(r.max - r.min));
        cullable[i] = glm::any(glm::lessThan(b.max + pad, r.min)) || glm::any(glm::greaterThan(b.min - pad, r.max));
    }
    return cullable;
}

bool CpuBitmaskSampler::simdAvailable() { return detail::floatRowsAvailable(); }

std::unique_ptr<CpuBitmaskSampler::Workspace> CpuBitmaskSampler::takeWorkspace() const
{
    std::lock_guard lock(workspaceMutex_);
    if (idleWorkspaces_.empty())
        return std::make_unique<Workspace>();
    std::unique_ptr<Workspace> work = std::move(idleWorkspaces_.back());
    idleWorkspaces_.pop_back();
    return work;
}

void CpuBitmaskSampler::returnWorkspace(std::unique_ptr<Workspace> work) const
{
    constexpr std::size_t kMaxIdle = 4;   // callers sampling concurrently
    std::lock_guard lock(workspaceMutex_);
    if (idleWorkspaces_.size() < kMaxIdle)
        idleWorkspaces_.push_back(std::move(work));
}

std::shared_ptr<const RayCastScene> CpuBitmaskSampler::wholeSceneCaster() const
{
    std::lock_guard lock(rayCasterMutex_);
    if (!rayCaster_)
        rayCaster_ = std::make_shared<const RayCastScene>(triangles_);
    return rayCaster_;
}

std::shared_ptr<const raycast::ProvenRayCaster> CpuBitmaskSampler::provenCaster() const
{
    std::lock_guard lock(rayCasterMutex_);
    if (!provenCaster_)
        provenCaster_ = std::make_shared<const raycast::ProvenRayCaster>(triangles_);
    return provenCaster_;
}

std::shared_ptr<const InnerProxy> CpuBitmaskSampler::innerProxy(std::size_t i, bool build, std::size_t* built) const
{
    std::lock_guard lock(proxyMutex_);
    if (proxies_.size() != instances_.size())
        proxies_.resize(instances_.size());
    if (proxies_[i] || !build)
        return proxies_[i];
    const InstanceInfo& info = instances_[i];
    const glm::vec3* vertices = &triangles_.vertices[3 * info.first];
    const std::uint64_t fingerprint = triangleFingerprint(vertices, info.count);
    for (auto earlier = earlierProxies_.begin(); earlier != earlierProxies_.end(); ++earlier)
        if ((*earlier)->builtFor(vertices, info.count, fingerprint)) {
            proxies_[i] = std::move(*earlier);
            earlierProxies_.erase(earlier);
            return proxies_[i];
        }
    proxies_[i] = std::make_shared<const InnerProxy>(buildInnerProxy(vertices, info.count, kProxyResolution));
    ++*built;
    return proxies_[i];
}

HiddenSampleMap CpuBitmaskSampler::sample(const Patch& source, const Patch& receiver, const BitmaskOptions& options,
                                          BitmaskStats* stats) const
{
    validatePatchPair(source, receiver);
    if (options.heights)
        validateReceiverHeights(source, receiver, *options.heights);
    const RoleSwapOptions swap{.exact = options.mode == MaskMode::Exact, .jittered = options.jitter.enabled(),
                               .bumpy = !flatReceiver(options.heights),
                               .raysForced = options.strategy == CpuStrategy::RayCast};
    if (options.swapRoles && swapPatchRoles(source, receiver, swap)) {
        BitmaskOptions swappedOptions = options;
        swappedOptions.heights = nullptr;   // all zero: the flat receiver, now the source
        const HiddenSampleMap swapped = sampleOriented(receiver, source, swappedOptions, stats, /*swappedRoles=*/true);
        if (stats)
            stats->swappedRoles = true;
        return swapped.withRolesSwapped(receiver.na, receiver.nb);
    }
    if (options.swapRoles)
        if (const std::optional<std::pair<int, int>> tiles = receiverTilesToSwap(source, receiver, swap))
            return sampleByReceiverTiles(source, receiver, options, stats, tiles->first, tiles->second);
    return sampleOriented(source, receiver, options, stats, /*swappedRoles=*/false);
}

namespace {

/// A tile's counts and times added to the whole call's.
void addTileStats(BitmaskStats& total, const BitmaskStats& tile)
{
    total.strategy = total.receiverTiles == 0 || std::string_view(total.strategy) == tile.strategy ? tile.strategy : "mixed";
    total.swappedRoles = total.swappedRoles || tile.swappedRoles;
    ++total.receiverTiles;
    total.setupMs += tile.setupMs, total.sampleMs += tile.sampleMs, total.rayMs += tile.rayMs;
    total.trianglesInShaft = std::max(total.trianglesInShaft, tile.trianglesInShaft);
    total.smallTriangles += tile.smallTriangles, total.pairs += tile.pairs, total.floatPairs += tile.floatPairs;
    total.floatFallbacks += tile.floatFallbacks, total.raysCast += tile.raysCast, total.provenHits += tile.provenHits;
    total.exactHitTests += tile.exactHitTests, total.raysConfirmed += tile.raysConfirmed;
    total.rayFloatMs += tile.rayFloatMs, total.rayConfirmMs += tile.rayConfirmMs;
    total.rayPackets = total.rayPackets || tile.rayPackets;
    total.culledFrontFaces += tile.culledFrontFaces, total.proxyFaces += tile.proxyFaces;
    total.proxyBlocked += tile.proxyBlocked, total.proxyMs += tile.proxyMs, total.proxiesBuilt += tile.proxiesBuilt;
    total.narrowedAway += tile.narrowedAway, total.tableMs += tile.tableMs;
    total.estimatedPairs += tile.estimatedPairs, total.estimatedTriangles += tile.estimatedTriangles;
    total.predictedBitmaskMs += tile.predictedBitmaskMs, total.predictedRayMs += tile.predictedRayMs;
    total.probed = total.probed || tile.probed;
    total.probeRayMs += tile.probeRayMs, total.probeBitmaskMs += tile.probeBitmaskMs;
    total.reusedChoice = total.reusedChoice || tile.reusedChoice;
    total.reusedTimedChoice = total.reusedTimedChoice || tile.reusedTimedChoice;
}

} // namespace

HiddenSampleMap CpuBitmaskSampler::sampleByReceiverTiles(const Patch& source, const Patch& receiver,
                                                         const BitmaskOptions& options, BitmaskStats* stats, int columns,
                                                         int rows) const
{
    // Each tile a patch of its own whose samples are the receiver's (up to rounding in the last
    // bits of their positions, far inside the tie distance), sampled with the roles swapped.
    HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
    BitmaskOptions tileOptions = options;
    tileOptions.heights = nullptr;   // none, or all zero: the flat receiver
    BitmaskStats total;
    total.receiverTiles = 0;
    for (int tb = 0; tb < rows; ++tb)
        for (int ta = 0; ta < columns; ++ta) {
            const int a0 = ta * receiver.na / columns, a1 = (ta + 1) * receiver.na / columns;
            const int b0 = tb * receiver.nb / rows, b1 = (tb + 1) * receiver.nb / rows;
            Patch tile = receiver;
            tile.corner = receiver.corner + double(a0) / receiver.na * receiver.u + double(b0) / receiver.nb * receiver.v;
            tile.u = receiver.u * (double(a1 - a0) / receiver.na);
            tile.v = receiver.v * (double(b1 - b0) / receiver.nb);
            tile.na = a1 - a0, tile.nb = b1 - b0;
            BitmaskStats part;
            const HiddenSampleMap tileMap = sample(source, tile, tileOptions, &part);
            for (int b = 0; b < tile.nb; ++b)
                for (int a = 0; a < tile.na; ++a) {
                    const std::span<const std::uint64_t> from = tileMap.row(b * tile.na + a);
                    std::ranges::copy(from, map.row((b0 + b) * receiver.na + a0 + a).begin());
                }
            addTileStats(total, part);
        }
    if (stats)
        *stats = total;
    return map;
}

HiddenSampleMap CpuBitmaskSampler::sampleOriented(const Patch& source, const Patch& receiver, const BitmaskOptions& options,
                                                  BitmaskStats* stats, bool swappedRoles) const
{
    // A bumpy receiver (§8). All-zero heights move no sample: the flat path, unchanged.
    const bool bumpy = !flatReceiver(options.heights);
    std::vector<glm::dvec3> displaced;
    Bounds displacedBox;
    glm::dvec3 normal(0.0);
    double lowest = 0.0, highest = 0.0;
    if (bumpy) {
        // The same expression as RayCastScene's and displacedReceiverSample's: the same bits.
        normal = receiverNormalTowardSource(source, receiver);
        const std::vector<double>& metres = options.heights->metres;
        displaced.resize(metres.size());
        for (int j = 0; j < receiver.sampleCount(); ++j) {
            displaced[std::size_t(j)] = receiver.sample(j) + metres[std::size_t(j)] * normal;
            displacedBox.extend(glm::vec3(displaced[std::size_t(j)]));
        }
        const auto [lo, hi] = std::minmax_element(metres.begin(), metres.end());
        lowest = *lo, highest = *hi;
    }
    HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
    BitmaskStats local;
    const auto setupStart = Clock::now();

    std::shared_ptr<const HoughMaskTable> table;
    if (options.mode == MaskMode::Table) {
        const auto tableStart = Clock::now();
        std::lock_guard lock(tableMutex_);
        if (!table_ || table_->width() != options.tableWidth || table_->height() != options.tableHeight ||
            table_->grid() != std::pair(source.na, source.nb)) {
            table_ = std::make_shared<const HoughMaskTable>(source.na, source.nb, options.tableWidth, options.tableHeight);
            local.tableMs = msSince(tableStart);
        }
        table = table_;
    }
    // Table mode is the paper's method as published: every triangle by bitmask, no narrowing.
    const bool exact = options.mode == MaskMode::Exact;
    const bool narrow = options.narrowShaft && exact;
    const CpuStrategy strategy = exact ? options.strategy : CpuStrategy::Bitmask;

    std::unique_ptr<Workspace> work = takeWorkspace();
    auto body = [&] {
        Shaft shaft(source, receiver, options.jitter, bumpy ? &displaced : nullptr);
        shaft.table = table.get();
        shaft.floatKernel = exact && options.simd && source.na <= 32 && detail::floatRowsAvailable();

        // A bumpy receiver's segments end in the prism of the receiver between its lowest and
        // highest bump (§8), so its shaft is the hull of the source's corners and that prism.
        const ShaftHull hull = bumpy ? ShaftHull([&] {
            std::vector<glm::dvec3> points;
            for (int k = 0; k < 4; ++k) {
                const glm::dvec3 rc = receiver.cornerPoint(k);
                points.push_back(source.cornerPoint(k));
                points.push_back(rc + lowest * normal);
                points.push_back(rc + highest * normal);
            }
            return points;
        }())
                                     : ShaftHull(source, receiver);
        TriangleFilter filter;
        filter.triangles = &triangles_;
        filter.hull = &hull;
        filter.instanceOutside.resize(instances_.size());
        for (std::size_t i = 0; i < instances_.size(); ++i)
            filter.instanceOutside[i] = hull.excludesBox(instances_[i].bounds.min, instances_[i].bounds.max);
        if (options.watertightCulling)
            filter.cullable = cullableInstances(receiver, bumpy ? &displacedBox : nullptr);
        for (int k = 0; k < 4; ++k)
            filter.sourceCorners[std::size_t(k)] = source.cornerPoint(k);
        std::vector<char> closedInstance(instances_.size());
        for (std::size_t i = 0; i < instances_.size(); ++i)
            closedInstance[i] = instances_[i].watertight;

        // The inner proxies first (InnerProxy.h): the rays through the meshes' insides,
        // by the bitmask on a few large faces, before any strategy looks at the meshes' triangles.
        if (exact && options.innerProxy) {
            const auto proxyStart = Clock::now();
            std::vector<glm::dvec3> ends;
            for (int k = 0; k < 4; ++k)
                ends.push_back(receiver.cornerPoint(k));
            const ProxyPass pass(shaft, hull, filter.sourceCorners, bumpy ? displaced : ends,
                                 {source, receiver, options.jitter, bumpy ? options.heights : nullptr},
                                 options.watertightCulling, narrow);
            std::vector<std::shared_ptr<const InnerProxy>> proxies;
            for (std::size_t i = 0; i < instances_.size(); ++i) {
                const InstanceInfo& info = instances_[i];
                if (info.count < kProxyMinTriangles || !proxyApplies(info.triangleBounds, pass))
                    continue;
                const bool build = double(map.rayCount()) >= kProxyBuildRaysPerTriangle * double(info.count);
                if (std::shared_ptr<const InnerProxy> proxy = innerProxy(i, build, &local.proxiesBuilt);
                    proxy && !proxy->faces.empty())
                    proxies.push_back(std::move(proxy));
            }
            if (!proxies.empty())
                local.proxyFaces = seedFromInnerProxies(proxies, pass, work->occluders, work->bins, map);
            if (local.proxyFaces > 0)
                local.proxyBlocked = map.blockedCount();
            local.proxyMs = msSince(proxyStart);
        }

        // Ray casting: the float pass and the reference's confirmation of the rays it leaves free.
        const auto castRays = [&](const RayCastOptions& rayOptions) {
            const std::shared_ptr<const RayCastScene> reference = wholeSceneCaster();
            const std::shared_ptr<const raycast::ProvenRayCaster> proven = provenCaster();
            raycast::ProvenCastStats cast;
            proven->sampleUnblocked(source, receiver, map, rayOptions, *reference, raycast::CastMode::Auto, &cast);
            local.raysCast += cast.floatRays;
            local.provenHits += cast.provenHits;
            local.exactHitTests += cast.exactTests;
            local.raysConfirmed += cast.confirmRays;
            local.rayFloatMs += cast.floatMs;
            local.rayConfirmMs += cast.confirmMs;
            local.rayPackets = cast.packets;
        };
        // A probe measures each method by one thread's processor time (so that other jobs sharing
        // the machine, which stretch the wall time of whatever runs while they do, do not decide
        // it): its setup and its batches run on this thread alone.
        tbb::task_arena one(1);
        const auto onOneThread = [&](const auto& f) {
            const double start = threadMs();
            one.execute(f);
            return threadMs() - start;
        };

        // Few source samples: ray casting everything may be cheaper than the bitmask, whose cost
        // follows (triangle, receiver sample) pairs, not rays (Strategy.h). An earlier choice on
        // a similar configuration serves without estimating again: the estimate prepares every
        // 32nd triangle, about a sixth of a call on a dense mesh.
        Plan plan = Plan::Bitmask;
        const Configuration configuration{source, receiver, options.jitter.enabled(), bumpy, shaft.floatKernel};
        bool warmGrids = false;   // Auto sampled these grids before: a probe's times are what later calls pay
        // A choice for later calls on a similar configuration (ProbeMemo).
        const auto remember = [&](bool rays, int calls, bool measured) {
            std::lock_guard lock(probeMutex_);
            probeMemo_ = std::make_unique<StrategyChoiceCache>(StrategyChoiceCache{{configuration, rays, calls, measured}});
        };
        if (strategy == CpuStrategy::Auto) {
            bool remembered = false;
            {
                std::lock_guard lock(probeMutex_);
                const std::array<int, 4> grids{source.na, source.nb, receiver.na, receiver.nb};
                warmGrids = std::find(sampledGrids_.begin(), sampledGrids_.end(), grids) != sampledGrids_.end();
                if (!warmGrids)
                    sampledGrids_.push_back(grids);
                if (probeMemo_ && probeMemo_->memo.callsLeft > 0 &&
                    similarConfiguration(probeMemo_->memo.configuration, configuration)) {
                    --probeMemo_->memo.callsLeft;
                    local.reusedChoice = true;
                    local.reusedTimedChoice = probeMemo_->memo.measured;
                    plan = probeMemo_->memo.rays ? Plan::RayCast : Plan::Bitmask;
                    remembered = true;
                }
            }
            if (!remembered) {
                const PairEstimate estimate = estimatePairs(shaft, filter);
                local.estimatedPairs = estimate.pairs;
                local.estimatedTriangles = estimate.triangles;
                const CostEstimate cost{.rays = map.rayCount(), .estimatedPairs = estimate.pairs,
                                        .estimatedTriangles = estimate.triangles, .floatKernel = shaft.floatKernel,
                                        .bumpy = bumpy, .receiverSamples = receiver.sampleCount(),
                                        .finerSamples = std::max(source.sampleCount(), receiver.sampleCount()),
                                        .swappedRoles = swappedRoles,
                                        .openShare = 1.0 - double(local.proxyBlocked) / double(map.rayCount())};
                const CostModel& model = measuredCosts(shaft.floatKernel);
                plan = planFor(cost, model);
                local.predictedBitmaskMs = predictedBitmaskMs(cost, model);
                local.predictedRayMs = predictedRayMs(cost, model);
                if (plan != Plan::Probe)
                    remember(plan == Plan::RayCast, kProbeReuse, /*measured=*/false);
            }
        }
        // With the roles swapped the receiver has too few tiles to time the bitmask on: the rays
        // of a few receiver samples are timed (their rows are final either way) and, unless they
        // are clearly cheaper than the bitmask's prediction, the bitmask is timed on this call's
        // whole answer (swappedRaysOrTimeBitmask, swappedMeasuredChoosesRays).
        std::vector<int> raySamples;   // the receiver samples left to cast, when not all
        bool timeSwappedBitmask = false;   // against the probe's rays, local.probeRayMs
        if (plan == Plan::Probe && swappedRoles) {
            std::vector<int> probe;
            swappedProbeSamples(receiver.sampleCount(), probe, raySamples);
            const auto probeStart = Clock::now();
            wholeSceneCaster(), provenCaster();
            const double probeMs =
                onOneThread([&] { castRays({.jitter = options.jitter, .receiverSubset = &probe}); });
            local.rayMs += msSince(probeStart);
            local.probed = true;
            local.probeRayMs = swappedRaysWholeMs(probeMs, probe.size(), std::size_t(receiver.sampleCount()));
            if (swappedRaysOrTimeBitmask(local.predictedBitmaskMs, local.probeRayMs) == SwappedVerdict::Rays) {
                plan = Plan::RayCast;
                remember(true, warmGrids ? kProbeReuse : 0, /*measured=*/true);
            } else {
                plan = Plan::Bitmask;
                timeSwappedBitmask = true;
            }
        }
        if (strategy == CpuStrategy::RayCast || plan == Plan::RayCast) {
            local.strategy = "raycast";
            wholeSceneCaster(), provenCaster();   // built on first use, counted as setup
            local.setupMs = msSince(setupStart);
            const auto rayStart = Clock::now();
            castRays({.jitter = options.jitter,
                      .heights = options.heights,
                      .receiverSubset = local.probed ? &raySamples : nullptr});
            local.rayMs += msSince(rayStart);
            return;
        }
        const bool probing = plan == Plan::Probe;
        const bool timed = probing || timeSwappedBitmask;   // one thread's processor time, for a verdict
        double setupThreadMs = 0.0;
        if (timed)
            setupThreadMs += onOneThread([&] { work->occluders.prepare(shaft, filter); });
        else
            work->occluders.prepare(shaft, filter);
        const std::vector<const Occluder*>& occluders = work->occluders.occluders;
        local.culledFrontFaces = work->occluders.culledFrontFaces;
        local.trianglesInShaft = occluders.size();

        // Hybrid: the small triangles leave the bitmask pass for a ray pass. With the SIMD kernel
        // the plain bitmask beats the hybrid's ray pass, so Auto sends small triangles to ray
        // casting only without it.
        std::vector<char>& small = work->small;
        small.assign(occluders.size(), 0);
        std::vector<std::uint32_t> smallTriangles;
        if (strategy != CpuStrategy::Bitmask)
            for (std::size_t i = 0; i < occluders.size(); ++i)
                if (occluders[i]->cells < options.smallCells)
                    smallTriangles.push_back(std::uint32_t(i));
        // (A CPU without AVX2, not a caller who asked for the double kernel.)
        const bool hybrid = strategy == CpuStrategy::Hybrid ||
                            (strategy == CpuStrategy::Auto && !detail::floatRowsAvailable() &&
                             smallTriangles.size() >= kHybridMinSmallTriangles);
        if (!hybrid)
            smallTriangles.clear();
        for (std::uint32_t& i : smallTriangles) {
            small[i] = 1;
            i = work->occluders.triangleOf[i];
        }
        local.strategy = hybrid ? "hybrid" : "bitmask";
        local.smallTriangles = smallTriangles.size();

        TileBins& bins = work->bins;
        if (timed)
            setupThreadMs += onOneThread([&] { bins.build(shaft, work->occluders, small, closedInstance, triangles_); });
        else
            bins.build(shaft, work->occluders, small, closedInstance, triangles_);
        local.setupMs = msSince(setupStart);

        const auto addCounts = [&](const TilePassCounts& counts) {
            local.pairs += counts.pairs;
            local.floatPairs += counts.floatPairs;
            local.floatFallbacks += counts.floatFallbacks;
            local.narrowedAway += counts.narrowedAway;
        };
        const auto sampleStart = Clock::now();
        if (plan == Plan::Probe && smallTriangles.empty()) {
            // A few tiles (probeTilesPerMethod) by bitmask and as many by rays, a batch of each at a time,
            // timed; their rows are final either way. Pairs of neighbouring tiles drawn at random
            // over the whole receiver, one of each to each method (probeTiles): in row order the
            // first batches would all lie along one edge (a floor's edge by the wall costs nothing
            // either way), and tiles drawn independently for each method differ in work.
            ProbeTiles split =
                probeTiles(bins.tileCount(), std::size_t(bins.tilesA()), probeTilesPerMethod(bins.tileCount()));
            const std::vector<std::uint32_t>& bitmaskTiles = split.bitmask;
            const std::vector<std::uint32_t>& rayTiles = split.rays;
            std::vector<std::uint32_t>& rest = split.rest;
            wholeSceneCaster(), provenCaster();
            std::vector<int> samples;
            RayCastOptions rayOptions{.jitter = options.jitter, .receiverSubset = &samples};
            const std::size_t batch = std::max<std::size_t>(4, 2 * std::size_t(tbb::this_task_arena::max_concurrency()));
            std::size_t bitmaskDone = 0, rayDone = 0;
            double bitmaskMs = 0.0, rayMs = 0.0;
            // Each method's work per tile (Strategy.h, probeShare): the bitmask's bin entries, and
            // the rays still free (the inner proxies may have answered many).
            std::vector<double> rayUnits(bins.tileCount());
            double bitmaskTotal = 0.0, rayTotal = 0.0;
            for (std::size_t t = 0; t < bins.tileCount(); ++t) {
                samples.clear();
                bins.tileSamples(t, receiver.na, receiver.nb, samples);
                for (int j : samples)
                    rayUnits[t] += double(source.sampleCount() - std::as_const(map).blockedCount(j));
                bitmaskTotal += double(bins.bin(t).size()), rayTotal += rayUnits[t];
            }
            double bitmaskProbed = 0.0, rayProbed = 0.0;
            const auto parts = [&] {
                return std::pair(
                    ProbePart{bitmaskMs, probeShare(bitmaskProbed, bitmaskTotal, bitmaskDone, bins.tileCount())},
                    ProbePart{rayMs, probeShare(rayProbed, rayTotal, rayDone, bins.tileCount())});
            };
            while (bitmaskDone < bitmaskTiles.size() || rayDone < rayTiles.size()) {
                if (bitmaskDone < bitmaskTiles.size()) {
                    const std::size_t end = std::min(bitmaskDone + batch, bitmaskTiles.size());
                    const std::vector<std::uint32_t> part(bitmaskTiles.begin() + std::ptrdiff_t(bitmaskDone),
                                                          bitmaskTiles.begin() + std::ptrdiff_t(end));
                    bitmaskMs += onOneThread([&] { addCounts(bitmaskPass(shaft, bins, map, narrow, &part)); });
                    for (std::uint32_t t : part)
                        bitmaskProbed += double(bins.bin(t).size());
                    bitmaskDone = end;
                }
                if (rayDone < rayTiles.size()) {
                    const std::size_t end = std::min(rayDone + batch, rayTiles.size());
                    samples.clear();
                    for (std::size_t k = rayDone; k < end; ++k) {
                        bins.tileSamples(rayTiles[k], receiver.na, receiver.nb, samples);
                        rayProbed += rayUnits[rayTiles[k]];
                    }
                    const auto start = Clock::now();
                    rayMs += onOneThread([&] { castRays(rayOptions); });
                    local.rayMs += msSince(start);
                    rayDone = end;
                }
                if (const auto [bitmask, rays] = parts(); probeIsDecided(bitmask, bitmaskDone, rays, rayDone, batch))
                    break;
            }
            rest.insert(rest.end(), bitmaskTiles.begin() + std::ptrdiff_t(bitmaskDone), bitmaskTiles.end());
            rest.insert(rest.end(), rayTiles.begin() + std::ptrdiff_t(rayDone), rayTiles.end());
            local.probed = true;
            const auto [bitmaskPart, rayPart] = parts();
            const ProbeVerdict verdict = probeVerdict(bitmaskPart, rayPart, setupThreadMs, warmGrids);
            remember(verdict.memoRays, verdict.memoCalls, /*measured=*/true);
            if (!verdict.restByRays) {
                local.strategy = "bitmask";
                addCounts(bitmaskPass(shaft, bins, map, narrow, &rest));
            } else {
                local.strategy = "raycast";
                samples.clear();
                for (std::uint32_t t : rest)
                    bins.tileSamples(t, receiver.na, receiver.nb, samples);
                const auto restStart = Clock::now();
                castRays(rayOptions);
                local.rayMs += msSince(restStart);
            }
            local.sampleMs = msSince(sampleStart) - local.rayMs;
            return;
        }
        if (timeSwappedBitmask) {
            const double passMs = onOneThread([&] { addCounts(bitmaskPass(shaft, bins, map, narrow)); });
            local.probeBitmaskMs = setupThreadMs + passMs;
            const bool rays = swappedMeasuredChoosesRays(local.probeRayMs, setupThreadMs, passMs);
            remember(rays, !warmGrids ? 0 : rays ? swappedRaysMemoCalls(local.probeRayMs, local.probeBitmaskMs) : kProbeReuse,
                     /*measured=*/true);
        } else {
            addCounts(bitmaskPass(shaft, bins, map, narrow));
        }
        local.sampleMs = msSince(sampleStart);
        if (!smallTriangles.empty()) {
            // The still-unblocked rays against a BVH of the small triangles only.
            const auto rayStart = Clock::now();
            WorldTriangles subset;
            subset.vertices.reserve(3 * smallTriangles.size());
            for (std::uint32_t t : smallTriangles) {
                subset.vertices.insert(subset.vertices.end(), &triangles_.vertices[3 * t], &triangles_.vertices[3 * t] + 3);
                subset.instanceOf.push_back(triangles_.instanceOf[t]);
            }
            const RayCastScene rays(subset, /*fastBuild=*/true);
            local.raysCast = rays.sampleUnblocked(source, receiver, map, {.jitter = options.jitter, .heights = options.heights});
            local.rayMs = msSince(rayStart);
        }
    };
    if (options.threads > 0) {
        tbb::task_arena arena(options.threads);
        arena.execute(body);
    } else {
        body();
    }
    returnWorkspace(std::move(work));
    if (stats)
        *stats = local;
    return map;
}

} // namespace sightline
