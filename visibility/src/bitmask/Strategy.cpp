#include "Strategy.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace sightline::bitmask {

namespace {

/// Auto picks RayCast when estimated pairs exceed this many times the rays. Scalar kernel: on the
/// demo a pair costs about half a ray. SIMD kernel: the crossover lies near 8 estimated pairs per
/// ray on the demo and the dense mesh (README, "Scene kinds"); 6 leans towards ray casting.
constexpr double kPairsPerRay = 2.0;
constexpr double kPairsPerRayFloat = 6.0;
/// Between kPairsPerRayFloat and this many estimated pairs per ray, Auto measures both methods
/// (the estimate does not see the narrowed shaft).
constexpr double kProbePairsPerRay = 20.0;
/// Below 64x64 receiver samples the probe's own cost (a batch of each method) is a large part of
/// the answer: the estimate decides there.
constexpr int kProbeMinSamples = 64 * 64;
/// The probe needs every triangle binned to its tiles first (about estimated pairs / 64 entries,
/// 4 bytes each): above this many, the estimate decides.
constexpr std::uint64_t kProbeMaxBinEntries = std::uint64_t(40) << 20;

} // namespace

Plan planFor(const CostEstimate& e)
{
    const double pairsPerRay = double(e.estimatedPairs) / double(std::max<std::uint64_t>(e.rays, 1));
    if (pairsPerRay <= (e.floatKernel ? kPairsPerRayFloat : kPairsPerRay))
        return Plan::Bitmask;
    const bool probe = pairsPerRay < kProbePairsPerRay && e.floatKernel && !e.bumpy &&
                       e.receiverSamples >= kProbeMinSamples && e.estimatedPairs / 64 <= kProbeMaxBinEntries;
    return probe ? Plan::Probe : Plan::RayCast;
}

bool probeIsDecided(std::size_t bitmaskTiles, double bitmaskMs, std::size_t rayTiles, double rayMs, std::size_t tiles,
                    std::size_t batch)
{
    if (bitmaskTiles < 2 * batch || rayTiles == 0)
        return false;
    // Once one method costs twice the other per tile, or the probe has cost a tenth of what the
    // faster would take for the whole receiver.
    const double perBitmask = bitmaskMs / double(bitmaskTiles), perRay = rayMs / double(rayTiles);
    const double wholeFaster = std::min(perBitmask, perRay) * double(tiles);
    return perBitmask > 2.0 * perRay || perRay > 2.0 * perBitmask || bitmaskMs + rayMs > 0.1 * wholeFaster;
}

bool probeChoosesRays(std::size_t bitmaskTiles, double bitmaskMs, std::size_t rayTiles, double rayMs)
{
    return bitmaskMs / double(std::max<std::size_t>(bitmaskTiles, 1)) > rayMs / double(std::max<std::size_t>(rayTiles, 1));
}

bool similarConfiguration(const Configuration& a, const Configuration& b)
{
    const auto sameGrid = [](const Patch& x, const Patch& y) { return x.na == y.na && x.nb == y.nb; };
    if (!sameGrid(a.source, b.source) || !sameGrid(a.receiver, b.receiver) || a.jittered != b.jittered ||
        a.bumpy != b.bumpy)
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
