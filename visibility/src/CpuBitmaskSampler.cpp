#include "visibility/CpuBitmaskSampler.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <ctime>
#include <limits>
#include <optional>
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
    total.debug.smallTriangles += tile.debug.smallTriangles, total.pairs += tile.pairs, total.debug.floatPairs += tile.debug.floatPairs;
    total.debug.floatFallbacks += tile.debug.floatFallbacks, total.raysCast += tile.raysCast, total.debug.provenHits += tile.debug.provenHits;
    total.debug.exactHitTests += tile.debug.exactHitTests, total.debug.raysConfirmed += tile.debug.raysConfirmed;
    total.debug.rayFloatMs += tile.debug.rayFloatMs, total.debug.rayConfirmMs += tile.debug.rayConfirmMs;
    total.debug.rayPackets = total.debug.rayPackets || tile.debug.rayPackets;
    total.debug.culledFrontFaces += tile.debug.culledFrontFaces, total.debug.proxyFaces += tile.debug.proxyFaces;
    total.proxyBlocked += tile.proxyBlocked, total.debug.proxyMs += tile.debug.proxyMs, total.debug.proxiesBuilt += tile.debug.proxiesBuilt;
    total.debug.narrowedAway += tile.debug.narrowedAway, total.debug.tableMs += tile.debug.tableMs;
    total.debug.estimatedPairs += tile.debug.estimatedPairs, total.debug.estimatedTriangles += tile.debug.estimatedTriangles;
    total.debug.predictedBitmaskMs += tile.debug.predictedBitmaskMs, total.debug.predictedRayMs += tile.debug.predictedRayMs;
    total.debug.probed = total.debug.probed || tile.debug.probed;
    total.debug.probeRayMs += tile.debug.probeRayMs, total.debug.probeBitmaskMs += tile.debug.probeBitmaskMs;
    total.debug.reusedChoice = total.debug.reusedChoice || tile.debug.reusedChoice;
    total.debug.reusedTimedChoice = total.debug.reusedTimedChoice || tile.debug.reusedTimedChoice;
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

/// One sampleOriented call: the shaft, the triangle filter and the inner proxies, then Auto's
/// choice between the bitmask and ray casting (an earlier choice, the cost model, or a probe that
/// times both on a few tiles), and the pass or passes chosen. Its members are the call's state;
/// each method one step.
class CpuBitmaskSampler::OrientedCall {
public:
    OrientedCall(const CpuBitmaskSampler& sampler, const Patch& source, const Patch& receiver, const BitmaskOptions& options,
                 bool swappedRoles, HiddenSampleMap& map, BitmaskStats& local, Workspace& work)
        : sampler_(sampler), source_(source), receiver_(receiver), options_(options), swappedRoles_(swappedRoles), map_(map),
          local_(local), work_(work), exact_(options.mode == MaskMode::Exact), narrow_(options.narrowShaft && exact_),
          // Table mode is the paper's method as published: every triangle by bitmask, no narrowing.
          strategy_(exact_ ? options.strategy : CpuStrategy::Bitmask)
    {
        displaceReceiver();
        setupStart_ = Clock::now();
        chooseTable();
    }

    void run()
    {
        shaft_.emplace(source_, receiver_, options_.jitter, bumpy_ ? &displaced_ : nullptr);
        shaft_->table = table_.get();
        shaft_->floatKernel = exact_ && options_.simd && source_.na <= 32 && detail::floatRowsAvailable();
        buildFilter();
        if (exact_ && options_.innerProxy)
            seedInnerProxies();
        if (strategy_ == CpuStrategy::Auto)
            choosePlan();
        if (plan_ == Plan::Probe && swappedRoles_)
            probeSwappedRays();
        if (strategy_ == CpuStrategy::RayCast || plan_ == Plan::RayCast) {
            castEverything();
            return;
        }
        prepareBitmask();
        const auto sampleStart = Clock::now();
        if (plan_ == Plan::Probe && smallTriangles_.empty()) {
            probeTilesAndFinish();
            local_.sampleMs = msSince(sampleStart) - local_.rayMs;
            return;
        }
        runBitmask();
        local_.sampleMs = msSince(sampleStart);
        if (!smallTriangles_.empty())
            castSmallTriangles();
    }

private:
    /// A bumpy receiver (§8). All-zero heights move no sample: the flat path, unchanged.
    void displaceReceiver()
    {
        bumpy_ = !flatReceiver(options_.heights);
        if (!bumpy_)
            return;
        // The same expression as RayCastScene's and displacedReceiverSample's: the same bits.
        normal_ = receiverNormalTowardSource(source_, receiver_);
        const std::vector<double>& metres = options_.heights->metres;
        displaced_.resize(metres.size());
        for (int j = 0; j < receiver_.sampleCount(); ++j) {
            displaced_[std::size_t(j)] = receiver_.sample(j) + metres[std::size_t(j)] * normal_;
            displacedBox_.extend(glm::vec3(displaced_[std::size_t(j)]));
        }
        const auto [lo, hi] = std::minmax_element(metres.begin(), metres.end());
        lowest_ = *lo, highest_ = *hi;
    }

    /// Table mode's Hough table: the last one built when it fits.
    void chooseTable()
    {
        if (options_.mode != MaskMode::Table)
            return;
        const auto tableStart = Clock::now();
        std::lock_guard lock(sampler_.tableMutex_);
        if (!sampler_.table_ || sampler_.table_->width() != options_.tableWidth ||
            sampler_.table_->height() != options_.tableHeight || sampler_.table_->grid() != std::pair(source_.na, source_.nb)) {
            sampler_.table_ = std::make_shared<const HoughMaskTable>(source_.na, source_.nb, options_.tableWidth, options_.tableHeight);
            local_.debug.tableMs = msSince(tableStart);
        }
        table_ = sampler_.table_;
    }

    /// The shaft's hull and what it lets through: instances outside it, front faces a closed
    /// mesh may cull.
    void buildFilter()
    {
        // A bumpy receiver's segments end in the prism of the receiver between its lowest and
        // highest bump (§8), so its shaft is the hull of the source's corners and that prism.
        if (bumpy_) {
            std::vector<glm::dvec3> points;
            for (int k = 0; k < 4; ++k) {
                const glm::dvec3 rc = receiver_.cornerPoint(k);
                points.push_back(source_.cornerPoint(k));
                points.push_back(rc + lowest_ * normal_);
                points.push_back(rc + highest_ * normal_);
            }
            hull_.emplace(points);
        } else {
            hull_.emplace(source_, receiver_);
        }
        const auto& instances = sampler_.instances_;
        filter_.triangles = &sampler_.triangles_;
        filter_.hull = &*hull_;
        filter_.instanceOutside.resize(instances.size());
        for (std::size_t i = 0; i < instances.size(); ++i)
            filter_.instanceOutside[i] = hull_->excludesBox(instances[i].bounds.min, instances[i].bounds.max);
        if (options_.watertightCulling)
            filter_.cullable = sampler_.cullableInstances(receiver_, bumpy_ ? &displacedBox_ : nullptr);
        for (int k = 0; k < 4; ++k)
            filter_.sourceCorners[std::size_t(k)] = source_.cornerPoint(k);
        closedInstance_.resize(instances.size());
        for (std::size_t i = 0; i < instances.size(); ++i)
            closedInstance_[i] = instances[i].watertight;
    }

    /// The inner proxies first (InnerProxy.h): the rays through the meshes' insides, by the
    /// bitmask on a few large faces, before any strategy looks at the meshes' triangles.
    void seedInnerProxies()
    {
        const auto proxyStart = Clock::now();
        std::vector<glm::dvec3> ends;
        for (int k = 0; k < 4; ++k)
            ends.push_back(receiver_.cornerPoint(k));
        const ProxyPass pass(*shaft_, *hull_, filter_.sourceCorners, bumpy_ ? displaced_ : ends,
                             {source_, receiver_, options_.jitter, bumpy_ ? options_.heights : nullptr},
                             options_.watertightCulling, narrow_);
        std::vector<std::shared_ptr<const InnerProxy>> proxies;
        for (std::size_t i = 0; i < sampler_.instances_.size(); ++i) {
            const InstanceInfo& info = sampler_.instances_[i];
            if (info.count < kProxyMinTriangles || !proxyApplies(info.triangleBounds, pass))
                continue;
            const bool build = double(map_.rayCount()) >= kProxyBuildRaysPerTriangle * double(info.count);
            if (std::shared_ptr<const InnerProxy> proxy = sampler_.innerProxy(i, build, &local_.debug.proxiesBuilt);
                proxy && !proxy->faces.empty())
                proxies.push_back(std::move(proxy));
        }
        if (!proxies.empty())
            local_.debug.proxyFaces = seedFromInnerProxies(proxies, pass, work_.occluders, work_.bins, map_);
        if (local_.debug.proxyFaces > 0)
            local_.proxyBlocked = map_.blockedCount();
        local_.debug.proxyMs = msSince(proxyStart);
    }

    /// Ray casting: the float pass and the reference's confirmation of the rays it leaves free.
    void castRays(const RayCastOptions& rayOptions)
    {
        const std::shared_ptr<const RayCastScene> reference = sampler_.wholeSceneCaster();
        const std::shared_ptr<const raycast::ProvenRayCaster> proven = sampler_.provenCaster();
        raycast::ProvenCastStats cast;
        proven->sampleUnblocked(source_, receiver_, map_, rayOptions, *reference, raycast::CastMode::Auto, &cast);
        local_.raysCast += cast.floatRays;
        local_.debug.provenHits += cast.provenHits;
        local_.debug.exactHitTests += cast.exactTests;
        local_.debug.raysConfirmed += cast.confirmRays;
        local_.debug.rayFloatMs += cast.floatMs;
        local_.debug.rayConfirmMs += cast.confirmMs;
        local_.debug.rayPackets = cast.packets;
    }

    /// A probe measures each method by one thread's processor time (so that other jobs sharing
    /// the machine, which stretch the wall time of whatever runs while they do, do not decide
    /// it): its setup and its batches run on this thread alone.
    template <typename F>
    double onOneThread(const F& f)
    {
        const double start = threadMs();
        one_.execute(f);
        return threadMs() - start;
    }

    /// A choice for later calls on a similar configuration (ProbeMemo).
    void remember(bool rays, int calls, bool measured)
    {
        std::lock_guard lock(sampler_.probeMutex_);
        sampler_.probeMemo_ = std::make_unique<StrategyChoiceCache>(StrategyChoiceCache{{configuration(), rays, calls, measured}});
    }

    Configuration configuration() const
    {
        return {source_, receiver_, options_.jitter.enabled(), bumpy_, shaft_->floatKernel};
    }

    /// Few source samples: ray casting everything may be cheaper than the bitmask, whose cost
    /// follows (triangle, receiver sample) pairs, not rays (Strategy.h). An earlier choice on a
    /// similar configuration serves without estimating again: the estimate prepares every 32nd
    /// triangle, about a sixth of a call on a dense mesh.
    void choosePlan()
    {
        {
            std::lock_guard lock(sampler_.probeMutex_);
            const std::array<int, 4> grids{source_.na, source_.nb, receiver_.na, receiver_.nb};
            auto& sampled = sampler_.sampledGrids_;
            warmGrids_ = std::find(sampled.begin(), sampled.end(), grids) != sampled.end();
            if (!warmGrids_)
                sampled.push_back(grids);
            auto& memo = sampler_.probeMemo_;
            if (memo && memo->memo.callsLeft > 0 && similarConfiguration(memo->memo.configuration, configuration())) {
                --memo->memo.callsLeft;
                local_.debug.reusedChoice = true;
                local_.debug.reusedTimedChoice = memo->memo.measured;
                plan_ = memo->memo.rays ? Plan::RayCast : Plan::Bitmask;
                return;
            }
        }
        const PairEstimate estimate = estimatePairs(*shaft_, filter_);
        local_.debug.estimatedPairs = estimate.pairs;
        local_.debug.estimatedTriangles = estimate.triangles;
        const CostEstimate cost{.rays = map_.rayCount(), .estimatedPairs = estimate.pairs,
                                .estimatedTriangles = estimate.triangles, .floatKernel = shaft_->floatKernel,
                                .bumpy = bumpy_, .receiverSamples = receiver_.sampleCount(),
                                .finerSamples = std::max(source_.sampleCount(), receiver_.sampleCount()),
                                .swappedRoles = swappedRoles_,
                                .openShare = 1.0 - double(local_.proxyBlocked) / double(map_.rayCount())};
        const CostModel& model = measuredCosts(shaft_->floatKernel);
        plan_ = planFor(cost, model);
        local_.debug.predictedBitmaskMs = predictedBitmaskMs(cost, model);
        local_.debug.predictedRayMs = predictedRayMs(cost, model);
        if (plan_ != Plan::Probe)
            remember(plan_ == Plan::RayCast, kProbeReuse, /*measured=*/false);
    }

    /// With the roles swapped the receiver has too few tiles to time the bitmask on: the rays of a
    /// few receiver samples are timed (their rows are final either way) and, unless they are
    /// clearly cheaper than the bitmask's prediction, the bitmask is timed on this call's whole
    /// answer (swappedRaysOrTimeBitmask, swappedMeasuredChoosesRays).
    void probeSwappedRays()
    {
        std::vector<int> probe;
        swappedProbeSamples(receiver_.sampleCount(), probe, raySamples_);
        const auto probeStart = Clock::now();
        sampler_.wholeSceneCaster(), sampler_.provenCaster();
        const double probeMs = onOneThread([&] { castRays({.jitter = options_.jitter, .receiverSubset = &probe}); });
        local_.rayMs += msSince(probeStart);
        local_.debug.probed = true;
        local_.debug.probeRayMs = swappedRaysWholeMs(probeMs, probe.size(), std::size_t(receiver_.sampleCount()));
        if (swappedRaysOrTimeBitmask(local_.debug.predictedBitmaskMs, local_.debug.probeRayMs) == SwappedVerdict::Rays) {
            plan_ = Plan::RayCast;
            remember(true, warmGrids_ ? kProbeReuse : 0, /*measured=*/true);
        } else {
            plan_ = Plan::Bitmask;
            timeSwappedBitmask_ = true;
        }
    }

    /// Every ray (or those the swapped probe left) by ray casting.
    void castEverything()
    {
        local_.strategy = "raycast";
        sampler_.wholeSceneCaster(), sampler_.provenCaster();   // built on first use, counted as setup
        local_.setupMs = msSince(setupStart_);
        const auto rayStart = Clock::now();
        castRays({.jitter = options_.jitter, .heights = options_.heights, .receiverSubset = local_.debug.probed ? &raySamples_ : nullptr});
        local_.rayMs += msSince(rayStart);
    }

    /// The occluders in the shaft, the hybrid's small triangles, and the receiver's tile bins.
    void prepareBitmask()
    {
        timed_ = plan_ == Plan::Probe || timeSwappedBitmask_;   // one thread's processor time, for a verdict
        if (timed_)
            setupThreadMs_ += onOneThread([&] { work_.occluders.prepare(*shaft_, filter_); });
        else
            work_.occluders.prepare(*shaft_, filter_);
        const std::vector<const Occluder*>& occluders = work_.occluders.occluders;
        local_.debug.culledFrontFaces = work_.occluders.culledFrontFaces;
        local_.trianglesInShaft = occluders.size();

        // Hybrid: the small triangles leave the bitmask pass for a ray pass. With the SIMD kernel
        // the plain bitmask beats the hybrid's ray pass, so Auto sends small triangles to ray
        // casting only without it.
        std::vector<char>& small = work_.small;
        small.assign(occluders.size(), 0);
        if (strategy_ != CpuStrategy::Bitmask)
            for (std::size_t i = 0; i < occluders.size(); ++i)
                if (occluders[i]->cells < options_.smallCells)
                    smallTriangles_.push_back(std::uint32_t(i));
        // (A CPU without AVX2, not a caller who asked for the double kernel.)
        const bool hybrid = strategy_ == CpuStrategy::Hybrid ||
                            (strategy_ == CpuStrategy::Auto && !detail::floatRowsAvailable() &&
                             smallTriangles_.size() >= kHybridMinSmallTriangles);
        if (!hybrid)
            smallTriangles_.clear();
        for (std::uint32_t& i : smallTriangles_) {
            small[i] = 1;
            i = work_.occluders.triangleOf[i];
        }
        local_.strategy = hybrid ? "hybrid" : "bitmask";
        local_.debug.smallTriangles = smallTriangles_.size();

        if (timed_)
            setupThreadMs_ += onOneThread(
                [&] { work_.bins.build(*shaft_, work_.occluders, small, closedInstance_, sampler_.triangles_); });
        else
            work_.bins.build(*shaft_, work_.occluders, small, closedInstance_, sampler_.triangles_);
        local_.setupMs = msSince(setupStart_);
    }

    void addCounts(const TilePassCounts& counts)
    {
        local_.pairs += counts.pairs;
        local_.debug.floatPairs += counts.floatPairs;
        local_.debug.floatFallbacks += counts.floatFallbacks;
        local_.debug.narrowedAway += counts.narrowedAway;
    }

    /// A few tiles (probeTilesPerMethod) by bitmask and as many by rays, a batch of each at a time,
    /// timed; their rows are final either way. Pairs of neighbouring tiles drawn at random over the
    /// whole receiver, one of each to each method (probeTiles): in row order the first batches
    /// would all lie along one edge (a floor's edge by the wall costs nothing either way), and
    /// tiles drawn independently for each method differ in work. The rest of the tiles go to the
    /// method the verdict picks.
    void probeTilesAndFinish()
    {
        TileBins& bins = work_.bins;
        ProbeTiles split = probeTiles(bins.tileCount(), std::size_t(bins.tilesA()), probeTilesPerMethod(bins.tileCount()));
        const std::vector<std::uint32_t>& bitmaskTiles = split.bitmask;
        const std::vector<std::uint32_t>& rayTiles = split.rays;
        std::vector<std::uint32_t>& rest = split.rest;
        sampler_.wholeSceneCaster(), sampler_.provenCaster();
        std::vector<int> samples;
        const RayCastOptions rayOptions{.jitter = options_.jitter, .receiverSubset = &samples};
        const std::size_t batch = std::max<std::size_t>(4, 2 * std::size_t(tbb::this_task_arena::max_concurrency()));
        std::size_t bitmaskDone = 0, rayDone = 0;
        double bitmaskMs = 0.0, rayMs = 0.0;
        // Each method's work per tile (Strategy.h, probeShare): the bitmask's bin entries, and the
        // rays still free (the inner proxies may have answered many).
        std::vector<double> rayUnits(bins.tileCount());
        double bitmaskTotal = 0.0, rayTotal = 0.0;
        for (std::size_t t = 0; t < bins.tileCount(); ++t) {
            samples.clear();
            bins.tileSamples(t, receiver_.na, receiver_.nb, samples);
            for (int j : samples)
                rayUnits[t] += double(source_.sampleCount() - std::as_const(map_).blockedCount(j));
            bitmaskTotal += double(bins.bin(t).size()), rayTotal += rayUnits[t];
        }
        double bitmaskProbed = 0.0, rayProbed = 0.0;
        const auto parts = [&] {
            return std::pair(ProbePart{bitmaskMs, probeShare(bitmaskProbed, bitmaskTotal, bitmaskDone, bins.tileCount())},
                             ProbePart{rayMs, probeShare(rayProbed, rayTotal, rayDone, bins.tileCount())});
        };
        while (bitmaskDone < bitmaskTiles.size() || rayDone < rayTiles.size()) {
            if (bitmaskDone < bitmaskTiles.size()) {
                const std::size_t end = std::min(bitmaskDone + batch, bitmaskTiles.size());
                const std::vector<std::uint32_t> part(bitmaskTiles.begin() + std::ptrdiff_t(bitmaskDone),
                                                      bitmaskTiles.begin() + std::ptrdiff_t(end));
                bitmaskMs += onOneThread([&] { addCounts(bitmaskPass(*shaft_, bins, map_, narrow_, &part)); });
                for (std::uint32_t t : part)
                    bitmaskProbed += double(bins.bin(t).size());
                bitmaskDone = end;
            }
            if (rayDone < rayTiles.size()) {
                const std::size_t end = std::min(rayDone + batch, rayTiles.size());
                samples.clear();
                for (std::size_t k = rayDone; k < end; ++k) {
                    bins.tileSamples(rayTiles[k], receiver_.na, receiver_.nb, samples);
                    rayProbed += rayUnits[rayTiles[k]];
                }
                const auto start = Clock::now();
                rayMs += onOneThread([&] { castRays(rayOptions); });
                local_.rayMs += msSince(start);
                rayDone = end;
            }
            if (const auto [bitmask, rays] = parts(); probeIsDecided(bitmask, bitmaskDone, rays, rayDone, batch))
                break;
        }
        rest.insert(rest.end(), bitmaskTiles.begin() + std::ptrdiff_t(bitmaskDone), bitmaskTiles.end());
        rest.insert(rest.end(), rayTiles.begin() + std::ptrdiff_t(rayDone), rayTiles.end());
        local_.debug.probed = true;
        const auto [bitmaskPart, rayPart] = parts();
        const ProbeVerdict verdict = probeVerdict(bitmaskPart, rayPart, setupThreadMs_, warmGrids_);
        remember(verdict.memoRays, verdict.memoCalls, /*measured=*/true);
        if (!verdict.restByRays) {
            local_.strategy = "bitmask";
            addCounts(bitmaskPass(*shaft_, bins, map_, narrow_, &rest));
        } else {
            local_.strategy = "raycast";
            samples.clear();
            for (std::uint32_t t : rest)
                bins.tileSamples(t, receiver_.na, receiver_.nb, samples);
            const auto restStart = Clock::now();
            castRays(rayOptions);
            local_.rayMs += msSince(restStart);
        }
    }

    /// The bitmask pass over every tile; timed against the swapped probe's rays when asked.
    void runBitmask()
    {
        if (!timeSwappedBitmask_) {
            addCounts(bitmaskPass(*shaft_, work_.bins, map_, narrow_));
            return;
        }
        const double passMs = onOneThread([&] { addCounts(bitmaskPass(*shaft_, work_.bins, map_, narrow_)); });
        local_.debug.probeBitmaskMs = setupThreadMs_ + passMs;
        const bool rays = swappedMeasuredChoosesRays(local_.debug.probeRayMs, setupThreadMs_, passMs);
        remember(rays, !warmGrids_ ? 0 : rays ? swappedRaysMemoCalls(local_.debug.probeRayMs, local_.debug.probeBitmaskMs) : kProbeReuse,
                 /*measured=*/true);
    }

    /// The hybrid's ray pass: the still-unblocked rays against a BVH of the small triangles only.
    void castSmallTriangles()
    {
        const auto rayStart = Clock::now();
        const WorldTriangles& triangles = sampler_.triangles_;
        WorldTriangles subset;
        subset.vertices.reserve(3 * smallTriangles_.size());
        for (std::uint32_t t : smallTriangles_) {
            subset.vertices.insert(subset.vertices.end(), &triangles.vertices[3 * t], &triangles.vertices[3 * t] + 3);
            subset.instanceOf.push_back(triangles.instanceOf[t]);
        }
        const RayCastScene rays(subset, /*fastBuild=*/true);
        local_.raysCast = rays.sampleUnblocked(source_, receiver_, map_, {.jitter = options_.jitter, .heights = options_.heights});
        local_.rayMs = msSince(rayStart);
    }

    const CpuBitmaskSampler& sampler_;
    const Patch& source_;
    const Patch& receiver_;
    const BitmaskOptions& options_;
    const bool swappedRoles_;
    HiddenSampleMap& map_;
    BitmaskStats& local_;
    Workspace& work_;
    const bool exact_, narrow_;
    const CpuStrategy strategy_;

    bool bumpy_ = false;
    std::vector<glm::dvec3> displaced_;
    Bounds displacedBox_;
    glm::dvec3 normal_{0.0};
    double lowest_ = 0.0, highest_ = 0.0;
    Clock::time_point setupStart_;
    std::shared_ptr<const HoughMaskTable> table_;

    std::optional<Shaft> shaft_;
    std::optional<ShaftHull> hull_;
    TriangleFilter filter_;
    std::vector<char> closedInstance_;
    tbb::task_arena one_{1};

    Plan plan_ = Plan::Bitmask;
    bool warmGrids_ = false;            ///< Auto sampled these grids before: a probe's times are what later calls pay
    std::vector<int> raySamples_;       ///< the receiver samples left to cast after the swapped probe, when not all
    bool timeSwappedBitmask_ = false;   ///< against the swapped probe's rays, local_.probeRayMs
    bool timed_ = false;                ///< setup and passes timed on one thread, for a verdict
    double setupThreadMs_ = 0.0;
    std::vector<std::uint32_t> smallTriangles_;   ///< the hybrid's, as indices into the world triangles
};

HiddenSampleMap CpuBitmaskSampler::sampleOriented(const Patch& source, const Patch& receiver, const BitmaskOptions& options,
                                                  BitmaskStats* stats, bool swappedRoles) const
{
    HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
    BitmaskStats local;
    std::unique_ptr<Workspace> work = takeWorkspace();
    {
        OrientedCall call(*this, source, receiver, options, swappedRoles, map, local, *work);
        if (options.threads > 0) {
            tbb::task_arena arena(options.threads);
            arena.execute([&] { call.run(); });
        } else {
            call.run();
        }
    }
    returnWorkspace(std::move(work));
    if (stats)
        *stats = local;
    return map;
}

} // namespace sightline
