#pragma once
// An importance map accumulated over the frames of a project's animation or recorded path
// (Eisemann & Décoret §9; project/ProjectMotion.h): the CLI's `importance` subcommand and the
// editor's "Accumulate Animation" / "Accumulate Recorded Path" all run this.

#include <functional>

#include "project/Animation.h"
#include "project/ProjectMotion.h"
#include "project/ProjectSampler.h"
#include "visibility/ImportanceMap.h"

namespace sightline {

struct ImportanceRunResult {
    ImportanceAccumulator accumulator;
    int framesDone = 0;
    bool cancelled = false;
    int framesSampled = 0;   ///< frames whose map was sampled (the others repeat the previous frame's)
    double sampleMs = 0.0;   ///< sampling time summed over frames
    double totalMs = 0.0;    ///< everything: scene updates, sampling, accumulation
};

/// One frame's importance map over `side`.
ImportanceMap importanceOf(const HiddenSampleMap& map, const Project& frame, ImportanceSide side);

/// Samples frames 0 .. frames-1 of `motion` applied to `project` and accumulates their importance
/// maps over `side`; a frame where the motion changes nothing (ProjectMotion::mayChangeAt) adds the
/// previous frame's map again without sampling. `progress(done, total)` is called after each frame
/// (may be empty); returning false stops the run (the result keeps the frames done, cancelled = true).
ImportanceRunResult accumulateImportance(ProjectSampler& sampler, const Project& project, const ProjectMotion& motion,
                                         int frames, ImportanceSide side,
                                         const std::function<bool(int, int)>& progress = {});
/// The same over the project's animation.
ImportanceRunResult accumulateImportance(ProjectSampler& sampler, const Project& project, const Animation& animation,
                                         int frames, ImportanceSide side,
                                         const std::function<bool(int, int)>& progress = {});

} // namespace sightline
