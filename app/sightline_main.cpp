// sightline: the editor. Also renders a project's view headlessly (--screenshot, optionally with
// an importance or light overlay and its legend), records it over the project's recorded path or
// animation to a video (--record, docs/design.md §4) and measures the live update rate
// (--benchmark-interaction, optionally with an overlay on).

#include <algorithm>
#include <atomic>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <CLI/CLI.hpp>
#include <QApplication>
#include <QCoreApplication>
#include <QPainter>
#include <QTemporaryDir>
#include <QSurfaceFormat>

#include "AnimationImportance.h"
#include "editor/DisagreementWorker.h"
#include "EditorDocument.h"
#include "InteractionBenchmark.h"
#include "MainWindow.h"
#include "OffscreenRender.h"
#include "OverlayControls.h"
#include "OverlayLegend.h"
#include "StallBenchmark.h"
#include "VideoRecording.h"
#include "editor/ViewSettings.h"
#include "Viewport.h"
#include "cli/OutputLimits.h"
#include "cli/OutputPaths.h"
#include "plugins/VideoEncoder.h"
#include "report/MapImage.h"
#include "report/OffscreenApplication.h"
#include "report/PngFile.h"
#include "base/Error.h"

namespace {

using namespace sightline;
using namespace sightline::ui;

struct Arguments {
    std::string file;
    std::string screenshot;
    std::string record;
    bool benchmark = false;
    bool stalls = false;
    std::string receiverSamples;
    std::string replay = "auto";
    int frames = 300;   ///< benchmark default; recordings use the path's or animation's length
    bool framesGiven = false;
    int backgroundLoad = 0;   ///< benchmarks: busy threads beside the editor
    double fps = 0.0;   ///< 0: the recorded path's, else 30
    std::string size = "1280x720";
    int rays = 4096;
    bool showBlocked = false;
    std::string glBackend = "osmesa";
    std::string overlay = "none";
    std::string statistic = "mean";
    bool accumulate = false;
    bool ao = false;
    bool lit = false;
    bool litIndirect = false;
    std::string litShows = "light";
    int litBudget = 4;
    std::string disagreement;   ///< screenshot: an approximation (project/Approximation.h), or empty
    bool allowOutsidePaths = false;
};

/// "WxH" with decimal sides in [1, INT_MAX], nothing else (no sign, space or suffix). Each side is
/// read as a 64-bit integer and range-checked before it becomes an int: "4294967312x16" is
/// refused, not wrapped to 16x16.
bool parseSize(const std::string& text, int& width, int& height)
{
    const auto side = [](std::string_view digits, int& out) {
        std::uint64_t value = 0;
        const char* end = digits.data() + digits.size();
        const auto [stop, error] = std::from_chars(digits.data(), end, value);
        if (digits.empty() || error != std::errc() || stop != end || value < 1 || value > std::uint64_t(INT_MAX))
            return false;
        out = int(value);
        return true;
    };
    const std::string_view all(text);
    const std::size_t x = all.find('x');
    return x != std::string_view::npos && side(all.substr(0, x), width) && side(all.substr(x + 1), height);
}

/// The overlay a screenshot shows: importance over the project's animation when it has one (the
/// editor's "Accumulate Animation"), else over the project as it is (one frame).
QString prepareOverlay(const EditorDocument& document, PatchOverlay& overlay)
{
    if (!isImportance(overlay.kind()))
        return {};
    const Animation animation = parseAnimation(document.project(), document.displayName().toStdString());
    if (animation.empty())
        return {};
    const ImportanceSide side = overlay.kind() == OverlayKind::SourceImportance ? ImportanceSide::Source : ImportanceSide::Receiver;
    ImportanceRunResult run = accumulateDocumentAnimation(document, animation, defaultFrameCount(animation), side);
    overlay.showAnimationResult(side, std::move(run.accumulator));
    return QString::asprintf("%.1f ms a frame", run.sampleMs / std::max(run.framesDone, 1));
}

/// Refuses an output that would replace the opened file or a file it names (cli/OutputPaths.h):
/// `--screenshot p.json p.json` replaced the project with the PNG.
void checkOutput(const std::string& option, const std::string& output, const std::string& file, const Project& project)
{
    std::vector<cli::FileRole> inputs = cli::projectInputs(file, project);
    inputs.front().role = "the opened file";
    cli::checkOutputs({{option, output}}, inputs);
}

int screenshot(const Arguments& args, int width, int height)
{
    const std::optional<Approximation> disagreement =   // a misspelling is refused before the level loads
        args.disagreement.empty() ? std::nullopt : std::optional(parseApproximation(args.disagreement));
    EditorDocument document;
    document.setAllowOutsidePaths(args.allowOutsidePaths);
    document.open(args.file);
    checkOutput("--screenshot", args.screenshot, args.file, document.project());
    ViewStyle style;
    style.rayCap = args.rays;
    style.showBlocked = args.showBlocked;
    style.litView = args.lit;
    style.litShading = parseLitShading(args.litShows);
    style.litBudget = args.litBudget;
    style.litIndirect = args.litIndirect;
    PatchOverlay overlay;
    overlay.setKind(parseOverlayKind(args.overlay));
    overlay.setStatistic(parseImportanceStatistic(args.statistic));
    const QString animationTime = prepareOverlay(document, overlay);
    const Project& project = document.project();
    const Camera camera = projectView(document.editorSettings(), project.source, project.receiver);
    OffscreenResult result = renderOffscreen(document, camera, style, width, height, gl::parseBackend(args.glBackend), &overlay,
                                             disagreement ? &*disagreement : nullptr);
    if (overlay.kind() == OverlayKind::LightOnReceiver && !overlay.error().empty())
        throw sightline::Error(overlay.error());
    if (overlay.kind() == OverlayKind::LightOnReceiver && overlay.light()) {
        const QString caption = QObject::tr("light from the source, of full (its colour scaled)");   // as in the editor
        const QSize size = legendPanelSize(caption, height - 16);
        QPainter painter(&result.image);
        paintLegendPanel(painter, QRect(QPoint(width - size.width() - 8, 8), size), caption, LegendScale::Light);
    }
    if (const ImportanceMap* map = overlay.importance()) {
        // The legend in the top-right corner, as in the editor.
        const QString caption = overlay.legendCaption();
        const QSize size = legendPanelSize(caption, height - 16);
        QPainter painter(&result.image);
        paintLegendPanel(painter, QRect(QPoint(width - size.width() - 8, 8), size), caption);
        painter.end();
        std::printf("overlay %s importance: %s (mean value %.1f%%%s%s)\n", toString(overlay.kind()),
                    overlay.legendCaption().toUtf8().constData(), 100.0 * map->mean(), animationTime.isEmpty() ? "" : ", ",
                    animationTime.toUtf8().constData());
    } else if (const LightImage* light = overlay.light()) {
        glm::dvec3 sum(0.0);
        for (const glm::vec3& c : light->rgb)
            sum += glm::dvec3(c);
        sum /= double(std::max<std::size_t>(light->rgb.size(), 1));
        std::printf("overlay light on the receiver: mean R %.1f%%, G %.1f%%, B %.1f%%\n", 100.0 * sum.r, 100.0 * sum.g, 100.0 * sum.b);
    }
    if (result.disagreement) {
        DisagreementAnswer answer;
        answer.approximation = *disagreement;
        answer.disagreement = std::make_shared<const RayDisagreement>(result.disagreement->disagreement);
        answer.approximateMs = result.disagreement->approximateMs;
        std::printf("disagreement %s\n", disagreementStatus(answer).c_str());
    }
    savePng(result.image, args.screenshot);   // atomic: an interrupted render leaves the old file
    std::printf("wrote %s (%dx%d): %s; %llu rays drawn\n", args.screenshot.c_str(), width, height,
                visibilitySummary(result.visibility).toUtf8().constData(), static_cast<unsigned long long>(result.raysDrawn));
    return 0;
}

/// `--record`: the project's recorded path (else its animation) rendered headless to a video.
int record(const Arguments& args, int width, int height)
{
    EditorDocument document;
    document.setAllowOutsidePaths(args.allowOutsidePaths);
    document.open(args.file);
    checkOutput("--record", args.record, args.file, document.project());
    ViewStyle style;
    style.rayCap = args.rays;
    style.showBlocked = args.showBlocked;
    const Project& project = document.project();
    // The section cut where the editor puts it on open (1.5 m above the higher patch), so that it
    // stays put while a recorded camera moves its target.
    style.cutHeight = std::max(project.source.centre().y, project.receiver.centre().y) + 1.5;
    RecordingScene scene = recordingScene(document, projectView(document.editorSettings(), project.source, project.receiver), style);
    scene.overlay = parseOverlayKind(args.overlay);
    scene.statistic = parseImportanceStatistic(args.statistic);
    scene.accumulate = args.accumulate;
    RecordingOptions options;
    options.output = args.record;
    options.width = width;
    options.height = height;
    options.fps = args.fps > 0.0 ? args.fps : defaultRecordingFps(scene);
    options.frames = args.framesGiven ? args.frames : defaultRecordingFrames(scene, options.fps);
    options.backend = gl::parseBackend(args.glBackend);
    const RecordingFigures f = recordVideo(scene, options);
    std::printf("wrote %s: %d frames at %dx%d, %.4g fps (%s, %s)\n", args.record.c_str(), f.frames, f.width, f.height, f.fps,
                f.encoder.c_str(), f.source.c_str());
    std::printf("recorded in %.2f s: %.1f frames per second (per frame: sampling %.1f ms, rendering %.1f ms, encoding %.1f ms)\n",
                f.seconds, f.framesPerSecond(), f.sampleMs / f.frames, f.renderMs / f.frames, f.encodeMs / f.frames);
    return 0;
}

/// Threads that keep cores busy while a benchmark runs, as other work on a shared desktop does
/// (a build, a game, a render): the editor's rate and stalls are then what a designer sees there.
class BackgroundLoad {
public:
    explicit BackgroundLoad(int threads)
    {
        for (int k = 0; k < threads; ++k)
            threads_.emplace_back([this] {
                volatile std::uint64_t x = 0;
                while (!stop_.load(std::memory_order_relaxed))
                    for (int i = 0; i < 100000; ++i)
                        x = x * 6364136223846793005ull + 1442695040888963407ull;
            });
    }
    ~BackgroundLoad()
    {
        stop_ = true;
        for (std::thread& t : threads_)
            t.join();
    }
    BackgroundLoad(const BackgroundLoad&) = delete;
    BackgroundLoad& operator=(const BackgroundLoad&) = delete;

private:
    std::atomic<bool> stop_{false};
    std::vector<std::thread> threads_;
};

int benchmark(const Arguments& args, int width, int height)
{
    MainWindow window(EditorOptions{.offerRecovery = false, .allowOutsidePaths = args.allowOutsidePaths});
    if (!window.openFile(QString::fromStdString(args.file)))
        return 1;
    window.viewport().style().rayCap = args.rays;
    window.viewport().style().showBlocked = args.showBlocked;
    window.overlayControls().setKind(parseOverlayKind(args.overlay));
    window.overlayControls().setStatistic(parseImportanceStatistic(args.statistic));
    window.overlayControls().setAccumulating(args.accumulate);
    if (args.lit) {
        const LitFigures f = runLitBenchmark(window, args.frames, width, height);
        std::printf("lit view benchmark: %s, %zu lights over %zu light-map texels at %dx%d\n", args.file.c_str(), f.lights,
                    f.texels, width, height);
        std::printf("  first exact    %.0f ms after the lit view was turned on%s\n", f.firstExactMs,
                    f.firstExactMs > 0.0 ? "" : " (not within 5 minutes)");
        std::printf("  camera orbit   %.1f Hz median, exact all the while (frame %.1f ms 90th percentile; %d frames)\n",
                    f.orbitHz, f.orbitP90FrameMs, f.orbitFrames);
        std::printf("  update rate    %.1f Hz median while dragging '%s' (interval %.1f ms median, %.1f ms 90th percentile; "
                    "%d frames)\n",
                    f.medianHz, f.dragged.c_str(), f.medianFrameMs, f.p90FrameMs, f.frames);
        std::printf("  exact again    %.0f ms after the light was let go%s\n", f.exactAgainMs,
                    f.exactAgainMs > 0.0 ? "" : " (not within 5 minutes)");
        std::printf("  occluder moved %d lit frames at most until exact, %.0f ms median ('%s' moved %d times)\n",
                    f.occluderMostFrames, f.occluderMedianMs, f.occluder.c_str(), f.occluderMoves);
        std::printf("  one bounce     %zu VPLs: exact %.0f ms after it was turned on, again %.0f ms after the light moved%s\n",
                    f.vpls, f.bounceFirstExactMs, f.bounceExactAgainMs,
                    f.bounceFirstExactMs > 0.0 && f.bounceExactAgainMs > 0.0 ? "" : " (0: not within 5 minutes)");
        return 0;
    }
    InteractionOptions options;
    options.width = width;
    options.height = height;
    options.withAo = args.ao;
    // The recorded path when asked, or by default when the project has one; else the drag.
    const bool hasPath = !parseRecordedPath(window.document().project(), args.file).empty();
    options.replay = args.replay == "path" || (args.replay == "auto" && hasPath) ? InteractionReplay::RecordedPath
                                                                                 : InteractionReplay::Drag;
    options.frames = args.framesGiven || options.replay == InteractionReplay::Drag
                         ? args.frames
                         : parseRecordedPath(window.document().project(), args.file).frames;
    const InteractionFigures f = runInteractionBenchmark(window, options);
    std::printf("interaction benchmark: %s, %d frames at %dx%d, %s\n", args.file.c_str(), f.frames, f.width, f.height,
                options.replay == InteractionReplay::Drag ? "receiver dragged along a scripted path"
                                                          : ("replaying its " + f.replay).c_str());
    std::printf("  sampler        %s\n", f.backend.c_str());
    std::printf("  rays           %llu per update (%llu drawn), %.1f%% visible on average\n",
                static_cast<unsigned long long>(f.rays), static_cast<unsigned long long>(f.raysDrawn), 100.0 * f.meanVisibleFraction);
    if (f.answers > 0)
        std::printf("  update rate    %.1f Hz median (interval %.1f ms median, %.1f ms 90th percentile; %d updates)\n",
                    f.medianHz, f.medianFrameMs, f.p90FrameMs, f.answers);
    else
        std::printf("  update rate    no update (nothing the path moved needed a new sample)\n");
    std::printf("  drawing        %.1f ms a frame median, %.1f ms 90th percentile; %.1f frames drawn per second, "
                "%.2f per update\n", f.medianDrawMs, f.p90DrawMs, f.drawnHz, f.framesPerAnswer);
    std::printf("  sampling       %.1f ms median per update\n", f.medianSampleMs);
    std::printf("  processor      %.1f ms per update (all threads), %.2f cores busy on average\n", f.cpuMsPerAnswer, f.cpuLoad);
    std::printf("  overlay        %s%s\n", args.overlay.c_str(), args.accumulate ? ", accumulating" : "");
    if (args.ao) {
        std::printf("  with AO        %.1f Hz median (frame %.1f ms 90th percentile) over the %d frames shown while the "
                    "level's AO was computing\n",
                    f.aoMedianHz, f.aoP90FrameMs, f.aoFrames);
        if (f.aoDoneMs > 0.0)
            std::printf("  AO k = 258     shown after %.0f ms\n", f.aoDoneMs);
        else
            std::printf("  AO k = 258     not reached within the run (give more --frames)\n");
    }
    return 0;
}

int stallBenchmark(const Arguments& args, int width, int height)
{
    std::optional<std::pair<int, int>> grid;
    if (!args.receiverSamples.empty()) {
        int na = 0, nb = 0;
        if (!parseSize(args.receiverSamples, na, nb) || na > 1024 || nb > 1024) {
            std::fprintf(stderr, "sightline: --receiver-samples must be NAxNB with sides in [1, 1024], got '%s'\n",
                         args.receiverSamples.c_str());
            return 2;
        }
        grid = std::pair{na, nb};
    }
    const QTemporaryDir folder;
    bool addedAnimation = false;
    const std::filesystem::path project = stallBenchmarkProject(
        args.file, grid, args.framesGiven ? args.frames : 10, folder.path().toStdString(), &addedAnimation);
    MainWindow window(EditorOptions{.offerRecovery = false, .allowOutsidePaths = args.allowOutsidePaths});
    window.viewport().style().rayCap = args.rays;
    window.viewport().style().showBlocked = args.showBlocked;
    const StallFigures f = runStallBenchmark(window, QString::fromStdString(project.string()), width, height);
    const Project& opened = window.document().project();
    const auto phase = [](const char* name, const StallPhase& p) {
        std::printf("  %-16s longest stall %.1f ms (at %.0f ms), %d over 50 ms, in %.0f ms\n", name, p.longestStallMs, p.at,
                    p.stallsOver50Ms, p.ms);
    };
    std::printf("event-loop stall benchmark: %s (receiver %dx%d) at %dx%d, a 1 ms timer ticking throughout\n",
                args.file.c_str(), opened.receiver.na, opened.receiver.nb, width, height);
    phase("first open", f.firstOpen);
    phase("open again", f.open);
    if (f.frames > 0) {
        phase("accumulate", f.accumulate);
        std::printf("  animation        %d frames%s%s\n", f.frames,
                    addedAnimation ? " (the benchmark's: the receiver steps 0.5 m every other frame)" : "",
                    f.shown ? "" : "; no result shown");
    }
    std::printf("  longest          %.1f ms (first open %.1f ms)\n", std::max(f.open.longestStallMs, f.accumulate.longestStallMs),
                f.firstOpen.longestStallMs);
    return 0;
}

/// The editor allocates and frees the same large blocks every update (the sampler's per-call
/// buffers, llvmpipe's per-frame bins). By default glibc returns the freed top of each heap to the
/// system at once (128 KiB trim threshold) and the next update faults it back in: thousands of
/// page faults an update, over a third of the editor's processor time while dragging on llvmpipe
/// (`--benchmark-interaction --rays 4096` shows it). Keeping up to 256 MiB of freed memory per
/// heap, and serving blocks up to 32 MiB (glibc's own upper bound) from the heaps, stops that.
void keepFreedMemory()
{
#if defined(__GLIBC__)
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
#endif
}

/// The options whose presence (not only value) matters after parsing.
struct OptionHandles {
    CLI::Option* frames = nullptr;
    CLI::Option* litShows = nullptr;
    CLI::Option* litBudget = nullptr;
    CLI::Option* litIndirect = nullptr;
};

OptionHandles addOptions(CLI::App& app, Arguments& args)
{
    OptionHandles handles;
    app.add_option("file", args.file, "Project (.json) or level (.glb .gltf .obj .ply .off .stl) to open");
    app.add_option("--screenshot", args.screenshot, "Render FILE's view (its saved camera, else across the shaft) to this PNG "
                                                    "without a display, then exit");
    app.add_option("--record", args.record,
                   "Render FILE's view over its recorded path (else its animation) to this video without a display, "
                   "then exit: .mp4 (H.264) or .webm (VP9)");
    app.add_option("--fps", args.fps, "Recording frame rate (default: the recorded path's, else 30)")
        ->check(CLI::Range(0.001, 240.0));
    app.add_flag("--benchmark-interaction", args.benchmark,
                 "Drag FILE's receiver along a scripted path in the editor (or replay its recorded path) and print "
                 "the median update rate");
    app.add_flag("--benchmark-stalls", args.stalls,
                 "Open FILE in the editor (twice) and accumulate its animation (without one, the receiver "
                 "stepping 0.5 m every other frame, --frames of them, default 10), and print the longest time the "
                 "event loop did not run in each");
    app.add_option("--receiver-samples", args.receiverSamples,
                   "Stall benchmark: the receiver's grid, NAxNB (e.g. 512x512 for the demo floor)");
    app.add_option("--replay", args.replay,
                   "Benchmark: what moves: the project's recorded path (path), the scripted drag of the receiver "
                   "(drag), or the path when the project has one (auto)")
        ->check(CLI::IsMember({"auto", "path", "drag"}));
    handles.frames = app.add_option("--frames", args.frames,
                                         "Benchmark frames (default 300, or the recorded path's length when "
                                         "replaying it); recording frames (default: the recorded path's length, "
                                         "else the animation's frames)")
                              ->check(CLI::Range(1, 100000));
    app.add_option("--size", args.size, "Screenshot, recording or benchmark viewport size, WxH (a recording needs even sides)");
    app.add_option("--rays", args.rays, "Most rays drawn (screenshot, recording and benchmark)")->check(CLI::Range(1, 1 << 30));
    app.add_flag("--show-blocked", args.showBlocked, "Draw blocked rays too, in red (screenshot, recording and benchmark)");
    app.add_option("--overlay", args.overlay, "Paint receiver or source importance, or the source's light on the "
                                              "receiver. Screenshot: importance accumulated over the project's animation "
                                              "when it has one (else this frame), with its legend; benchmark: shown while "
                                              "dragging")
        ->check(CLI::IsMember({"none", "receiver", "source", "light"}));
    app.add_option("--statistic", args.statistic,
                   "How accumulated frames combine (screenshot: the animation's; benchmark: with --accumulate): "
                   "mean, max or ever")
        ->check(CLI::IsMember({"mean", "max", "ever"}));
    app.add_flag("--accumulate", args.accumulate, "Benchmark: accumulate importance while dragging; recording: over the video's frames");
    app.add_option("--background-load", args.backgroundLoad,
                   "Benchmarks: keep this many threads busy beside the editor during the run, as other work on a "
                   "shared desktop does (the rate and stalls under load)")
        ->check(CLI::Range(0, 256));
    app.add_flag("--ao", args.ao, "Benchmark: start the level's ambient occlusion preview with the drag and report the "
                                  "update rate while it computes (to k = 258)");
    app.add_flag("--lit", args.lit, "The lit view (the project's lights on the level's light-map texels, shadowed exactly). "
                                    "Screenshot: lit and exact; benchmark: drag the first light with the lit view on and "
                                    "print the lit view's update rate and how soon it is exact again");
    handles.litShows = app.add_option("--lit-shows", args.litShows,
                                    "Screenshot with --lit: what the lit view shows: light, complexity (shadow complexity), "
                                    "overlap (lights a texel against --lit-budget), staleness or error (against the reference path)")
                         ->check(CLI::IsMember({"light", "complexity", "overlap", "staleness", "error"}));
    handles.litBudget = app.add_option("--lit-budget", args.litBudget, "Screenshot with --lit: the overlapping lights a texel may take (default 4)")
                          ->check(CLI::Range(1, 1000));
    handles.litIndirect = app.add_flag("--lit-indirect", args.litIndirect,
                                       "Screenshot with --lit: add one bounce of indirect light, as View > Lit View Shows > Indirect Light "
                                       "(the lights' virtual point lights, each surface's material albedo)");
    app.add_option("--disagreement", args.disagreement,
                   "Screenshot: draw, in place of the rays, those an approximation answers differently from the exact "
                   "sampler (false-blocked red, false-free blue, ties amber): table[-WxH], gl, gl-table[-WxH], samples-K, "
                   "coarse[-N], inner[-R] (docs/cli.md)");
    app.add_option("--gl-backend", args.glBackend, "Screenshot and recording: headless GL, osmesa or egl")->check(CLI::IsMember({"osmesa", "egl"}));
    app.add_flag("--allow-outside-paths", args.allowOutsidePaths,
                 "Read files the project names by a relative path that leaves its folder (refused otherwise; "
                 "the editor's File menu keeps this as a setting)");
    return handles;
}

/// Refuses, with one line on stderr, what the parser cannot: empty output names, a bad size,
/// options that need others; returns 2 then, else 0 with the view size in `width` x `height`.
int checkArguments(const CLI::App& app, Arguments& args, const OptionHandles& handles, int& width, int& height)
{
    args.framesGiven = handles.frames->count() > 0;
    // An empty name would read as "option not given" below and open the editor instead.
    for (const auto& [option, output] : {std::pair{"--record", &args.record}, std::pair{"--screenshot", &args.screenshot}})
        if (app.get_option(option)->count() > 0 && output->empty()) {
            std::fprintf(stderr, "sightline: %s needs an output file name, got ''\n", option);
            return 2;
        }
    if (!parseSize(args.size, width, height)) {
        std::fprintf(stderr, "sightline: --size must be WxH with whole positive sides, got '%s'\n", args.size.c_str());
        return 2;
    }
    try {
        // Render target, read-back and two conversions: about 24 bytes a pixel.
        cli::checkImageSize(width, height, "--size " + args.size, 24);
    } catch (const sightline::Error& e) {
        std::fprintf(stderr, "sightline: %s\n", e.what());
        return 2;
    }
    if ((!args.screenshot.empty() || !args.record.empty() || args.benchmark || args.stalls) && args.file.empty()) {
        std::fprintf(stderr, "sightline: --screenshot, --record, --benchmark-interaction and --benchmark-stalls need a project file\n");
        return 2;
    }
    if ((handles.litShows->count() > 0 || handles.litBudget->count() > 0 || handles.litIndirect->count() > 0) &&
        (!args.lit || args.screenshot.empty())) {
        std::fprintf(stderr, "sightline: --lit-shows, --lit-budget and --lit-indirect apply to --screenshot --lit\n");
        return 2;
    }
    if (!args.disagreement.empty() && args.screenshot.empty()) {
        std::fprintf(stderr, "sightline: --disagreement applies to --screenshot (the editor's is View > Disagreement With Exact, Ctrl+Shift+D)\n");
        return 2;
    }
    if (args.lit && !args.benchmark && args.screenshot.empty()) {
        std::fprintf(stderr, "sightline: --lit applies to --screenshot and --benchmark-interaction (the editor's lit view is View > Lit View, I)\n");
        return 2;
    }
    if (args.backgroundLoad > 0 && !args.benchmark && !args.stalls) {
        std::fprintf(stderr, "sightline: --background-load applies to --benchmark-interaction and --benchmark-stalls\n");
        return 2;
    }
    if (args.ao && !args.benchmark) {
        std::fprintf(stderr, "sightline: --ao applies to --benchmark-interaction only (the editor's AO is View > Ambient Occlusion, O)\n");
        return 2;
    }
    if (!args.record.empty()) {
        // Checked before the project loads: a bad name or size costs nothing.
        try {
            cli::checkOutputs({{"--record", args.record}}, {{"the opened file", args.file}});
            videoFormatFor(args.record);
            VideoSettings video;
            video.width = width;
            video.height = height;
            video.fps = args.fps > 0.0 ? args.fps : 30.0;
            checkVideoSettings(video);
        } catch (const sightline::Error& e) {
            std::fprintf(stderr, "sightline: --record: %s\n", e.what());
            return 2;
        }
    }
    return 0;
}

/// Runs what the arguments ask: a recording, a screenshot, a benchmark or the editor.
int run(const Arguments& args, int width, int height, int argc, char** argv)
{
    QCoreApplication::setOrganizationName("Sightline");
    QCoreApplication::setApplicationName("Sightline");
    try {
        if (!args.record.empty()) {
            // No display needed, as for --screenshot (the legend is not drawn in videos).
            QCoreApplication core(argc, argv);
            return record(args, width, height);
        }
        if (!args.screenshot.empty()) {
            // No display needed: OSMesa renders. An overlay legend's text needs a
            // QGuiApplication, on the offscreen platform when there is no display.
            if (args.overlay == "receiver" || args.overlay == "source" || args.overlay == "light") {
                const auto application = ensureApplication();
                return screenshot(args, width, height);
            }
            QCoreApplication core(argc, argv);
            return screenshot(args, width, height);
        }
        QSurfaceFormat format;
        format.setVersion(4, 5);
        format.setProfile(QSurfaceFormat::CoreProfile);
        format.setDepthBufferSize(24);
        format.setStencilBufferSize(8);
        format.setSwapInterval(0);   // measure and draw as fast as the frame is ready
        QSurfaceFormat::setDefaultFormat(format);
        QApplication application(argc, argv);
        if (args.benchmark || args.stalls) {
            const BackgroundLoad load(args.backgroundLoad);
            if (args.backgroundLoad > 0)
                std::printf("background load: %d busy threads\n", args.backgroundLoad);
            return args.benchmark ? benchmark(args, width, height) : stallBenchmark(args, width, height);
        }
        MainWindow window;
        window.show();
        if (!args.file.empty())
            window.openFile(QString::fromStdString(args.file));
        return application.exec();
    } catch (const std::exception& e) {
        const std::string doing = !args.record.empty()       ? "recording " + args.file + " to " + args.record
                                  : !args.screenshot.empty() ? "rendering the screenshot of " + args.file
                                  : args.benchmark || args.stalls ? "benchmarking " + args.file
                                                            : std::string("running the editor");
        std::fprintf(stderr, "sightline: %s\n", describeFailure(e, doing).c_str());
        return 1;
    }
}

} // namespace

int main(int argc, char** argv)
{
    keepFreedMemory();
    CLI::App app{"Sightline: see which rays between two patches of a level are blocked, live.\n"
                 "Without options, opens the editor (on FILE if given)."};
    Arguments args;
    const OptionHandles handles = addOptions(app, args);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // One line, as sightline-cli does (CLI11's default adds a second "Run with --help").
        std::fprintf(stderr, "sightline: error: %s (see --help)\n", e.what());
        return 2;
    }
    int width = 0, height = 0;
    if (const int refused = checkArguments(app, args, handles, width, height))
        return refused;
    return run(args, width, height, argc, argv);
}
