#include "project/ImportanceRun.h"

#include <chrono>
#include <optional>

namespace sightline {

ImportanceMap importanceOf(const HiddenSampleMap& map, const Project& frame, ImportanceSide side)
{
    return side == ImportanceSide::Receiver ? receiverImportance(map)
                                            : sourceImportance(map, frame.source.na, frame.source.nb);
}

ImportanceRunResult accumulateImportance(ProjectSampler& sampler, const Project& project, const ProjectMotion& motion,
                                         int frames, ImportanceSide side, const std::function<bool(int, int)>& progress)
{
    const auto start = std::chrono::steady_clock::now();
    const Project base = withoutMotionKeys(project);   // copied for each frame
    ImportanceRunResult result;
    std::optional<ImportanceMap> last;
    for (int f = 0; f < frames; ++f) {
        if (!last || motion.mayChangeAt(f)) {
            const Project frame = motion.at(base, f);
            const HiddenSampleMap map = sampler.sample(frame);   // reassembles only if occluders moved
            result.sampleMs += sampler.lastSampleMs();
            ++result.framesSampled;
            last = importanceOf(map, frame, side);
        }
        result.accumulator.add(*last);
        ++result.framesDone;
        if (progress && !progress(f + 1, frames)) {
            result.cancelled = f + 1 < frames;
            break;
        }
    }
    result.totalMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

ImportanceRunResult accumulateImportance(ProjectSampler& sampler, const Project& project, const Animation& animation,
                                         int frames, ImportanceSide side, const std::function<bool(int, int)>& progress)
{
    return accumulateImportance(sampler, project, ProjectMotion::of(animation), frames, side, progress);
}

} // namespace sightline
