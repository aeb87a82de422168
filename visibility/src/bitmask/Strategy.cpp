#include "Strategy.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>

namespace sightline::bitmask {

namespace {

/// One prediction under this fraction of the other is clear-cut.
constexpr double kClearCut = 0.5;
/// Below this many receiver samples (16 tiles of 8x8) a probe's tiles are too few to tell.
constexpr int kProbeMinSamples = 32 * 32;
/// The probe needs every triangle binned to its tiles first (about estimated pairs / 64 entries,
/// 4 bytes each): above this many, the prediction decides.
constexpr std::uint64_t kProbeMaxBinEntries = std::uint64_t(40) << 20;
/// The SIMD kernel's rows hold up to 32 source columns (BitmaskRows.h).
constexpr int kSwapMaxColumns = 32;

} // namespace

const CostModel& measuredCosts(bool floatKernel)
{
    // docs/benchmarks.md, "Auto's cost model": least squares on the logarithms over the bench
    // scenes (the bitmask: 2 threads; ray casting: the medians of three runs of one thread's
    // processor time, times 0.40, the median ratio of the bitmask's predictions to its one-thread
    // times over the same runs; fitted by scripts/fit_auto_costs.py to the caster's
    // occlusion traversal); the double kernel's pairs cost about four times the float kernel's.
    static const CostModel simd{.setupNsPerTriangle = 400.0, .passNsPerPair = 2.5, .passFalloff = 0.5,
                                .rayLogBase = 3.4861, .rayLogTriangles = 0.1329, .rayLogPairs = 0.5658,
                                .rayLogPairs2 = -0.0854, .rayLogSide = -0.2930, .rayCoverage = -0.8215};
    static const CostModel scalar = [] {
        CostModel m = simd;
        m.passNsPerPair = 10.0;
        return m;
    }();
    return floatKernel ? simd : scalar;
}

double CostModel::passNs(double pairsPerRay) const
{
    // Clamped below: one pair in a thousand rays is no cheaper per pair than one in a hundred.
    return passNsPerPair * std::pow(std::max(pairsPerRay, 0.01) / 4.0, -passFalloff);
}

double CostModel::rayNs(std::uint64_t trianglesInShaft, double pairsPerRay, int receiverSamples, double coverage) const
{
    const double l = std::clamp(std::log1p(std::max(pairsPerRay, 0.0)), 0.0, 7.0);
    const double side = std::sqrt(double(std::max(receiverSamples, 1)));
    return std::exp(rayLogBase + rayLogTriangles * std::log1p(double(trianglesInShaft)) + rayLogPairs * l +
                    rayLogPairs2 * l * l + rayLogSide * std::log(side) + rayCoverage * std::clamp(coverage, 0.0, 1.0));
}

namespace {

double passMs(const CostEstimate& e, const CostModel& m)
{
    const double pairsPerRay = e.rays > 0 ? double(e.estimatedPairs) / double(e.rays) : 0.0;
    return 1e-6 * m.passNs(pairsPerRay) * double(e.estimatedPairs);
}

} // namespace

double predictedBitmaskMs(const CostEstimate& e, const CostModel& m)
{
    return 1e-6 * m.setupNsPerTriangle * double(e.estimatedTriangles) + passMs(e, m);
}

double predictedRayMs(const CostEstimate& e, const CostModel& m)
{
    const double pairsPerRay = e.rays > 0 ? double(e.estimatedPairs) / double(e.rays) : 0.0;
    const double coverage = e.estimatedTriangles > 0 && e.receiverSamples > 0
                                ? double(e.estimatedPairs) / (double(e.estimatedTriangles) * double(e.receiverSamples))
                                : 0.0;
    const int finer = std::max(e.finerSamples, e.receiverSamples);
    return 1e-6 * m.rayNs(e.estimatedTriangles, pairsPerRay, finer, coverage) * double(e.rays) *
           std::clamp(e.openShare, 0.0, 1.0);
}

bool swapPatchRoles(const Patch& source, const Patch& receiver, const RoleSwapOptions& options)
{
    return options.exact && !options.jittered && !options.bumpy && !options.raysForced &&
           receiver.sampleCount() > source.sampleCount() && receiver.sampleCount() <= kMaxSourceSamples &&
           receiver.na <= kSwapMaxColumns;
}

std::optional<std::pair<int, int>> receiverTilesToSwap(const Patch& source, const Patch& receiver,
                                                       const RoleSwapOptions& options)
{
    if (receiver.sampleCount() <= kMaxSourceSamples)
        return std::nullopt;
    const int columns = (receiver.na + kSwapMaxColumns - 1) / kSwapMaxColumns;
    const int rows = (receiver.nb + kSwapMaxColumns - 1) / kSwapMaxColumns;
    // The smallest tile: the sides split as evenly as they go.
    Patch smallest = receiver;
    smallest.na = receiver.na / columns, smallest.nb = receiver.nb / rows;
    if (!swapPatchRoles(source, smallest, options))
        return std::nullopt;
    return std::pair(columns, rows);
}

void swappedProbeSamples(int receiverSamples, std::vector<int>& probe, std::vector<int>& rest)
{
    std::vector<int> all(std::size_t(std::max(receiverSamples, 0)));
    for (std::size_t k = 0; k < all.size(); ++k)
        all[k] = int(k);
    std::mt19937 scramble(12345);
    std::shuffle(all.begin(), all.end(), scramble);
    const std::size_t count = std::min(all.size(), std::max<std::size_t>(1, all.size() / 8));
    probe.assign(all.begin(), all.begin() + std::ptrdiff_t(count));
    rest.assign(all.begin() + std::ptrdiff_t(count), all.end());
    std::sort(probe.begin(), probe.end());
    std::sort(rest.begin(), rest.end());
}

double swappedRaysWholeMs(double probeMs, std::size_t probed, std::size_t samples)
{
    return probeMs * double(samples) / double(std::max<std::size_t>(probed, 1));
}

SwappedVerdict swappedRaysOrTimeBitmask(double bitmaskPredictedMs, double raysWholeMs)
{
    return raysWholeMs < kSwappedRaysUntimedBelow * bitmaskPredictedMs
               ? SwappedVerdict::Rays
               : SwappedVerdict::TimeBitmask;
}

bool swappedMeasuredChoosesRays(double raysWholeMs, double bitmaskSetupMs, double bitmaskPassMs)
{
    return raysWholeMs < kProbeRaysOverestimate * (bitmaskSetupMs + bitmaskPassMs);
}

int swappedRaysMemoCalls(double raysWholeMs, double bitmaskWholeMs)
{
    const double calls = std::ceil(bitmaskWholeMs / (kSwappedProbeShare * std::max(raysWholeMs, 1e-6)));
    return int(std::clamp(calls, double(kProbeReuse), double(kMaxSwappedReuse)));
}

std::size_t probeTilesPerMethod(std::size_t tiles)
{
    return std::max(tiles / 8, std::min<std::size_t>(4, tiles / 4));
}

Plan planFor(const CostEstimate& e, const CostModel& m)
{
    const double bitmask = predictedBitmaskMs(e, m), rays = predictedRayMs(e, m);
    if (e.swappedRoles)
        return bitmask <= kSwappedBitmaskClearCut * rays ? Plan::Bitmask
               : bitmask >= kSwappedRaysClearCut * rays  ? Plan::RayCast
                                                          : Plan::Probe;
    if (bitmask <= kClearCut * rays)
        return Plan::Bitmask;
    if (rays <= kClearCut * bitmask)
        return Plan::RayCast;
    const bool probe = !e.bumpy && e.receiverSamples >= kProbeMinSamples && e.estimatedPairs / 64 <= kProbeMaxBinEntries;
    if (probe)
        return Plan::Probe;
    return bitmask <= rays ? Plan::Bitmask : Plan::RayCast;
}

double probeShare(double probedUnits, double totalUnits, std::size_t probedTiles, std::size_t tiles)
{
    const double byTiles = double(probedTiles) / double(std::max<std::size_t>(tiles, 1));
    if (!(probedUnits > 0.0 && totalUnits >= probedUnits))
        return byTiles;
    return 0.5 * (probedUnits / totalUnits + byTiles);
}

bool probeIsDecided(const ProbePart& bitmask, std::size_t bitmaskTiles, const ProbePart& rays, std::size_t rayTiles,
                    std::size_t batch)
{
    if (bitmaskTiles < 2 * batch || rayTiles == 0)
        return false;
    // Once one method costs twice the other, or the probe has cost a tenth of what the faster
    // would take for the whole receiver.
    const double wholeBitmask = bitmask.wholeMs(), wholeRays = rays.wholeMs();
    return wholeBitmask > 2.0 * wholeRays || wholeRays > 2.0 * wholeBitmask ||
           bitmask.ms + rays.ms > 0.1 * std::min(wholeBitmask, wholeRays);
}

bool probeChoosesRays(const ProbePart& bitmask, const ProbePart& rays, double bitmaskSetupMs)
{
    return rays.wholeMs() < bitmaskSetupMs + bitmask.wholeMs();
}

ProbeTiles probeTiles(std::size_t tiles, std::size_t tilesA, std::size_t perMethod)
{
    tilesA = std::max<std::size_t>(tilesA, 1);
    const std::size_t rows = (tiles + tilesA - 1) / tilesA;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    if (tilesA >= 2) {
        for (std::size_t b = 0; b < rows; ++b)
            for (std::size_t a = 0; a + 1 < tilesA && b * tilesA + a + 1 < tiles; a += 2)
                pairs.emplace_back(std::uint32_t(b * tilesA + a), std::uint32_t(b * tilesA + a + 1));
    } else {
        for (std::size_t b = 0; b + 1 < tiles; b += 2)
            pairs.emplace_back(std::uint32_t(b), std::uint32_t(b + 1));
    }
    std::mt19937 scramble(12345);
    std::shuffle(pairs.begin(), pairs.end(), scramble);
    ProbeTiles out;
    std::vector<char> probed(tiles, 0);
    for (std::size_t k = 0; k < std::min(perMethod, pairs.size()); ++k) {
        const auto [first, second] = pairs[k];
        out.bitmask.push_back(k % 2 == 0 ? first : second);
        out.rays.push_back(k % 2 == 0 ? second : first);
        probed[first] = probed[second] = 1;
    }
    for (std::size_t t = 0; t < tiles; ++t)
        if (!probed[t])
            out.rest.push_back(std::uint32_t(t));
    return out;
}

ProbeVerdict probeVerdict(const ProbePart& bitmask, const ProbePart& rays, double bitmaskSetupMs, bool warm)
{
    return {.restByRays = rays.wholeMs() < bitmask.wholeMs(),
            .memoRays = probeChoosesRays(bitmask, rays, bitmaskSetupMs),
            .memoCalls = warm ? kProbeReuse : 0};
}

bool similarConfiguration(const Configuration& a, const Configuration& b)
{
    const auto sameGrid = [](const Patch& x, const Patch& y) { return x.na == y.na && x.nb == y.nb; };
    if (!sameGrid(a.source, b.source) || !sameGrid(a.receiver, b.receiver) || a.jittered != b.jittered ||
        a.bumpy != b.bumpy || a.floatKernel != b.floatKernel)
        return false;
    const double distance = glm::length(a.receiver.centre() - a.source.centre());
    const double cos10 = std::cos(10.0 * M_PI / 180.0);
    for (const auto& [x, y] : {std::pair(a.source, b.source), std::pair(a.receiver, b.receiver)}) {
        if (glm::dot(x.normal(), y.normal()) < cos10)
            return false;
        if (glm::length(x.centre() - y.centre()) > 0.2 * distance)
            return false;
        for (const auto& [e, f] : {std::pair(x.u, y.u), std::pair(x.v, y.v)})
            if (std::abs(glm::length(e) - glm::length(f)) > 0.2 * glm::length(e))
                return false;
    }
    return true;
}

} // namespace sightline::bitmask
