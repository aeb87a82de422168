#pragma once
// What an approximation costs, ray by ray: where an approximate hidden-samples map (a Hough table,
// fewer samples, coarse occluders, a GPU pass) answers differently from the exact one. A ray the
// approximation blocks but the exact answer leaves free is *false-blocked*; one it leaves free but
// the exact answer blocks is *false-free*. Each such ray is judged by the contract's brute force
// (ExactJudge.h): within the tie distance (docs/design.md §2) either answer is allowed, so those
// rays are counted apart as ties, never as errors.

#include <cstdint>
#include <vector>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"

namespace sightline {

class ExactJudge;

/// Past this many differing rays the judge is not asked (brute force over each ray's triangles):
/// every difference then counts as an error, and none as a tie.
inline constexpr std::uint64_t kMaxJudgedDisagreements = 50'000;

struct RayDisagreement {
    HiddenSampleMap falseBlocked;   ///< blocked by the approximation only
    HiddenSampleMap falseFree;      ///< blocked by the exact answer only
    HiddenSampleMap ties;           ///< answered differently within the tie distance
    std::uint64_t falseBlockedCount = 0, falseFreeCount = 0, tieCount = 0;
    /// Rays on which the judge sided with the approximation against the exact map (outside ties):
    /// a bug in the exact sampler, reported rather than hidden. Kept in neither map.
    std::uint64_t exactErrors = 0;
    bool judged = false;   ///< the differences went to the judge (false: more than the cap, or no judge)
    std::uint64_t rays = 0;

    std::uint64_t errorCount() const { return falseBlockedCount + falseFreeCount; }
    double errorFraction() const { return rays ? double(errorCount()) / double(rays) : 0.0; }
};

/// Sorts the rays on which `approximate` differs from `exact` (same dimensions). With a judge and
/// at most `maxJudged` differences, each is judged: ties go to `ties`, the rest by the judge's
/// verdict; otherwise every difference is an error, sorted by the exact map.
RayDisagreement rayDisagreement(const HiddenSampleMap& exact, const HiddenSampleMap& approximate,
                                const ExactJudge* judge, std::uint64_t maxJudged = kMaxJudgedDisagreements);

/// The patch with its sample grid made `factor` times coarser along each side (at least one sample).
Patch withFewerSamples(const Patch& patch, int factor);

/// The answer of a sampling between coarser grids, stood in for every ray between the full ones:
/// ray (source i, receiver j) takes the coarse ray between the coarse samples whose cells hold the
/// full samples' centres. `coarse` answers coarseSource -> coarseReceiver.
HiddenSampleMap spreadToFullGrids(const HiddenSampleMap& coarse, const Patch& coarseSource, const Patch& coarseReceiver,
                                  const Patch& source, const Patch& receiver);

/// A picture of every ray: a tile per receiver sample (receiver (a, b) at tile column a, tile row
/// b), in it a pixel per source sample (source (a, b) at column a, row b), one pixel of gutter
/// between tiles. Agreed-free rays are light, agreed-blocked dark, false-blocked red, false-free
/// blue, ties amber. Larger than `maxSide` pixels, it is drawn without gutters at one pixel per
/// k x k rays (the smallest k that fits), a disagreement's colour winning over agreement in its block.
struct DisagreementImage {
    int width = 0, height = 0;
    int raysPerPixelSide = 1;          ///< k: each pixel stands for k x k rays of the mosaic
    std::vector<std::uint8_t> rgb;     ///< width x height x 3, rows top to bottom
};
DisagreementImage disagreementImage(const HiddenSampleMap& exact, const RayDisagreement& disagreement, int sourceNa,
                                    int sourceNb, int maxSide = 4096);

/// The colours of the picture and the editor's disagreement view (sRGB bytes).
inline constexpr std::uint8_t kFalseBlockedRgb[3] = {225, 45, 45};
inline constexpr std::uint8_t kFalseFreeRgb[3] = {40, 120, 245};
inline constexpr std::uint8_t kTieRgb[3] = {240, 190, 40};

} // namespace sightline
