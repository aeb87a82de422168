#pragma once
// Renders a project's view over time to a video: every frame is rendered headless
// (OSMesa or EGL, HeadlessContext) by the editor's own ViewportRenderer, after sampling the
// hidden-samples map with the editor's LiveVisibility, so the video shows what the viewport shows
// (level, occluders, patches, rays, the overlay) at a fixed frame rate whatever the editor's update
// rate was. Frames are rendered, not grabbed from a window. Serves `sightline --record` and the
// editor's recorder (RecordingControls.h), which runs it on a worker thread: a RecordingScene is a
// snapshot that shares nothing with the document.
//
// What moves: the project's recorded path (project/RecordedPath.h: camera and edits) when it has
// one, played at its own speed (video frame k shows the path at time k / fps); else the project's
// animation (project/Animation.h), one animation frame per video frame, seen from a fixed camera.

#include <filesystem>
#include <functional>
#include <string>

#include "editor/Camera.h"
#include "PatchOverlay.h"
#include "editor/ViewportRenderer.h"
#include "project/Animation.h"
#include "project/Project.h"
#include "project/RecordedPath.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::ui {

class EditorDocument;

/// The recorded path's camera and the editor's are the same five numbers.
Camera toCamera(const PathCamera& camera);
PathCamera toPathCamera(const Camera& camera);

struct RecordingScene {
    Project project;
    ProjectMeshes meshes;           ///< the level (moved objects placed) and each occluder's mesh
    std::string what;               ///< names the project in messages
    Camera camera;                  ///< the view where the path has no camera (or there is no path)
    Animation animation;            ///< played when `path` is empty
    RecordedPath path;
    ViewStyle style;
    OverlayKind overlay = OverlayKind::None;
    ImportanceStatistic statistic = ImportanceStatistic::Mean;
    bool accumulate = false;        ///< the importance overlay accumulates over the video's frames
};

/// A snapshot of the document as it is now (unsaved edits included), its recorded path and
/// animation parsed (throws sightline::Error naming the key when one is malformed).
RecordingScene recordingScene(const EditorDocument& document, const Camera& camera, const ViewStyle& style);

/// The rate a recording uses unless told: the path's, else 30 frames per second.
double defaultRecordingFps(const RecordingScene& scene);
/// The frames a recording renders unless told: the path's length at `fps` (at least 1), else the
/// animation's frame count (defaultFrameCount: the demo's 40), else 1. Throws sightline::Error when
/// the path's length comes to more than kMaxRecordedFrames video frames.
int defaultRecordingFrames(const RecordingScene& scene, double fps);

/// The project and camera of video frame `k` at `fps`.
struct RecordingFrame {
    Project project;
    Camera camera;
};
RecordingFrame recordingFrame(const RecordingScene& scene, int k, double fps);

struct RecordingOptions {
    std::filesystem::path output;   ///< .mp4 (H.264) or .webm (VP9), plugins/VideoEncoder.h
    int width = 1280;
    int height = 720;
    double fps = 30.0;
    int frames = 1;
    gl::Backend backend = gl::Backend::OSMesa;
};

struct RecordingFigures {
    int frames = 0;
    int width = 0, height = 0;
    double fps = 0.0;
    double seconds = 0.0;      ///< wall time of the whole recording (set-up and encoding included)
    double sampleMs = 0.0;     ///< summed over frames: visibility sampling (and scene rebuilds)
    double renderMs = 0.0;     ///< drawing and reading back the pixels
    double encodeMs = 0.0;     ///< colour conversion, encoding and writing
    std::string encoder;       ///< e.g. "libx264"
    std::string source;        ///< "recorded path", "animation" or "still view"
    double framesPerSecond() const { return seconds > 0.0 ? frames / seconds : 0.0; }
};

/// Renders `options.frames` frames to `options.output` (atomically: the file appears complete or
/// not at all). `progress(done, total)` after each frame; returning false cancels, and the function
/// then returns with figures.frames < options.frames and no file written. Throws sightline::Error
/// (bad size, unknown extension, unwritable folder, no GL context, or patches that are not a valid
/// pair at some frame of the path or animation: validateMotionFrames, before any file is opened).
RecordingFigures recordVideo(const RecordingScene& scene, const RecordingOptions& options,
                             const std::function<bool(int, int)>& progress = {});

} // namespace sightline::ui
