#include "AnimationImportance.h"

#include "project/LightingSetup.h"
#include "project/ProjectSampler.h"
#include "visibility/Error.h"

namespace sightline::ui {

ImportanceRunResult accumulateDocumentAnimation(const EditorDocument& document, const Animation& animation, int frames,
                                                ImportanceSide side, const std::function<bool(int, int)>& progress)
{
    const Project& project = document.project();
    const std::string what = document.displayName().toStdString();
    SamplerSettings settings;
    settings.method = "cpu";
    settings.heights = projectReceiverHeights(project, project.receiver, what);
    ProjectSampler sampler(projectAtFrame(project, animation, 0), document.projectMeshes(), settings);
    int done = 0;
    try {
        return accumulateImportance(sampler, project, animation, frames, side, [&](int d, int total) {
            done = d;
            return !progress || progress(d, total);
        });
    } catch (const Error& e) {
        throw Error("frame " + std::to_string(done) + ": " + e.what());   // frames count from 0
    }
}

} // namespace sightline::ui
