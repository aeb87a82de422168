#pragma once
// An importance map accumulated over the frames of a project's animation (Eisemann & Décoret §9):
// the CLI's `importance` subcommand and the editor's "Accumulate Animation" both run this.

#include <functional>

#include "project/Animation.h"
#include "project/ProjectSampler.h"
#include "visibility/ImportanceMap.h"

namespace sightline {

struct ImportanceRunResult {
    ImportanceAccumulator accumulator;
    int framesDone = 0;
    bool cancelled = false;
    double sampleMs = 0.0;   ///< sampling time summed over frames
    double totalMs = 0.0;    ///< everything: scene updates, sampling, accumulation
};

/// One frame's importance map over `side`.
ImportanceMap importanceOf(const HiddenSampleMap& map, const Project& frame, ImportanceSide side);

/// Samples frames 0 .. frames-1 of `animation` applied to `project` and accumulates their importance
/// maps over `side`. `progress(done, total)` is called after each frame (may be empty); returning
/// false stops the run (the result keeps the frames done, cancelled = true).
ImportanceRunResult accumulateImportance(ProjectSampler& sampler, const Project& project, const Animation& animation,
                                         int frames, ImportanceSide side,
                                         const std::function<bool(int, int)>& progress = {});

} // namespace sightline
