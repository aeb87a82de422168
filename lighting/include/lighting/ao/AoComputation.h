#pragma once
// A progressive visibility-matrix computation (Sattler et al. 2004 §3.4): directions are filled in
// the light sphere's order, so k = 6 -> 18 -> 66 -> 258 -> 1026 each reuse every bit of the level
// before and only test the new directions. A worker thread drives it level by level (refineLevel)
// or in chunks of a few directions (step), with a cancel flag and a progress count (AoFillControl);
// after each call, completedK() names the finest complete level, whose AO or relit colours can be
// shown at once (AoShading.h) while the next level is computed.
//
// Threading: step() and refineLevel() write the matrix; read it (or copy it) from the driving
// thread between calls. Bits of directions below directionsDone() never change again.

#include "lighting/ao/AoFiller.h"

namespace sightline {

class AoComputation {
public:
    /// `points` must outlive the computation and have their origins set; throws sightline::Error
    /// for a `targetK` outside the light sphere's counts.
    AoComputation(AoFiller& filler, const AoPoints& points, int targetK);

    int targetK() const { return targetK_; }
    /// The finest level all of whose directions are done (0 before the first level completes).
    int completedK() const;
    int directionsDone() const { return done_; }
    bool finished() const { return done_ == targetK_; }

    /// Fills up to `maxDirections` further directions. Returns false when cancelled (the chunk is
    /// then not counted and is redone by the next call).
    bool step(int maxDirections, const AoFillControl& control = {});
    /// Fills the rest of the next level (6, then 18, ...). Returns false when cancelled.
    bool refineLevel(const AoFillControl& control = {});
    /// Runs to the target k.
    bool run(const AoFillControl& control = {});

    const VisibilityMatrix& matrix() const { return matrix_; }
    const AoDirectionSet& directions() const { return set_; }
    const AoPoints& points() const { return points_; }

private:
    AoFiller& filler_;
    const AoPoints& points_;
    const AoDirectionSet& set_;
    int targetK_;
    int done_ = 0;
    VisibilityMatrix matrix_;
};

} // namespace sightline
