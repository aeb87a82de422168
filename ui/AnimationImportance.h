#pragma once
// "Accumulate Animation": the importance map of the document's project accumulated over the
// frames of its "animation" key (Eisemann & Décoret §9, accumulation over time; format in
// project/Animation.h), exactly as `sightline-cli importance` computes it (same run, same
// CPU sampler, the project's receiver_heights included), but on the document as it is now,
// unsaved edits included, with the meshes the editor already loaded. Also serves
// `sightline --screenshot --overlay receiver|source`.

#include <functional>

#include "EditorDocument.h"
#include "project/Animation.h"
#include "project/ImportanceRun.h"

namespace sightline::ui {

/// Accumulates `side`'s importance over `frames` frames of `animation` applied to the document's
/// project. `progress(done, total)` as in accumulateImportance (false cancels). Throws
/// sightline::Error naming the frame that failed (an invalid pair, a broken light or height key).
ImportanceRunResult accumulateDocumentAnimation(const EditorDocument& document, const Animation& animation, int frames,
                                                ImportanceSide side, const std::function<bool(int, int)>& progress = {});

} // namespace sightline::ui
