#pragma once
// Shows a frame of a recorded path (project/RecordedPath.h) in the editor: the patches and placed
// occluders the path moves are set on the document without undo, the camera on the controller.
// Shared by "Play Recorded Path" (RecordingControls) and the interaction benchmark's replay, so
// that both show exactly the states `projectAtPathFrame` gives.

#include "project/Project.h"
#include "project/RecordedPath.h"

namespace sightline::ui {

class EditorDocument;
class ViewportController;

/// Moves the document's source, receiver and occluders to `shown`'s where they differ (only those
/// changes reach the viewport, so a still object costs no new sample). Returns whether anything moved.
bool showProjectState(EditorDocument& document, const Project& shown);

/// Shows frame `frame` of `path` applied to `base` (the project before the playback): its edits
/// on the document and, when the path has camera keys, its camera. Returns whether an object moved.
bool showPathFrame(EditorDocument& document, ViewportController& controller, const Project& base,
                   const RecordedPath& path, int frame);

} // namespace sightline::ui
