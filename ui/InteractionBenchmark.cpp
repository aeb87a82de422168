#include "InteractionBenchmark.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <numbers>
#include <utility>
#include <vector>

#include <QApplication>
#include <QElapsedTimer>
#include <QEventLoop>
#include <QTimer>

#include <glm/gtc/matrix_transform.hpp>

#include "EditorDocument.h"
#include "MainWindow.h"
#include "PathPlayback.h"
#include "Viewport.h"
#include "ViewportController.h"
#include "lighting/Light.h"
#include "project/ProjectMotion.h"
#include "base/Error.h"

namespace sightline::ui {

namespace {

double percentile(std::vector<double> values, double q)
{
    if (values.empty())
        return 0.0;
    const auto k = std::size_t(std::clamp(q, 0.0, 1.0) * double(values.size() - 1));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return values[k];
}

constexpr int kWarmUp = 10;

/// Processor time of this process, all threads, in ms.
double processCpuMs()
{
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

/// Runs the event loop until `done()` holds (checked after every event batch) or `ms` passed.
template <class Done>
void runUntil(Done done, int ms)
{
    QEventLoop loop;
    QTimer poll;
    poll.setInterval(10);
    QObject::connect(&poll, &QTimer::timeout, &loop, [&] {
        if (done())
            loop.quit();
    });
    QTimer::singleShot(ms, &loop, &QEventLoop::quit);
    poll.start();
    if (!done())
        loop.exec();
}

/// Processes events until the viewport is exposed (10 s at most).
void waitUntilExposed(Viewport& viewport)
{
    QElapsedTimer wait;
    wait.start();
    while (!viewport.isExposed() && wait.elapsed() < 10'000)
        QApplication::processEvents(QEventLoop::AllEvents, 50);
}

/// What runInteractionBenchmark's frames measured, summarised into its figures once it is over.
struct InteractionSamples {
    std::vector<double> answerMs, drawMs, frameMs, sampleMs, aoAnswerMs;
    double visible = 0.0;
    int drawn = 0;
    double cpuMs = 0.0, wallMs = 0.0;
};

/// Runs the motion (warm-up, then the counted frames) and collects its intervals; the AO preview's
/// completion is written into `figures` as it happens.
InteractionSamples measureInteraction(MainWindow& window, const InteractionOptions& options, const Project& start,
                                      const RecordedPath& path, InteractionFigures& figures)
{
    EditorDocument& document = window.document();
    Viewport& viewport = window.viewport();
    ViewportController& controller = window.controller();
    const bool replayPath = options.replay == InteractionReplay::RecordedPath;

    // A motion as a hand makes it: the next pose after every frame drawn, whether or not an answer
    // came (the sampler works on a worker thread, the latest request wins).
    const ObjectRef receiver{ObjectKind::Receiver, 0};
    const Project base = withoutMotionKeys(start);
    int step = 0;
    const auto pose = [&] {
        if (!replayPath) {
            document.applyState(receiver, scriptedReceiver(start.receiver, step, options.frames));
            return;
        }
        const int frame = step % path.frames;
        showPathFrame(document, controller, base, path, frame);
        if (options.posed)
            options.posed(frame);
        viewport.update();   // a pose that moves nothing is drawn too
    };

    // The drag counts answers shown; the path counts frames drawn (a path frame that moves no
    // patch needs no answer).
    std::vector<double> answerMs, drawMs, frameMs, sampleMs;
    double visible = 0.0;
    int counted = 0, drawn = 0;
    bool measuring = false;
    const int wanted = kWarmUp + options.frames;
    QEventLoop loop;
    QElapsedTimer answerClock, frameClock, measured, aoClock;
    std::vector<double> aoAnswerMs;
    double cpuStart = 0.0;
    const auto startMeasuring = [&] {
        measuring = true;
        answerClock.start();
        measured.start();
        cpuStart = processCpuMs();
        drawn = 0;
        if (options.withAo) {
            viewport.setAmbientOcclusion(true);
            aoClock.start();
        }
    };
    const auto drawnConnection = QObject::connect(&viewport, &QOpenGLWindow::frameSwapped, &viewport, [&] {
        ++drawn;
        if (measuring) {
            drawMs.push_back(viewport.lastDrawMs());
            frameMs.push_back(double(frameClock.nsecsElapsed()) * 1e-6);
        }
        frameClock.restart();
        if (replayPath && ++counted == kWarmUp)
            startMeasuring();
        if (replayPath && counted >= wanted) {
            loop.quit();
            return;
        }
        ++step;
        pose();
    });
    const auto answerConnection = QObject::connect(&viewport, &Viewport::visibilityUpdated, &viewport, [&] {
        if (!replayPath && ++counted == kWarmUp) {
            startMeasuring();
            return;
        }
        if (!measuring)
            return;
        answerMs.push_back(double(answerClock.nsecsElapsed()) * 1e-6);
        answerClock.restart();
        if (options.withAo && figures.aoDoneMs == 0.0) {   // shown while the AO was computing
            aoAnswerMs.push_back(answerMs.back());
            if (viewport.aoLevel() >= 258)
                figures.aoDoneMs = double(aoClock.nsecsElapsed()) * 1e-6;
        }
        sampleMs.push_back(viewport.visibility().ms);
        visible += viewport.visibility().visibleFraction();
        if (!replayPath && kWarmUp + int(answerMs.size()) >= wanted)
            loop.quit();
    });
    frameClock.start();
    pose();
    QTimer::singleShot(std::min(wanted, 100'000) * 20'000, &loop, &QEventLoop::quit);   // 20 s for the slowest frame
    loop.exec();
    const double cpuMs = measuring ? processCpuMs() - cpuStart : 0.0;
    const double wallMs = measuring ? double(measured.nsecsElapsed()) * 1e-6 : 0.0;
    QObject::disconnect(drawnConnection);
    QObject::disconnect(answerConnection);
    if (options.withAo)
        viewport.setAmbientOcclusion(false);
    return {std::move(answerMs), std::move(drawMs), std::move(frameMs), std::move(sampleMs), std::move(aoAnswerMs),
            visible, drawn, cpuMs, wallMs};
}

/// The figures the samples give: intervals, rates, processor time and the AO preview's updates.
void summariseInteraction(const InteractionSamples& s, InteractionFigures& figures)
{
    figures.answers = int(s.answerMs.size());
    figures.medianFrameMs = percentile(s.answerMs, 0.5);
    figures.p90FrameMs = percentile(s.answerMs, 0.9);
    figures.medianHz = figures.medianFrameMs > 0.0 ? 1000.0 / figures.medianFrameMs : 0.0;
    figures.medianSampleMs = percentile(s.sampleMs, 0.5);
    figures.medianDrawMs = percentile(s.drawMs, 0.5);
    figures.p90DrawMs = percentile(s.drawMs, 0.9);
    const double medianFrame = percentile(s.frameMs, 0.5);
    figures.drawnHz = medianFrame > 0.0 ? 1000.0 / medianFrame : 0.0;
    figures.cpuMsPerAnswer = s.answerMs.empty() ? 0.0 : s.cpuMs / double(s.answerMs.size());
    figures.cpuLoad = s.wallMs > 0.0 ? s.cpuMs / s.wallMs : 0.0;
    figures.aoFrames = int(s.aoAnswerMs.size());
    figures.aoP90FrameMs = percentile(s.aoAnswerMs, 0.9);
    const double aoMedian = percentile(s.aoAnswerMs, 0.5);
    figures.aoMedianHz = aoMedian > 0.0 ? 1000.0 / aoMedian : 0.0;
    figures.framesPerAnswer = s.answerMs.empty() ? 0.0 : double(s.drawn) / double(s.answerMs.size());
    figures.meanVisibleFraction = s.answerMs.empty() ? 0.0 : s.visible / double(s.answerMs.size());
}

} // namespace

Patch scriptedReceiver(const Patch& start, int frame, int frames)
{
    const double t = 2.0 * std::numbers::pi * double(frame) / std::max(frames, 1);
    Patch p = start;
    p.corner += 0.3 * std::sin(t) * start.u + 0.2 * std::sin(2.0 * t) * start.v;
    return p;
}

InteractionFigures runInteractionBenchmark(MainWindow& window, const InteractionOptions& options)
{
    EditorDocument& document = window.document();
    const Project start = document.project();
    RecordedPath path;
    const bool replayPath = options.replay == InteractionReplay::RecordedPath;
    if (replayPath) {
        path = parseRecordedPath(start, document.displayName().toStdString());
        if (path.empty())
            throw Error(document.displayName().toStdString() +
                        " has no recorded path (\"recorded_path\"): record one in the editor (F9), or drag instead");
    }

    InteractionFigures figures;
    figures.width = options.width;
    figures.height = options.height;
    figures.replay = replayPath ? "recorded path, " + std::to_string(path.frames) + " frames" : "scripted drag";
    window.viewportContainer()->setFixedSize(options.width, options.height);
    window.show();
    Viewport& viewport = window.viewport();
    ViewportController& controller = window.controller();
    const Camera camera = controller.camera();
    waitUntilExposed(viewport);

    const InteractionSamples samples = measureInteraction(window, options, start, path, figures);

    // Back to where it started.
    showProjectState(document, start);
    controller.setCamera(camera);
    runUntil([&] { return !viewport.resultIsStale(); }, 10'000);

    figures.frames = options.frames;
    summariseInteraction(samples, figures);
    figures.rays = viewport.visibility().rays;
    figures.raysDrawn = viewport.raysDrawn();
    figures.backend = viewport.backendName();
    return figures;
}

namespace {

/// Where a light shines from (an area light's centre).
glm::dvec3 lightCentre(const Light& light)
{
    return light.type == LightType::Area ? light.area.centre() : light.position;
}

/// Moves an occluder (the project's first, else a box added a metre under the first light, taken
/// away after) half a metre at a time, and counts the lit frames shown until the view is exact.
void measureOccluderMoves(EditorDocument& document, Viewport& viewport, LitFigures& figures)
{
    constexpr int kMoves = 4;
    constexpr int kExactWithinMs = 300'000;
    const bool added = document.project().occluders.empty();
    if (added) {
        OccluderSpec box;
        box.mesh = "box";
        box.name = "benchmark box";
        const Light& light = document.lights().front();
        const glm::dvec3 under = light.type == LightType::Directional ? glm::dvec3(0.0) : lightCentre(light) - glm::dvec3(0.0, 1.0, 0.0);
        box.transform = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(under)), glm::vec3(0.6f));
        document.addOccluder(box);
        runUntil([&] { return viewport.litExact(); }, kExactWithinMs);
    }
    const ObjectRef occluder{ObjectKind::Occluder, 0};
    figures.occluder = document.occluder(0).name;
    std::vector<double> ms;
    int shown = 0;
    const auto counted = QObject::connect(&viewport, &Viewport::litUpdated, &viewport, [&] { ++shown; });
    for (int move = 0; move < kMoves; ++move) {
        const glm::dvec3 step = (move % 2 == 0 ? 0.5 : -0.5) * glm::dvec3(1.0, 0.0, 0.5);
        QElapsedTimer clock;
        clock.start();
        shown = 0;
        document.applyState(occluder, translated(document.state(occluder), step));
        runUntil([&] { return viewport.litExact(); }, kExactWithinMs);
        if (!viewport.litExact())
            break;
        ms.push_back(double(clock.nsecsElapsed()) * 1e-6);
        figures.occluderMostFrames = std::max(figures.occluderMostFrames, shown);
        ++figures.occluderMoves;
    }
    QObject::disconnect(counted);
    figures.occluderMedianMs = percentile(ms, 0.5);
    if (added)
        document.undoStack()->undo();
}

/// The camera orbits, one step a frame drawn, the lit view shown exact all the while.
void measureOrbit(MainWindow& window, Viewport& viewport, int frames, LitFigures& figures)
{
    ViewportController& controller = window.controller();
    const Camera camera = controller.camera();
    std::vector<double> drawnMs;
    QEventLoop orbitLoop;
    QElapsedTimer frameClock;
    const auto swapped = QObject::connect(&viewport, &QOpenGLWindow::frameSwapped, &viewport, [&] {
        drawnMs.push_back(double(frameClock.nsecsElapsed()) * 1e-6);
        frameClock.restart();
        if (int(drawnMs.size()) > frames) {
            orbitLoop.quit();
            return;
        }
        Camera next = controller.camera();
        orbit(next, 6.0, 0.0);
        controller.setCamera(next);
        viewport.update();
    });
    frameClock.start();
    viewport.update();
    QTimer::singleShot(std::min(frames, 100'000) * 2'000, &orbitLoop, &QEventLoop::quit);
    orbitLoop.exec();
    QObject::disconnect(swapped);
    controller.setCamera(camera);
    if (!drawnMs.empty())
        drawnMs.erase(drawnMs.begin());   // from the request, not a frame interval
    figures.orbitFrames = int(drawnMs.size());
    const double median = percentile(drawnMs, 0.5);
    figures.orbitHz = median > 0.0 ? 1000.0 / median : 0.0;
    figures.orbitP90FrameMs = percentile(drawnMs, 0.9);
}

/// Each lit frame moves the light on (1 m across and 0.5 m along, a Lissajous figure) as it
/// arrives; the interval counted is between the window's first swaps after each, so a frame
/// replaced before it was drawn is not counted.
void measureLightDrag(EditorDocument& document, Viewport& viewport, const ObjectRef& light, const ObjectState& start, int frames,
                      LitFigures& figures)
{
    int step = 0;
    std::vector<double> frameMs;
    QEventLoop loop;
    QElapsedTimer interval;
    bool toShow = false;
    const auto moveOn = [&] {
        const double t = 2.0 * std::numbers::pi * double(step) / double(std::max(frames, 1));
        document.applyState(light, translated(start, {0.5 * std::sin(t), 0.0, 0.25 * std::sin(2.0 * t)}));
        ++step;
    };
    const auto arrived = QObject::connect(&viewport, &Viewport::litUpdated, &viewport, [&](const QString&, bool, const QString& error) {
        if (!error.isEmpty()) {
            loop.quit();
            return;
        }
        toShow = step > 0;
        if (int(frameMs.size()) < frames)
            moveOn();
    });
    const auto shown = QObject::connect(&viewport, &QOpenGLWindow::frameSwapped, &viewport, [&] {
        if (!toShow)
            return;
        toShow = false;
        if (interval.isValid())
            frameMs.push_back(double(interval.nsecsElapsed()) * 1e-6);
        interval.restart();
        if (int(frameMs.size()) >= frames)
            loop.quit();
    });
    moveOn();
    QTimer::singleShot(std::min(frames, 100'000) * 20'000, &loop, &QEventLoop::quit);
    loop.exec();
    QObject::disconnect(arrived);
    QObject::disconnect(shown);
    figures.frames = int(frameMs.size());
    figures.medianFrameMs = percentile(frameMs, 0.5);
    figures.p90FrameMs = percentile(frameMs, 0.9);
    figures.medianHz = figures.medianFrameMs > 0.0 ? 1000.0 / figures.medianFrameMs : 0.0;
}

} // namespace

LitFigures runLitBenchmark(MainWindow& window, int frames, int width, int height)
{
    EditorDocument& document = window.document();
    if (document.lights().empty())
        throw Error(document.displayName().toStdString() + " has no lights to drag: add one (Create > Add Point Light) or a \"lights\" key");
    window.viewportContainer()->setFixedSize(width, height);
    window.show();
    Viewport& viewport = window.viewport();
    waitUntilExposed(viewport);

    LitFigures figures;
    figures.lights = document.lights().size();
    figures.dragged = displayName(document.lights(), 0);
    constexpr int kExactWithinMs = 300'000;
    QElapsedTimer clock;
    clock.start();
    viewport.setLitView(true);
    runUntil([&] { return viewport.litExact(); }, kExactWithinMs);
    if (viewport.litExact())
        figures.firstExactMs = double(clock.nsecsElapsed()) * 1e-6;
    figures.texels = viewport.litTexels();

    measureOrbit(window, viewport, frames, figures);

    const ObjectRef light{ObjectKind::Light, 0};
    const ObjectState start = document.state(light);
    measureLightDrag(document, viewport, light, start, frames, figures);

    // Let go where it started: the view refines to the exact answer.
    clock.restart();
    document.applyState(light, start);   // litExact() is false until a frame of the lights as they are now
    runUntil([&] { return viewport.litExact(); }, kExactWithinMs);
    if (viewport.litExact())
        figures.exactAgainMs = double(clock.nsecsElapsed()) * 1e-6;
    measureOccluderMoves(document, viewport, figures);

    // One bounce: on (every VPL lit), then the light moved once (its VPLs lit again, not all).
    clock.restart();
    viewport.setLitIndirect(true);
    runUntil([&] { return viewport.litExact(); }, kExactWithinMs);
    if (viewport.litExact())
        figures.bounceFirstExactMs = double(clock.nsecsElapsed()) * 1e-6;
    clock.restart();
    document.applyState(light, translated(start, {0.5, 0.0, 0.25}));
    runUntil([&] { return viewport.litExact(); }, kExactWithinMs);
    if (viewport.litExact())
        figures.bounceExactAgainMs = double(clock.nsecsElapsed()) * 1e-6;
    figures.vpls = viewport.litVpls();
    viewport.setLitIndirect(false);
    document.applyState(light, start);
    viewport.setLitView(false);
    return figures;
}

} // namespace sightline::ui
