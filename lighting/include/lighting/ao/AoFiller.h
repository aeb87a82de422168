#pragma once
// Ways to fill the visibility matrix (the exact CPU mode and the paper's depth maps, docs/ao.md,
// plus the Embree baseline): each tests directions [first, last) of a direction set for every
// usable point facing them and sets the visible bits. Directions are independent, so a
// progressive run (AoComputation.h) fills a level's new directions, or any chunk of them, and
// keeps the bits of earlier calls.

#include <atomic>
#include <string>

#include "lighting/ao/AoDirections.h"
#include "lighting/ao/AoGeometry.h"
#include "lighting/ao/VisibilityMatrix.h"

namespace sightline {

/// For a worker thread: `cancel` stops at the next direction (the matrix then holds a partial
/// chunk, which AoComputation discards); `directionsDone` counts finished directions.
struct AoFillControl {
    const std::atomic<bool>* cancel = nullptr;
    std::atomic<int>* directionsDone = nullptr;

    bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
    void finishedOne() const
    {
        if (directionsDone)
            directionsDone->fetch_add(1, std::memory_order_relaxed);
    }
};

class AoFiller {
public:
    virtual ~AoFiller() = default;
    virtual std::string name() const = 0;
    /// Tests directions [first, last) of `set` for `points` (origins set) into `matrix`.
    /// Returns false when cancelled before the end.
    virtual bool fill(const AoPoints& points, const AoDirectionSet& set, int first, int last, VisibilityMatrix& matrix,
                      const AoFillControl& control = {}) = 0;
};

} // namespace sightline
