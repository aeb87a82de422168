#include "project/ImportanceRun.h"

#include <chrono>

namespace sightline {

ImportanceMap importanceOf(const HiddenSampleMap& map, const Project& frame, ImportanceSide side)
{
    return side == ImportanceSide::Receiver ? receiverImportance(map)
                                            : sourceImportance(map, frame.source.na, frame.source.nb);
}

ImportanceRunResult accumulateImportance(ProjectSampler& sampler, const Project& project, const Animation& animation,
                                         int frames, ImportanceSide side, const std::function<bool(int, int)>& progress)
{
    const auto start = std::chrono::steady_clock::now();
    ImportanceRunResult result;
    for (int f = 0; f < frames; ++f) {
        const Project frame = projectAtFrame(project, animation, f);
        const HiddenSampleMap map = sampler.sample(frame);   // reassembles only if occluders moved
        result.sampleMs += sampler.lastSampleMs();
        result.accumulator.add(importanceOf(map, frame, side));
        ++result.framesDone;
        if (progress && !progress(f + 1, frames)) {
            result.cancelled = f + 1 < frames;
            break;
        }
    }
    result.totalMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

} // namespace sightline
