#include "lighting/ao/VisibilityMatrix.h"

#include <bit>

namespace sightline {

std::uint64_t VisibilityMatrix::visibleCount(int k) const
{
    std::uint64_t n = 0;
    const int full = k / 64, rest = k % 64;
    for (std::size_t i = 0; i < points_; ++i) {
        const std::uint64_t* r = row(i);
        for (int w = 0; w < full; ++w)
            n += unsigned(std::popcount(r[w]));
        if (rest)
            n += unsigned(std::popcount(r[full] & ((std::uint64_t(1) << rest) - 1)));
    }
    return n;
}

} // namespace sightline
