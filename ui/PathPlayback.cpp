#include "PathPlayback.h"

#include "EditorDocument.h"
#include "VideoRecording.h"
#include "ViewportController.h"

namespace sightline::ui {

namespace {
bool samePatch(const Patch& a, const Patch& b) { return a.corner == b.corner && a.u == b.u && a.v == b.v; }
} // namespace

bool showProjectState(EditorDocument& document, const Project& shown)
{
    bool moved = false;
    if (!samePatch(document.project().source, shown.source)) {
        document.applyState({ObjectKind::Source, 0}, shown.source);
        moved = true;
    }
    if (!samePatch(document.project().receiver, shown.receiver)) {
        document.applyState({ObjectKind::Receiver, 0}, shown.receiver);
        moved = true;
    }
    for (std::size_t i = 0; i < shown.occluders.size() && i < document.project().occluders.size(); ++i)
        if (document.project().occluders[i].transform != shown.occluders[i].transform) {
            document.applyState({ObjectKind::Occluder, i}, shown.occluders[i].transform);
            moved = true;
        }
    return moved;
}

bool showPathFrame(EditorDocument& document, ViewportController& controller, const Project& base,
                   const RecordedPath& path, int frame)
{
    const bool moved = showProjectState(document, projectAtPathFrame(base, path, frame));
    if (const auto camera = path.cameraAt(frame))
        controller.setCamera(toCamera(*camera));
    return moved;
}

} // namespace sightline::ui
