#include "visibility/RayDisagreement.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <utility>

#include "visibility/ExactJudge.h"

namespace sightline {

namespace {

/// Every difference an error, sorted by the exact map (no judge, or too many to judge).
void sortUnjudged(const HiddenSampleMap& exact, const HiddenSampleMap& approximate, RayDisagreement& out)
{
    for (int j = 0; j < exact.receiverCount(); ++j) {
        const auto e = exact.row(j), a = approximate.row(j);
        const auto fb = out.falseBlocked.row(j), ff = out.falseFree.row(j);
        for (std::size_t w = 0; w < e.size(); ++w) {
            fb[w] = a[w] & ~e[w];
            ff[w] = e[w] & ~a[w];
            out.falseBlockedCount += std::uint64_t(std::popcount(fb[w]));
            out.falseFreeCount += std::uint64_t(std::popcount(ff[w]));
        }
    }
}

void sortJudged(const HiddenSampleMap& exact, const HiddenSampleMap& approximate, const ExactJudge& judge,
                RayDisagreement& out)
{
    std::vector<std::pair<int, int>> differ;
    for (int j = 0; j < exact.receiverCount(); ++j) {
        const auto e = exact.row(j), a = approximate.row(j);
        for (std::size_t w = 0; w < e.size(); ++w)
            for (std::uint64_t bits = e[w] ^ a[w]; bits; bits &= bits - 1)
                differ.emplace_back(j, int(64 * w) + std::countr_zero(bits));
    }
    if (differ.empty())
        return;
    const std::vector<RayKind> kinds = judge.kinds(differ);
    for (std::size_t k = 0; k < differ.size(); ++k) {
        const auto [j, i] = differ[k];
        const bool approximateBlocks = approximate.blocked(j, i);
        switch (kinds[k]) {
        case RayKind::Free:
            if (approximateBlocks)
                out.falseBlocked.setBlocked(j, i), ++out.falseBlockedCount;
            else
                ++out.exactErrors;
            break;
        case RayKind::Blocked:
            if (!approximateBlocks)
                out.falseFree.setBlocked(j, i), ++out.falseFreeCount;
            else
                ++out.exactErrors;
            break;
        case RayKind::EdgeTie:
        case RayKind::EndTie: out.ties.setBlocked(j, i), ++out.tieCount; break;
        }
    }
}

/// Which coarse sample's cell holds full sample k of n (cells of equal width on both grids).
int coarseCell(int k, int n, int coarseN) { return std::min(int((k + 0.5) / n * coarseN), coarseN - 1); }

} // namespace

RayDisagreement rayDisagreement(const HiddenSampleMap& exact, const HiddenSampleMap& approximate, const ExactJudge* judge,
                                std::uint64_t maxJudged)
{
    assert(exact.sourceCount() == approximate.sourceCount() && exact.receiverNa() == approximate.receiverNa() &&
           exact.receiverNb() == approximate.receiverNb());
    RayDisagreement out;
    out.rays = exact.rayCount();
    out.falseBlocked = out.falseFree = out.ties = HiddenSampleMap(exact.sourceCount(), exact.receiverNa(), exact.receiverNb());
    out.judged = judge && exact.differenceCount(approximate) <= maxJudged;
    if (out.judged)
        sortJudged(exact, approximate, *judge, out);
    else
        sortUnjudged(exact, approximate, out);
    return out;
}

Patch withFewerSamples(const Patch& patch, int factor)
{
    assert(factor >= 1);
    Patch coarse = patch;
    coarse.na = std::max(1, (patch.na + factor - 1) / factor);
    coarse.nb = std::max(1, (patch.nb + factor - 1) / factor);
    return coarse;
}

HiddenSampleMap spreadToFullGrids(const HiddenSampleMap& coarse, const Patch& coarseSource, const Patch& coarseReceiver,
                                  const Patch& source, const Patch& receiver)
{
    assert(coarse.sourceCount() == coarseSource.sampleCount() && coarse.receiverNa() == coarseReceiver.na &&
           coarse.receiverNb() == coarseReceiver.nb);
    std::vector<int> coarseSourceOf(std::size_t(source.sampleCount()));
    for (int i = 0; i < source.sampleCount(); ++i)
        coarseSourceOf[std::size_t(i)] = coarseCell(i / source.na, source.nb, coarseSource.nb) * coarseSource.na +
                                         coarseCell(i % source.na, source.na, coarseSource.na);
    HiddenSampleMap full(source.sampleCount(), receiver.na, receiver.nb);
    for (int b = 0; b < receiver.nb; ++b)
        for (int a = 0; a < receiver.na; ++a) {
            const int coarseJ = coarseCell(b, receiver.nb, coarseReceiver.nb) * coarseReceiver.na +
                                coarseCell(a, receiver.na, coarseReceiver.na);
            const int j = b * receiver.na + a;
            for (int i = 0; i < source.sampleCount(); ++i)
                if (coarse.blocked(coarseJ, coarseSourceOf[std::size_t(i)]))
                    full.setBlocked(j, i);
        }
    return full;
}

namespace {

/// What one ray is in the picture; higher values win within a block of rays.
enum Shade : std::uint8_t { AgreedFree, AgreedBlocked, Tie, FalseFree, FalseBlocked };

Shade shadeOf(const HiddenSampleMap& exact, const RayDisagreement& d, int j, int i)
{
    if (d.falseBlocked.blocked(j, i))
        return FalseBlocked;
    if (d.falseFree.blocked(j, i))
        return FalseFree;
    if (d.ties.blocked(j, i))
        return Tie;
    return exact.blocked(j, i) ? AgreedBlocked : AgreedFree;
}

void putPixel(std::vector<std::uint8_t>& rgb, int width, int x, int y, const std::uint8_t colour[3])
{
    std::copy(colour, colour + 3, rgb.begin() + (std::ptrdiff_t(y) * width + x) * 3);
}

} // namespace

DisagreementImage disagreementImage(const HiddenSampleMap& exact, const RayDisagreement& disagreement, int sourceNa,
                                    int sourceNb, int maxSide)
{
    assert(sourceNa * sourceNb == exact.sourceCount() && maxSide >= 1);
    static constexpr std::uint8_t kAgreedFree[3] = {236, 234, 224}, kAgreedBlocked[3] = {72, 72, 78},
                                  kGutter[3] = {160, 160, 160};
    const std::uint8_t* colours[] = {kAgreedFree, kAgreedBlocked, kTieRgb, kFalseFreeRgb, kFalseBlockedRgb};
    const int raNa = exact.receiverNa(), raNb = exact.receiverNb();
    DisagreementImage image;
    const long fullWidth = long(raNa) * (sourceNa + 1) - 1, fullHeight = long(raNb) * (sourceNb + 1) - 1;
    if (fullWidth <= maxSide && fullHeight <= maxSide) {
        image.width = int(fullWidth), image.height = int(fullHeight);
        image.rgb.resize(std::size_t(image.width) * std::size_t(image.height) * 3);
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x)
                putPixel(image.rgb, image.width, x, y, kGutter);
        for (int j = 0; j < exact.receiverCount(); ++j)
            for (int i = 0; i < exact.sourceCount(); ++i) {
                const int x = (j % raNa) * (sourceNa + 1) + i % sourceNa, y = (j / raNa) * (sourceNb + 1) + i / sourceNa;
                putPixel(image.rgb, image.width, x, y, colours[shadeOf(exact, disagreement, j, i)]);
            }
        return image;
    }
    // Without gutters: mosaic pixel (x, y) is ray (receiver (x / sna, y / snb), source (x % sna, y % snb)).
    const long mosaicWidth = long(raNa) * sourceNa, mosaicHeight = long(raNb) * sourceNb;
    const int k = int(std::max((mosaicWidth + maxSide - 1) / maxSide, (mosaicHeight + maxSide - 1) / maxSide));
    image.raysPerPixelSide = k;
    image.width = int((mosaicWidth + k - 1) / k), image.height = int((mosaicHeight + k - 1) / k);
    std::vector<std::uint8_t> shade(std::size_t(image.width) * std::size_t(image.height), AgreedFree);
    std::vector<std::uint32_t> blockedIn(shade.size(), 0), raysIn(shade.size(), 0);
    for (long my = 0; my < mosaicHeight; ++my)
        for (long mx = 0; mx < mosaicWidth; ++mx) {
            const int j = int(my / sourceNb) * raNa + int(mx / sourceNa), i = int(my % sourceNb) * sourceNa + int(mx % sourceNa);
            const std::size_t p = std::size_t(my / k) * std::size_t(image.width) + std::size_t(mx / k);
            const Shade s = shadeOf(exact, disagreement, j, i);
            shade[p] = std::max<std::uint8_t>(shade[p], s >= Tie ? s : AgreedFree);
            blockedIn[p] += s == AgreedBlocked;
            ++raysIn[p];
        }
    image.rgb.resize(shade.size() * 3);
    for (std::size_t p = 0; p < shade.size(); ++p) {
        std::uint8_t mixed[3];
        if (shade[p] >= Tie) {
            std::copy(colours[shade[p]], colours[shade[p]] + 3, mixed);
        } else {   // agreement: grey by the share of blocked rays in the block
            const double t = raysIn[p] ? double(blockedIn[p]) / double(raysIn[p]) : 0.0;
            for (int c = 0; c < 3; ++c)
                mixed[c] = std::uint8_t(std::lround((1.0 - t) * kAgreedFree[c] + t * kAgreedBlocked[c]));
        }
        std::copy(mixed, mixed + 3, image.rgb.begin() + std::ptrdiff_t(p) * 3);
    }
    return image;
}

} // namespace sightline
