#pragma once
// The hidden-samples map (docs/design.md §2): for each receiver sample j, the set B_j of source samples
// whose ray to j is blocked, as a bitset indexed by source bit index i = b * na + a.
//
// Storage is one row of 64-bit words per receiver sample, least significant bit first, so a row's
// bytes in little-endian order are exactly the .npy mask layout of docs/design.md §4 (bit i % 8 of byte
// i / 8). Bits past the source count in a row's last word stay zero (an invariant the counting
// functions rely on).

#include <bit>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace sightline {

class HiddenSampleMap {
public:
    HiddenSampleMap() = default;
    /// An empty map (nothing blocked) for `sourceCount` source samples and a receiver grid of
    /// receiverNa x receiverNb samples (receiver sample (a, b) has index j = b * receiverNa + a).
    HiddenSampleMap(int sourceCount, int receiverNa, int receiverNb);

    int sourceCount() const { return sourceCount_; }
    int receiverNa() const { return receiverNa_; }
    int receiverNb() const { return receiverNb_; }
    int receiverCount() const { return receiverNa_ * receiverNb_; }
    int wordsPerRow() const { return wordsPerRow_; }
    std::uint64_t rayCount() const { return std::uint64_t(sourceCount_) * std::uint64_t(receiverCount()); }

    bool blocked(int receiver, int source) const
    {
        assert(source >= 0 && source < sourceCount_);
        return (row(receiver)[source >> 6] >> (source & 63)) & 1u;
    }
    void setBlocked(int receiver, int source)
    {
        assert(source >= 0 && source < sourceCount_);
        row(receiver)[source >> 6] |= std::uint64_t(1) << (source & 63);
    }

    std::span<std::uint64_t> row(int receiver)
    {
        assert(receiver >= 0 && receiver < receiverCount());
        return {words_.data() + std::size_t(receiver) * wordsPerRow_, std::size_t(wordsPerRow_)};
    }
    std::span<const std::uint64_t> row(int receiver) const
    {
        assert(receiver >= 0 && receiver < receiverCount());
        return {words_.data() + std::size_t(receiver) * wordsPerRow_, std::size_t(wordsPerRow_)};
    }

    /// Blocked source samples seen from one receiver sample.
    int blockedCount(int receiver) const;
    /// All blocked rays.
    std::uint64_t blockedCount() const;

    /// Number of rays blocked in exactly one of the two maps (their XOR). Same dimensions required.
    std::uint64_t differenceCount(const HiddenSampleMap& other) const;

    bool operator==(const HiddenSampleMap& other) const = default;

    /// The same rays with the patches' roles swapped: `this` is a map whose receiver grid is
    /// the other map's source grid, and whose sources are the other map's receiver grid of
    /// na x nb samples (sourceCount() must be na * nb); ray (receiver j, source i) here is ray
    /// (receiver i, source j) there.
    HiddenSampleMap withRolesSwapped(int na, int nb) const;

private:
    int sourceCount_ = 0;
    int receiverNa_ = 0;
    int receiverNb_ = 0;
    int wordsPerRow_ = 0;
    std::vector<std::uint64_t> words_;
};

} // namespace sightline
