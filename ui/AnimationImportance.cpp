#include "AnimationImportance.h"

#include "project/LightingSetup.h"
#include "project/ProjectSampler.h"
#include "base/Error.h"

namespace sightline::ui {

AnimationInput animationInput(const EditorDocument& document)
{
    return {document.project(), document.projectMeshes(), document.displayName().toStdString()};
}

ImportanceRunResult accumulateDocumentAnimation(const EditorDocument& document, const Animation& animation, int frames,
                                                ImportanceSide side, const std::function<bool(int, int)>& progress)
{
    return accumulateAnimation(animationInput(document), animation, frames, side, progress);
}

ImportanceRunResult accumulateAnimation(const AnimationInput& input, const Animation& animation, int frames,
                                        ImportanceSide side, const std::function<bool(int, int)>& progress)
{
    return accumulateMotion(input, ProjectMotion::of(animation), frames, side, progress);
}

ImportanceRunResult accumulateMotion(const AnimationInput& input, const ProjectMotion& motion, int frames,
                                     ImportanceSide side, const std::function<bool(int, int)>& progress)
{
    const Project project = withoutMotionKeys(input.project);
    SamplerSettings settings;
    settings.method = "cpu";
    settings.heights = projectReceiverHeights(project, project.receiver, input.name);
    ProjectSampler sampler(motion.at(project, 0), input.meshes, settings);
    int done = 0;
    try {
        return accumulateImportance(sampler, project, motion, frames, side, [&](int d, int total) {
            done = d;
            return !progress || progress(d, total);
        });
    } catch (const Error& e) {
        throw Error("frame " + std::to_string(done) + ": " + e.what());   // frames count from 0
    }
}

} // namespace sightline::ui
