#include "RayPackets.h"

#include <numeric>
#include <string>

#include "base/Error.h"

namespace sightline::raycast {

SampleEnds::SampleEnds(const Patch& source_, const Patch& receiver_, const ReceiverHeights* heights_)
    : receiver(receiver_), heights(heights_)
{
    if (heights)
        validateReceiverHeights(source_, receiver, *heights);
    bumpy = !flatReceiver(heights);
    if (bumpy)
        normal = receiverNormalTowardSource(source_, receiver);
    source.resize(std::size_t(source_.sampleCount()));
    for (int i = 0; i < source_.sampleCount(); ++i)
        source[std::size_t(i)] = source_.sample(i);
}

std::vector<int> packetOrder(const Patch& source)
{
    const int S = source.sampleCount();
    std::vector<int> order(static_cast<std::size_t>(S));
    std::iota(order.begin(), order.end(), 0);
    if (source.na % 4 == 0 && source.nb % 4 == 0)
        for (int k = 0; k < S; ++k) {
            const int block = k / 16, within = k % 16, blocksAcross = source.na / 4;
            order[std::size_t(k)] = ((block / blocksAcross) * 4 + within / 4) * source.na + (block % blocksAcross) * 4 + within % 4;
        }
    return order;
}

std::vector<std::vector<int>> receiverBlocks(const Patch& receiver, const std::vector<int>* subset)
{
    const int blocksA = (receiver.na + 3) / 4, blocksB = (receiver.nb + 3) / 4;
    std::vector<std::vector<int>> byBlock(std::size_t(blocksA) * std::size_t(blocksB));
    const int count = subset ? int(subset->size()) : receiver.sampleCount();
    for (int k = 0; k < count; ++k) {
        const int j = subset ? (*subset)[std::size_t(k)] : k;
        if (j < 0 || j >= receiver.sampleCount())
            throw Error("receiver sample " + std::to_string(j) + " is outside the grid");
        byBlock[std::size_t((j / receiver.na / 4) * blocksA + (j % receiver.na) / 4)].push_back(j);
    }
    std::erase_if(byBlock, [](const std::vector<int>& block) { return block.empty(); });
    return byBlock;
}

// (A float filter in front of it, deciding most lanes in single precision, measured slower: the
// callbacks hold few lanes.)
__attribute__((target_clones("avx2", "default"))) void crossedLanes(const TriangleSeenFrom& tri, const double* dx,
                                                                     const double* dy, const double* dz, int count,
                                                                     std::int64_t* hit)
{
    const double margin2 = kEndMarginMetres * kEndMarginMetres;
    for (int i = 0; i < count; ++i) {
        const double w0 = tri.ab.x * dx[i] + tri.ab.y * dy[i] + tri.ab.z * dz[i];
        const double w1 = tri.bc.x * dx[i] + tri.bc.y * dy[i] + tri.bc.z * dz[i];
        const double w2 = tri.ca.x * dx[i] + tri.ca.y * dy[i] + tri.ca.z * dz[i];
        const bool inside = ((w0 >= 0.0) & (w1 >= 0.0) & (w2 >= 0.0)) | ((w0 <= 0.0) & (w1 <= 0.0) & (w2 <= 0.0));
        const double sq = tri.sp + (tri.normal.x * dx[i] + tri.normal.y * dy[i] + tri.normal.z * dz[i]);
        const bool opposite = ((tri.sp > 0.0) & (sq < 0.0)) | ((tri.sp < 0.0) & (sq > 0.0));
        const double t = tri.sp / (tri.sp - sq);   // inf or NaN only where `opposite` is false
        const double length2 = dx[i] * dx[i] + dy[i] * dy[i] + dz[i] * dz[i];
        const bool ends = (t * t * length2 > margin2) & ((1.0 - t) * (1.0 - t) * length2 > margin2);
        hit[i] = std::int64_t(inside & opposite & ends);
    }
}

} // namespace sightline::raycast
