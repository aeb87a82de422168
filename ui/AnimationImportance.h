#pragma once
// "Accumulate Animation" / "Accumulate Recorded Path": the importance map of the document's
// project accumulated over the frames of its "animation" key or of its recorded path (Eisemann &
// Décoret §9, accumulation over time; project/ProjectMotion.h), exactly as `sightline-cli
// importance [--path]` computes it (same run, same
// CPU sampler, the project's receiver_heights included), but on the document as it is now,
// unsaved edits included, with the meshes the editor already loaded. Also serves
// `sightline --screenshot --overlay receiver|source`.

#include <functional>

#include "EditorDocument.h"
#include "project/Animation.h"
#include "project/ImportanceRun.h"
#include "project/ProjectMotion.h"

namespace sightline::ui {

/// What a run reads of the document, copied, so that it can run on another thread while the
/// document lives on (and autosave writes its editor settings) on the GUI thread.
struct AnimationInput {
    Project project;
    ProjectMeshes meshes;
    std::string name;   ///< the document's name, for messages
};
AnimationInput animationInput(const EditorDocument& document);

/// Accumulates `side`'s importance over `frames` frames of `motion` applied to `input`'s project.
/// Touches nothing but its arguments: safe on a worker thread.
ImportanceRunResult accumulateMotion(const AnimationInput& input, const ProjectMotion& motion, int frames,
                                     ImportanceSide side, const std::function<bool(int, int)>& progress = {});
/// The same over an animation.
ImportanceRunResult accumulateAnimation(const AnimationInput& input, const Animation& animation, int frames,
                                        ImportanceSide side, const std::function<bool(int, int)>& progress = {});

/// Accumulates `side`'s importance over `frames` frames of `animation` applied to the document's
/// project. `progress(done, total)` as in accumulateImportance (false cancels). Throws
/// sightline::Error naming the frame that failed (an invalid pair, a broken light or height key).
ImportanceRunResult accumulateDocumentAnimation(const EditorDocument& document, const Animation& animation, int frames,
                                                ImportanceSide side, const std::function<bool(int, int)>& progress = {});

} // namespace sightline::ui
