#include "VideoRecording.h"

#include <chrono>
#include <cmath>
#include <vector>

#include "EditorDocument.h"
#include "editor/LiveVisibility.h"
#include "editor/RayEnds.h"
#include "plugins/VideoEncoder.h"
#include "project/ProjectMotion.h"
#include "base/Error.h"

namespace sightline::ui {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// The placed occluders alone, and which occluder each instance belongs to (what
/// EditorDocument::occluderScene gives the renderer).
Scene occluderScene(const Project& project, const ProjectMeshes& meshes, std::vector<std::size_t>& occluderOf)
{
    Scene scene;
    occluderOf.clear();
    for (std::size_t i = 0; i < project.occluders.size(); ++i) {
        const std::size_t before = scene.instances.size();
        appendOccluder(scene, meshes.occluders.at(i), project.occluders[i]);
        occluderOf.insert(occluderOf.end(), scene.instances.size() - before, i);
    }
    return scene;
}

bool sameOccluders(const Project& a, const Project& b)
{
    if (a.occluders.size() != b.occluders.size())
        return false;
    for (std::size_t i = 0; i < a.occluders.size(); ++i)
        if (a.occluders[i].transform != b.occluders[i].transform)
            return false;
    return true;
}

/// Refuses a recording of no frames, or of a motion that `importance` would refuse.
void validateRecording(const RecordingScene& scene, const RecordingOptions& options)
{
    if (options.frames < 1)
        throw Error("a recording needs at least one frame");
    // The checks `importance` makes on the same motion: a frame it refuses is not rendered either.
    if (!scene.path.empty())
        validateMotionFrames(withoutMotionKeys(scene.project), ProjectMotion::of(scene.path), scene.path.frames);
    else
        validateMotionFrames(withoutMotionKeys(scene.project), ProjectMotion::of(scene.animation), options.frames);
}

/// Samples, renders, reads back and encodes each frame in turn, timing each step into `figures`;
/// returns whether `progress` cancelled the recording.
bool renderFrames(const RecordingScene& scene, const RecordingOptions& options, const gl::Functions& gl, const RenderTarget& target,
                  VideoEncoder& encoder, RecordingFigures& figures, const std::function<bool(int, int)>& progress)
{
    std::vector<std::uint8_t> pixels(std::size_t(options.width) * std::size_t(options.height) * 4);
    bool cancelled = false;
    ViewportRenderer renderer(gl);
    renderer.setSceneFile(scene.meshes.level);
    LiveVisibility visibility;
    PatchOverlay overlay;
    overlay.setKind(scene.overlay);
    overlay.setStatistic(scene.statistic);
    overlay.setAccumulating(scene.accumulate);

    std::optional<Project> previous;   // what the scene and the receiver heights were built for
    std::vector<std::size_t> occluderOf;
    std::optional<pvs::FirstHitCaster> hits;   // blocked rays' first stops, when they are drawn
    const bool drawStops = scene.style.showBlocked && scene.style.showRays;
    double sceneRadius = 10.0;
    for (int k = 0; k < options.frames; ++k) {
        const RecordingFrame frame = recordingFrame(scene, k, options.fps);
        const Project& project = frame.project;

        Clock::time_point t = Clock::now();
        if (!previous || !sameOccluders(*previous, project)) {
            // Occluders moved (or the first frame): rebuild what the samplers and renderer see.
            const Scene occluders = occluderScene(project, scene.meshes, occluderOf);
            renderer.setOccluders(occluders, occluderOf);
            Scene all = scene.meshes.level;
            all.append(occluders);
            const Bounds bounds = all.bounds();
            sceneRadius = bounds.empty() ? 10.0 : 0.5 * glm::length(bounds.max - bounds.min);
            visibility.setScene(all);
            if (drawStops)
                hits.emplace(all);
        }
        if (!previous || previous->receiver.na != project.receiver.na || previous->receiver.nb != project.receiver.nb)
            visibility.loadReceiverHeights(project, scene.what);
        const VisibilityResult result = visibility.sample(project.source, project.receiver);
        renderer.setHiddenSamples(result.valid ? &result.map : nullptr);
        if (result.valid && drawStops) {
            // Blocked rays end where they are first stopped, as in the editor.
            const RaySubset subset = raySubset(result.map.sourceCount(), result.map.receiverCount(), scene.style.rayCap);
            renderer.setRayEnds(drawnRayEnds(*hits, result.map, project.source, project.receiver, subset), scene.style.rayCap);
        }
        if (scene.overlay != OverlayKind::None) {
            overlay.setLive(result, project, true);
            renderer.setOverlay(overlayPatch(overlay.kind()), &overlay.texels());
        }
        previous = project;
        figures.sampleMs += msSince(t);

        t = Clock::now();
        FrameState state;
        state.camera = frame.camera;
        state.width = options.width;
        state.height = options.height;
        state.framebuffer = target.framebuffer;
        state.sceneRadius = sceneRadius;
        state.source = project.source;
        state.receiver = project.receiver;
        state.pairValid = result.valid;
        state.style = scene.style;
        renderer.render(state);
        gl.BindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
        gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
        gl.ReadPixels(0, 0, options.width, options.height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
        figures.renderMs += msSince(t);

        t = Clock::now();
        encoder.addFrame(pixels.data(), std::ptrdiff_t(options.width) * 4, /*bottomUp=*/true);   // GL rows run bottom-up
        figures.encodeMs += msSince(t);
        figures.frames = k + 1;
        if (progress && !progress(k + 1, options.frames)) {
            cancelled = true;
            break;
        }
    }
    return cancelled;
}

} // namespace

Camera toCamera(const PathCamera& p)
{
    Camera c;
    c.target = p.target;
    c.distance = p.distance;
    c.yaw = p.yaw;
    c.pitch = p.pitch;
    c.fovY = p.fovY;
    c.orthographic = p.orthographic;
    return c;
}

PathCamera toPathCamera(const Camera& c) { return {c.target, c.distance, c.yaw, c.pitch, c.fovY, c.orthographic}; }

RecordingScene recordingScene(const EditorDocument& document, const Camera& camera, const ViewStyle& style)
{
    RecordingScene scene;
    scene.project = document.project();
    scene.meshes = document.projectMeshes();
    scene.what = document.displayName().toStdString();
    scene.camera = camera;
    scene.animation = parseAnimation(scene.project, scene.what);
    scene.path = parseRecordedPath(scene.project, scene.what);
    scene.style = style;
    return scene;
}

double defaultRecordingFps(const RecordingScene& scene) { return scene.path.empty() ? 30.0 : scene.path.fps; }

int defaultRecordingFrames(const RecordingScene& scene, double fps)
{
    if (!scene.path.empty()) {
        // In double: a slow path played fast overflows an int (1e6 frames at 0.001 fps, at 240 fps).
        const double frames = std::round(scene.path.seconds() * fps);
        if (!(frames <= double(kMaxRecordedFrames)))
            throw Error(scene.what + ": the recorded path (" + std::to_string(scene.path.frames) + " frames at " +
                        std::to_string(scene.path.fps) + " fps) would take " + std::to_string(frames) + " video frames at " +
                        std::to_string(fps) + " fps; at most " + std::to_string(kMaxRecordedFrames) +
                        " are recorded (give --frames or a higher path fps)");
        return std::max(1, int(frames));
    }
    return defaultFrameCount(scene.animation);   // 1 without tracks
}

RecordingFrame recordingFrame(const RecordingScene& scene, int k, double fps)
{
    if (!scene.path.empty()) {
        const int f = scene.path.frameAtTime(k / fps);
        const std::optional<PathCamera> camera = scene.path.cameraAt(f);
        return {projectAtPathFrame(scene.project, scene.path, f), camera ? toCamera(*camera) : scene.camera};
    }
    return {projectAtFrame(scene.project, scene.animation, k), scene.camera};
}

RecordingFigures recordVideo(const RecordingScene& scene, const RecordingOptions& options,
                             const std::function<bool(int, int)>& progress)
{
    const Clock::time_point start = Clock::now();
    validateRecording(scene, options);
    VideoSettings settings;
    settings.width = options.width;
    settings.height = options.height;
    settings.fps = options.fps;
    // Opens the temporary file first: a bad name, size or folder fails before any rendering.
    VideoEncoder encoder(options.output, settings);

    RecordingFigures figures;
    figures.width = options.width;
    figures.height = options.height;
    figures.fps = options.fps;
    figures.encoder = encoder.format().encoder;
    figures.source = !scene.path.empty() ? "recorded path" : scene.animation.empty() ? "still view" : "animation";

    const auto context = gl::HeadlessContext::create(options.backend);
    const gl::Functions& gl = context->functions();
    RenderTarget target;
    if (!target.create(gl, options.width, options.height))
        throw Error("recording: the offscreen framebuffer is incomplete");
    const bool cancelled = renderFrames(scene, options, gl, target, encoder, figures, progress);
    target.destroy(gl);
    if (!cancelled) {
        const Clock::time_point t = Clock::now();
        encoder.finish();
        figures.encodeMs += msSince(t);
    }
    figures.seconds = msSince(start) / 1000.0;
    return figures;
}

} // namespace sightline::ui
