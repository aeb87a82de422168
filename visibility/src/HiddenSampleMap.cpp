#include "visibility/HiddenSampleMap.h"

#include <stdexcept>

namespace sightline {

HiddenSampleMap::HiddenSampleMap(int sourceCount, int receiverNa, int receiverNb)
    : sourceCount_(sourceCount), receiverNa_(receiverNa), receiverNb_(receiverNb),
      wordsPerRow_((sourceCount + 63) / 64)
{
    if (sourceCount < 1 || receiverNa < 1 || receiverNb < 1)
        throw std::invalid_argument("HiddenSampleMap needs at least one source and one receiver sample");
    words_.assign(std::size_t(wordsPerRow_) * std::size_t(receiverNa) * std::size_t(receiverNb), 0);
}

int HiddenSampleMap::blockedCount(int receiver) const
{
    int count = 0;
    for (std::uint64_t word : row(receiver))
        count += std::popcount(word);
    return count;
}

std::uint64_t HiddenSampleMap::blockedCount() const
{
    std::uint64_t count = 0;
    for (std::uint64_t word : words_)
        count += std::uint64_t(std::popcount(word));
    return count;
}

HiddenSampleMap HiddenSampleMap::withRolesSwapped(int na, int nb) const
{
    if (std::int64_t(na) * std::int64_t(nb) != sourceCount_)
        throw std::invalid_argument("HiddenSampleMap::withRolesSwapped: the grid does not match the source count");
    HiddenSampleMap out(receiverCount(), na, nb);
    for (int j = 0; j < receiverCount(); ++j) {
        const std::span<const std::uint64_t> bits = row(j);
        for (std::size_t w = 0; w < bits.size(); ++w)
            for (std::uint64_t word = bits[w]; word; word &= word - 1)
                out.setBlocked(int(64 * w) + std::countr_zero(word), j);
    }
    return out;
}

std::uint64_t HiddenSampleMap::differenceCount(const HiddenSampleMap& other) const
{
    if (other.sourceCount_ != sourceCount_ || other.receiverNa_ != receiverNa_ ||
        other.receiverNb_ != receiverNb_)
        throw std::invalid_argument("HiddenSampleMap::differenceCount: maps of different dimensions");
    std::uint64_t count = 0;
    for (std::size_t i = 0; i < words_.size(); ++i)
        count += std::uint64_t(std::popcount(words_[i] ^ other.words_[i]));
    return count;
}

} // namespace sightline
