#include "lighting/ao/AoComputation.h"

#include <algorithm>

namespace sightline {

AoComputation::AoComputation(AoFiller& filler, const AoPoints& points, int targetK)
    : filler_(filler), points_(points), set_(aoDirections(targetK)), targetK_(targetK), matrix_(points.size(), targetK)
{
}

int AoComputation::completedK() const
{
    int k = 0;
    for (int level : kAoDirectionCounts)
        if (level <= done_)
            k = level;
    return k;
}

bool AoComputation::step(int maxDirections, const AoFillControl& control)
{
    const int last = std::min(targetK_, done_ + std::max(1, maxDirections));
    if (done_ >= last)
        return true;
    if (!filler_.fill(points_, set_, done_, last, matrix_, control))
        return false;
    done_ = last;
    return true;
}

bool AoComputation::refineLevel(const AoFillControl& control)
{
    for (int level : kAoDirectionCounts)
        if (level > done_ && level <= targetK_)
            return step(level - done_, control);
    return true;
}

bool AoComputation::run(const AoFillControl& control)
{
    while (!finished())
        if (!refineLevel(control))
            return false;
    return true;
}

} // namespace sightline
