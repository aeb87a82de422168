#include "TableMode.h"

#include <algorithm>
#include <utility>

#include "visibility/Patch.h"

namespace sightline::bitmask {

void tableMask(const HoughMaskTable& table, const double* ps, const double* pt, int count, std::uint64_t* mask)
{
    double area = 0.0;
    for (int i = 0, k = count - 1; i < count; k = i++)
        area += ps[k] * pt[i] - ps[i] * pt[k];
    if (area == 0.0)
        return;   // degenerate: covers no area
    std::uint64_t inside[kMaxSourceSamples / 64];
    const int words = table.wordsPerMask();
    std::fill_n(inside, words, ~std::uint64_t(0));
    for (int e = 0; e < count; ++e) {
        int from = e, to = (e + 1) % count;
        if (area < 0.0)
            std::swap(from, to);
        if (ps[from] == ps[to] && pt[from] == pt[to])
            continue;
        const std::uint64_t* edge = table.lookup(ps[from], pt[from], ps[to], pt[to]);
        for (int w = 0; w < words; ++w)
            inside[w] &= edge[w];
    }
    for (int w = 0; w < words; ++w)
        mask[w] |= inside[w];
}

} // namespace sightline::bitmask
