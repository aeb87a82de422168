#include "TilePass.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "DoubleBackprojection.h"
#include "Narrowing.h"
#include "SampleRange.h"

namespace sightline::bitmask {

namespace {

/// Per tile, occluders are tested against the source samples the tile's receiver samples still
/// see (narrowed shaft); that set is recomputed every this many occluders (32 rather than 256:
/// 4% fewer pairs on the 128x128 wall receiver).
constexpr int kNarrowRefresh = 32;

/// The receiver samples of one tile as groups of eight lanes for the SIMD kernel: lane
/// (b - b0) * kTile + (a - a0) is sample (a, b), and group g holds lanes 8 g to 8 g + 7, so
/// kRowsPerGroup whole rows of the tile.
constexpr int kTileLanes = kTile * kTile;
constexpr int kRowsPerGroup = detail::kLanes / kTile;
constexpr int kGroups = kTileLanes / detail::kLanes;
static_assert(detail::kLanes % kTile == 0 && kTileLanes <= 64, "groups of whole tile rows; lane masks in 64 bits");
static_assert(kRowsPerGroup == 1, "a lane group is part of one receiver row");

struct TileLanes {
    detail::LaneGroup group[kGroups];
    std::uint64_t inside = 0;   // per lane: inside the grid
    /// The kernel's row for lanes outside the grid: it only ever ORs zeros into it.
    std::array<std::uint64_t, kMaxSourceSamples / 64> scratch{};
};

/// Fills `lanes` in place: the scratch row's address must stay valid.
void tileLanes(const Shaft& shaft, HiddenSampleMap& map, int a0, int b0, TileLanes& lanes)
{
    lanes.inside = 0;
    for (int lane = 0; lane < kTileLanes; ++lane) {
        const int a = a0 + lane % kTile, b = b0 + lane / kTile;
        const bool inside = a < shaft.rna && b < shaft.rnb;
        // Lanes outside the grid compute with the tile's first sample and are never active: the
        // kernel only ORs zeros into their scratch row.
        const int j = inside ? b * shaft.rna + a : b0 * shaft.rna + a0;
        detail::LaneGroup& g = lanes.group[lane / 8];
        const int l = lane % 8;
        g.s[l] = shaft.receiverS[std::size_t(j)];
        g.t[l] = shaft.receiverT[std::size_t(j)];
        g.d[l] = shaft.receiverD[std::size_t(j)];
        const glm::dvec3& r = shaft.receiverInSource[std::size_t(j)];
        g.sLo[l] = float(r.x - double(g.s[l]));
        g.tLo[l] = float(r.y - double(g.t[l]));
        g.dLo[l] = float(r.z - double(g.d[l]));
        if (l == 0)
            g.sReach = g.tReach = 0.0f;
        g.sReach = std::max(g.sReach, std::abs(g.s[l]));
        g.tReach = std::max(g.tReach, std::abs(g.t[l]));
        g.shiftS[l] = float(shaft.jitterShift[std::size_t(j)].x);
        g.shiftT[l] = float(shaft.jitterShift[std::size_t(j)].y);
        g.shifted = shaft.jittered;
        g.rowCentres = shaft.rowCentres.data();
        g.metresPerS = float(shaft.metresPerS);
        g.metresPerT = float(shaft.metresPerT);
        g.bandBudget = float(kFloatBandBudget);
        g.rows[l] = inside ? map.row(j).data() : lanes.scratch.data();
        lanes.inside |= std::uint64_t(inside) << lane;
    }
}

/// Whether `o`, on `path`, may hide a source sample in `open` from a receiver sample of [a0, a1]
/// x [b0, b1] (Narrowing.h): on a flat receiver from the rectangle's corners, on a bumpy one from
/// every sample (its rectangles are not planar).
bool mayHitFrom(const Shaft& shaft, const TileOccluder& o, Path path, int a0, int a1, int b0, int b1, const SourceBox& open)
{
    const int na = shaft.rna;
    if (!shaft.bumpy) {
        const std::array<int, 4> corners = {b0 * na + a0, b0 * na + a1, b1 * na + a0, b1 * na + a1};
        if (path == Path::Float)
            return mayHitFloat(shaft, o.single, corners, open);
        return mayHit(shaft, *o.occluder, path, corners.data(), 4, open);
    }
    std::array<int, kTile * kTile> samples;
    int count = 0;
    for (int b = b0; b <= b1; ++b)
        for (int a = a0; a <= a1; ++a)
            samples[std::size_t(count++)] = b * na + a;
    return mayHit(shaft, *o.occluder, path, samples.data(), count, open);
}

constexpr int kRankDigitBits = 12;

/// One stable counting-sort pass on the rank's digit at `shift`.
void countingPass(const std::vector<SizeKey>& from, std::vector<SizeKey>& to, int shift)
{
    constexpr std::uint32_t kDigits = 1u << kRankDigitBits;
    std::array<std::uint32_t, kDigits + 1> start{};
    for (const SizeKey& k : from)
        ++start[((k.rank >> shift) & (kDigits - 1)) + 1];
    for (std::uint32_t d = 1; d <= kDigits; ++d)
        start[d] += start[d - 1];
    for (const SizeKey& k : from)
        to[start[(k.rank >> shift) & (kDigits - 1)]++] = k;
}

/// One tile's walk through its bin: its occluders, largest first, each on the cheapest path its
/// samples allow, unless the narrowed shaft rules it out. Counts into `counts`.
struct TileWalk {
    TileWalk(const Shaft& shaft_, const TileBins& bins_, HiddenSampleMap& map_, std::size_t tile_,
             TilePassCounts& counts_);

    void run(bool narrow);

    const Shaft& shaft;
    const TileBins& bins;
    HiddenSampleMap& map;
    TilePassCounts& counts;
    const std::size_t tile;
    const int words, rna;
    int a0, b0, aEnd, bEnd;   ///< the tile's receiver samples [a0, aEnd) x [b0, bEnd)
    TileLanes lanes;
    std::uint64_t full = 0;   ///< per lane: row already full

private:
    /// Switches off the lanes whose rows are full.
    void checkFull();
    /// Backprojects `o` to the tile's samples [ia0, ia1] x [ib0, ib1], a group of the kernel's rows
    /// at a time.
    void backprojectGroups(const TileOccluder& o, Path path, int ia0, int ia1, int ib0, int ib1);
    /// Group g's lanes in columns ia0..ia1 of rows gb0..gb1 (`columns`) through the float kernel;
    /// what it could not prove in double.
    void floatGroup(const TileOccluder& o, int g, int gr0, int gb0, int gb1, unsigned columns);
    /// The samples [ia0, ia1] x [gb0, gb1] whose rows are not full, on `groupPath` (not Float).
    void exactGroup(const TileOccluder& o, Path groupPath, int ia0, int ia1, int gb0, int gb1);
};

TileWalk::TileWalk(const Shaft& shaft_, const TileBins& bins_, HiddenSampleMap& map_, std::size_t tile_,
                   TilePassCounts& counts_)
    : shaft(shaft_), bins(bins_), map(map_), counts(counts_), tile(tile_), words(map_.wordsPerRow()), rna(shaft_.rna)
{
    const int rnb = shaft.rnb;
    const int ta = int(tile % std::size_t(bins.tilesA())), tb = int(tile / std::size_t(bins.tilesA()));
    a0 = ta * kTile, b0 = tb * kTile;
    aEnd = std::min(rna, a0 + kTile), bEnd = std::min(rnb, b0 + kTile);
    if (shaft.floatKernel)
        tileLanes(shaft, map, a0, b0, lanes);
}

void TileWalk::run(bool narrow)
{
    // Lanes whose rows are full are switched off; rechecked every this many float occluders.
    constexpr int kFullRefresh = 32;
    constexpr std::size_t kPrefetch = 4;
    // The source samples the tile still sees. Kept per lane group instead (measured with
    // 4x4 tiles and groups of 2x4), the sets rejected 15% more pairs on the 128x128 wall
    // but cost more than they saved.
    SourceBox open;
    int sinceNarrowed = -1;   // -1: not narrowed yet
    int sinceFullChecked = kFullRefresh;
    const std::vector<std::uint32_t>& tileBin = bins.bin(tile);
    for (std::size_t next = 0; next < tileBin.size(); ++next) {
        if (next + kPrefetch < tileBin.size()) {
            const char* ahead = reinterpret_cast<const char*>(&bins.occluder(tileBin[next + kPrefetch]));
            for (std::size_t line = 0; line < sizeof(TileOccluder); line += 64)
                __builtin_prefetch(ahead + line);
        }
        const TileOccluder& o = bins.occluder(tileBin[next]);
        // This tile's part of the occluder's region, and the cheapest path there.
        const int ia0 = std::max<int>(a0, o.a0), ia1 = std::min<int>(aEnd - 1, o.a1);
        const int ib0 = std::max<int>(b0, o.b0), ib1 = std::min<int>(bEnd - 1, o.b1);
        // (A Float occluder takes the double path where the shaft has no float kernel.)
        const Path path = (o.path == Path::Float && shaft.floatKernel) || shaft.bumpy
                              ? o.path
                              : shaft.pathFor(o.maxD, shaft.nearestSample(ia0, ia1, ib0, ib1));
        if (narrow) {
            if (sinceNarrowed < 0 || sinceNarrowed >= kNarrowRefresh) {
                open = unblockedBox(shaft, map, a0, aEnd - 1, b0, bEnd - 1);
                sinceNarrowed = 0;
                if (open.empty())
                    break;   // the whole tile is blocked
            }
            ++sinceNarrowed;
            if (!mayHitFrom(shaft, o, path, ia0, ia1, ib0, ib1, open)) {
                ++counts.narrowedAway;
                continue;
            }
        }
        if (path == Path::Float && ++sinceFullChecked >= kFullRefresh) {
            checkFull();
            sinceFullChecked = 0;
        }
        backprojectGroups(o, path, ia0, ia1, ib0, ib1);
    }
}

void TileWalk::checkFull()
{
    full = 0;
    for (int lane = 0; lane < kTileLanes; ++lane)
        if ((lanes.inside >> lane & 1) && rowFull(lanes.group[lane / 8].rows[lane % 8], words, shaft.S))
            full |= std::uint64_t(1) << lane;
}

void TileWalk::backprojectGroups(const TileOccluder& o, Path path, int ia0, int ia1, int ib0, int ib1)
{
    // The kernel's groups of kRowsPerGroup rows.
    const unsigned columns = ((2u << (ia1 - a0)) - 1u) & ~((1u << (ia0 - a0)) - 1u);
    for (int g = (ib0 - b0) / kRowsPerGroup; g <= (ib1 - b0) / kRowsPerGroup; ++g) {
        const int gr0 = b0 + kRowsPerGroup * g;
        const int gb0 = std::max(ib0, gr0), gb1 = std::min(ib1, gr0 + kRowsPerGroup - 1);
        // A sloping receiver's group may be well clear of an occluder that reaches the
        // tile's nearest sample (furniture on a floor).
        const Path groupPath = path == Path::Float || shaft.bumpy
                                   ? path
                                   : shaft.pathFor(o.maxD, shaft.nearestSample(ia0, ia1, gb0, gb1));
        if (groupPath == Path::Float) {
            floatGroup(o, g, gr0, gb0, gb1, columns);
            continue;
        }
        exactGroup(o, groupPath, ia0, ia1, gb0, gb1);
    }
}

void TileWalk::floatGroup(const TileOccluder& o, int g, int gr0, int gb0, int gb1, unsigned columns)
{
    // Lanes: columns ia0..ia1 of rows gb0..gb1, inside the grid, not full.
    unsigned active = 0;
    for (int b = gb0; b <= gb1; ++b)
        active |= columns << (kTile * (b - gr0));
    active &= unsigned(~full >> (8 * g) & lanes.inside >> (8 * g));
    unsigned fallback = 0;
    const int n = detail::backprojectRowsAvx2(o.single, lanes.group[g], active, shaft.na, shaft.nb, &fallback);
    counts.pairs += std::uint64_t(n);
    counts.floatPairs += std::uint64_t(n);
    // What the kernel could not prove, in double.
    for (; fallback; fallback &= fallback - 1) {
        const int lane = std::countr_zero(fallback);
        const int j = gr0 * rna + a0 + lane;
        backproject(shaft, *o.occluder, Path::Double, j, map.row(j).data());
        ++counts.pairs;
        ++counts.floatFallbacks;
    }
}

void TileWalk::exactGroup(const TileOccluder& o, Path groupPath, int ia0, int ia1, int gb0, int gb1)
{
    // A receiver row parallel to the source plane (a floor seen from a wall) lies
    // at one distance: one clip serves all its samples. The distance is affine
    // along the row, so its two ends tell.
    const int j0 = gb0 * rna + ia0, j1 = gb1 * rna + ia1;
    const double z0 = shaft.receiverInSource[std::size_t(j0)].z;
    const bool sharedClip = groupPath == Path::Clip && !shaft.bumpy && o.maxD >= Shaft::clipDistance(z0) &&
                            std::abs(shaft.receiverInSource[std::size_t(j1)].z - z0) <= 1e-12 * z0;
    const auto eachOpenRow = [&](const auto& each) {
        for (int b = gb0; b <= gb1; ++b)
            for (int a = ia0; a <= ia1; ++a) {
                const int j = b * rna + a;
                std::uint64_t* row = map.row(j).data();
                if (rowFull(row, words, shaft.S))
                    continue;
                each(j, row);
                ++counts.pairs;
            }
    };
    if (sharedClip) {
        const ClippedPolygon clipped = clippedFor(*o.occluder, z0);
        if (clipped.count >= 3)
            eachOpenRow([&](int j, std::uint64_t* row) {
                backprojectPolygon(shaft, clipped.vertices.data(), clipped.count,
                                   shaft.receiverInSource[std::size_t(j)],
                                   shaft.jitterShift[std::size_t(j)], row, nullptr);
            });
    } else {
        eachOpenRow([&](int j, std::uint64_t* row) { backproject(shaft, *o.occluder, groupPath, j, row); });
    }
}

} // namespace

std::uint32_t sizeRank(double cells)
{
    // A non-negative double's bits order as its value; the top 24 are the (zero) sign bit, 11 of
    // exponent and 12 of mantissa. Negated: largest first.
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(cells > 0.0 ? cells : 0.0);
    return ~std::uint32_t(bits >> 40) & ((1u << (2 * kRankDigitBits)) - 1u);
}

void sortLargestFirst(std::vector<SizeKey>& keys, std::vector<SizeKey>& scratch)
{
    scratch.resize(keys.size());
    countingPass(keys, scratch, 0);
    countingPass(scratch, keys, kRankDigitBits);
}

TilePassCounts& TilePassCounts::operator+=(const TilePassCounts& other)
{
    pairs += other.pairs;
    floatPairs += other.floatPairs;
    floatFallbacks += other.floatFallbacks;
    narrowedAway += other.narrowedAway;
    return *this;
}

void TileBins::build(const Shaft& shaft, const OccluderSet& set, const std::vector<char>& leave,
                     const std::vector<char>& closedInstance, const WorldTriangles& triangles)
{
    const std::vector<const Occluder*>& occluders = set.occluders;
    // Largest first; equal ranks in triangle order, so the order does not depend on the thread
    // count. The order only makes narrowing effective (an occluder is skipped only where all it
    // may hide is hidden already), so sizes within 2^-12 of each other may go either way.
    keys_.clear();
    for (std::size_t i = 0; i < occluders.size(); ++i)
        if (leave.empty() || !leave[i])
            keys_.push_back({sizeRank(occluders[i]->cells), std::uint32_t(i)});
    sortLargestFirst(keys_, keysScratch_);
    order_.resize(keys_.size());
    for (std::size_t n = 0; n < keys_.size(); ++n)
        order_[n] = keys_[n].occluder;
    tilesA_ = (shaft.rna + kTile - 1) / kTile;
    const int tilesB = (shaft.rnb + kTile - 1) / kTile;
    bins_.resize(std::size_t(tilesA_) * std::size_t(tilesB));
    for (auto& tileBin : bins_)
        tileBin.clear();
    tileOccluders_.resize(order_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order_.size(), 1024), [&](const auto& range) {
        constexpr std::size_t kAhead = 4;
        for (std::size_t n = range.begin(); n != range.end(); ++n) {
            // The occluders are read in sorted order, so all over memory: without fetching ahead
            // the conversion below waited on the cache for most of its time (perf annotate).
            if (n + kAhead < range.end()) {
                const char* ahead = reinterpret_cast<const char*>(occluders[order_[n + kAhead]]);
                for (std::size_t line = 0; line < sizeof(Occluder); line += 64)
                    __builtin_prefetch(ahead + line);
            }
            const Occluder& o = *occluders[order_[n]];
            const std::uint32_t instance = triangles.instanceOf[set.triangleOf[order_[n]]];
            const bool closed = !closedInstance.empty() && closedInstance[instance];
            tileOccluders_[n] = {shaft.floatKernel ? floatPolygon(shaft, o, closed) : detail::FloatPolygon{},
                                 std::int16_t(o.a0), std::int16_t(o.a1), std::int16_t(o.b0), std::int16_t(o.b1),
                                 o.path, closed, o.maxD, &o};
        }
    });
    for (std::size_t n = 0; n < order_.size(); ++n) {
        const TileOccluder& o = tileOccluders_[n];
        for (int tb = o.b0 / kTile; tb <= o.b1 / kTile; ++tb)
            for (int ta = o.a0 / kTile; ta <= o.a1 / kTile; ++ta)
                bins_[std::size_t(tb) * std::size_t(tilesA_) + std::size_t(ta)].push_back(std::uint32_t(n));
    }
}

void TileBins::tileSamples(std::size_t tile, int receiverNa, int receiverNb, std::vector<int>& out) const
{
    const int a0 = int(tile % std::size_t(tilesA_)) * kTile, b0 = int(tile / std::size_t(tilesA_)) * kTile;
    for (int b = b0; b < std::min(receiverNb, b0 + kTile); ++b)
        for (int a = a0; a < std::min(receiverNa, a0 + kTile); ++a)
            out.push_back(b * receiverNa + a);
}

TilePassCounts bitmaskPass(const Shaft& shaft, const TileBins& bins, HiddenSampleMap& map, bool narrow,
                           const std::vector<std::uint32_t>* only)
{
    std::atomic<std::uint64_t> narrowedAway{0}, pairs{0}, floatPairs{0}, floatFallbacks{0};
    const std::size_t tileCount = only ? only->size() : bins.tileCount();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tileCount, 1), [&](const auto& range) {
        TilePassCounts counts;
        for (std::size_t k = range.begin(); k != range.end(); ++k)
            TileWalk(shaft, bins, map, only ? (*only)[k] : k, counts).run(narrow);
        pairs += counts.pairs;
        floatPairs += counts.floatPairs;
        narrowedAway += counts.narrowedAway;
        floatFallbacks += counts.floatFallbacks;
    });
    return {pairs, floatPairs, floatFallbacks, narrowedAway};
}

} // namespace sightline::bitmask
