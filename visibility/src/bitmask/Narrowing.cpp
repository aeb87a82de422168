#include "Narrowing.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "SampleRange.h"

namespace sightline::bitmask {

namespace {

/// Whether the box [sMin, sMax] x [tMin, tMax], widened by `pad`, holds an open sample: centres
/// (a + 0.5) / na, or anywhere in their cell when jittered.
bool boxMayHit(const Shaft& shaft, double sMin, double sMax, double tMin, double tMax, double pad, const SourceBox& box)
{
    if (!(sMin <= box.sMax + pad && sMax >= box.sMin - pad && tMin <= box.tMax + pad && tMax >= box.tMin - pad))
        return false;
    const auto range = shaft.jittered ? cellRange : sampleRange;
    int aFirst, aLast, bFirst, bLast;
    range(sMin - pad, sMax + pad, shaft.na, aFirst, aLast);
    range(tMin - pad, tMax + pad, shaft.nb, bFirst, bLast);
    if (aFirst > aLast || bFirst > bLast)
        return false;
    for (int b = bFirst; b <= bLast; ++b)
        if (box.anyOpen(b * shaft.na + aFirst, b * shaft.na + aLast))
            return true;
    return false;
}

} // namespace

bool SourceBox::anyOpen(int first, int last) const
{
    const int w0 = first >> 6, w1 = last >> 6;
    const std::uint64_t lo = ~std::uint64_t(0) << (first & 63);
    const std::uint64_t hi = ~std::uint64_t(0) >> (63 - (last & 63));
    if (w0 == w1)
        return (open[std::size_t(w0)] & lo & hi) != 0;
    if (open[std::size_t(w0)] & lo)
        return true;
    for (int w = w0 + 1; w < w1; ++w)
        if (open[std::size_t(w)])
            return true;
    return (open[std::size_t(w1)] & hi) != 0;
}

SourceBox unblockedBox(const Shaft& shaft, const HiddenSampleMap& map, int a0, int a1, int b0, int b1)
{
    SourceBox box;
    auto& open = box.open;
    const int words = map.wordsPerRow(), na = shaft.na, nb = shaft.nb, S = shaft.S;
    for (int b = b0; b <= b1; ++b)
        for (int a = a0; a <= a1; ++a) {
            const auto row = map.row(b * shaft.rna + a);
            for (int w = 0; w < words; ++w)
                open[std::size_t(w)] |= ~row[std::size_t(w)];
        }
    if (S % 64)
        open[std::size_t(words - 1)] &= (std::uint64_t(1) << (S % 64)) - 1;
    int aMin = na, aMax = -1, bMin = nb, bMax = -1;
    if (na <= 64) {
        // Row by row: the rows with an open sample, and the union of their columns.
        std::uint64_t columns = 0;
        for (int b = 0; b < nb; ++b) {
            const int first = b * na, w = first >> 6, shift = first & 63;
            std::uint64_t bits = open[std::size_t(w)] >> shift;
            if (shift + na > 64)
                bits |= open[std::size_t(w) + 1] << (64 - shift);
            if (na < 64)
                bits &= (std::uint64_t(1) << na) - 1;
            if (bits) {
                bMin = std::min(bMin, b), bMax = b;
                columns |= bits;
            }
        }
        if (columns)
            aMin = std::countr_zero(columns), aMax = 63 - std::countl_zero(columns);
    } else {
        for (int w = 0; w < words; ++w)
            for (std::uint64_t bits = open[std::size_t(w)]; bits; bits &= bits - 1) {
                const int i = 64 * w + std::countr_zero(bits);
                const int a = i % na, b = i / na;
                aMin = std::min(aMin, a), aMax = std::max(aMax, a);
                bMin = std::min(bMin, b), bMax = std::max(bMax, b);
            }
    }
    // Jittered samples lie up to half a cell from their cell centres.
    const double lo = shaft.jittered ? 0.0 : 0.5, hi = shaft.jittered ? 1.0 : 0.5;
    if (aMax >= 0) {
        box.sMin = (aMin + lo) / na, box.sMax = (aMax + hi) / na;
        box.tMin = (bMin + lo) / nb, box.tMax = (bMax + hi) / nb;
    }
    return box;
}

bool mayHit(const Shaft& shaft, const Occluder& o, Path path, const int* samples, int sampleCount, const SourceBox& box)
{
    if (path == Path::Clip)
        return true;
    double sMin = 1e300, sMax = -1e300, tMin = 1e300, tMax = -1e300;
    for (int n = 0; n < sampleCount; ++n) {
        const glm::dvec3& r = shaft.receiverInSource[std::size_t(samples[n])];
        for (int i = 0; i < o.count; ++i) {
            const glm::dvec3& x = o.vertices[std::size_t(i)];
            const double k = shaft.parallel ? o.factor[std::size_t(i)] : r.z / (r.z - x.z);
            const double s = r.x + (x.x - r.x) * k, t = r.y + (x.y - r.y) * k;
            sMin = std::min(sMin, s), sMax = std::max(sMax, s);
            tMin = std::min(tMin, t), tMax = std::max(tMax, t);
        }
    }
    // Relative to the projections: a Double-path vertex may lie within the end margin of a
    // sample's distance and project to 1e9.
    const double magnitude = std::max({std::abs(sMin), std::abs(sMax), std::abs(tMin), std::abs(tMax)});
    return boxMayHit(shaft, sMin, sMax, tMin, tMax, 1e-9 * (1.0 + magnitude), box);
}

bool mayHitFloat(const Shaft& shaft, const detail::FloatPolygon& polygon, const std::array<int, 4>& corners,
                 const SourceBox& box)
{
    // The box is padded by the rounding of a backprojection in float from float coordinates
    // with factors k up to kMaxFloatFactor: per vertex about u (2k |r| + (2k + 2) |p - r| + |p|)
    // (BitmaskRows.h), under 70 u (|r| + |p|) = 4.2e-6 (|r| + |p|); 1e-5 taken.
    float rs[4], rt[4], rd[4], bounds[4];
    double magnitude = 0.0;
    for (int c = 0; c < 4; ++c) {
        const std::size_t j = std::size_t(corners[std::size_t(c)]);
        rs[c] = shaft.receiverS[j], rt[c] = shaft.receiverT[j], rd[c] = shaft.receiverD[j];
        magnitude = std::max({magnitude, std::abs(double(rs[c])), std::abs(double(rt[c]))});
    }
    detail::backprojectedBounds(polygon, rs, rt, rd, bounds);
    magnitude += std::max({std::abs(bounds[0]), std::abs(bounds[1]), std::abs(bounds[2]), std::abs(bounds[3])});
    return boxMayHit(shaft, bounds[0], bounds[1], bounds[2], bounds[3], 1e-5 * (1.0 + magnitude), box);
}

} // namespace sightline::bitmask
