#include "InteractionBenchmark.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <QApplication>
#include <QElapsedTimer>
#include <QEventLoop>
#include <QTimer>

#include "MainWindow.h"
#include "Viewport.h"

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

/// Runs the event loop until the viewport shows a new answer (or 10 s passed).
void waitForAnswer(Viewport& viewport)
{
    QEventLoop loop;
    QObject::connect(&viewport, &Viewport::visibilityUpdated, &loop, &QEventLoop::quit);
    QTimer::singleShot(10'000, &loop, &QEventLoop::quit);
    loop.exec();
}

} // namespace

Patch scriptedReceiver(const Patch& start, int frame, int frames)
{
    const double t = 2.0 * std::numbers::pi * double(frame) / std::max(frames, 1);
    Patch p = start;
    p.corner += 0.3 * std::sin(t) * start.u + 0.2 * std::sin(2.0 * t) * start.v;
    return p;
}

InteractionFigures runInteractionBenchmark(MainWindow& window, int frames, int width, int height, bool withAo)
{
    InteractionFigures figures;
    figures.width = width;
    figures.height = height;
    window.viewportContainer()->setFixedSize(width, height);
    window.show();
    Viewport& viewport = window.viewport();
    QElapsedTimer wait;
    wait.start();
    while (!viewport.isExposed() && wait.elapsed() < 10'000)
        QApplication::processEvents(QEventLoop::AllEvents, 50);

    EditorDocument& document = window.document();
    const ObjectRef receiver{ObjectKind::Receiver, 0};
    const Patch start = document.project().receiver;
    // A drag as a hand makes it: the receiver moves on to its next position after every frame
    // drawn, whether or not an answer came (the sampler works on a worker thread, the latest
    // request wins). An update is an answer shown; the figure is the interval between them.
    int step = 0;
    const auto move = QObject::connect(&viewport, &QOpenGLWindow::frameSwapped, &viewport, [&] {
        document.applyState(receiver, scriptedReceiver(start, ++step, frames));
    });
    constexpr int kWarmUp = 10;
    std::vector<double> frameMs, sampleMs, aoFrameMs;
    double visible = 0.0;
    QElapsedTimer clock, aoClock;
    document.applyState(receiver, scriptedReceiver(start, step, frames));
    for (int f = -kWarmUp; f < frames; ++f) {
        if (f == 0) {
            clock.start();
            if (withAo) {
                viewport.setAmbientOcclusion(true);
                aoClock.start();
            }
        }
        const bool aoComputing = withAo && f >= 0 && figures.aoDoneMs == 0.0;
        waitForAnswer(viewport);
        if (f < 0)
            continue;
        frameMs.push_back(double(clock.nsecsElapsed()) * 1e-6);
        if (aoComputing) {
            aoFrameMs.push_back(frameMs.back());
            if (viewport.aoLevel() >= 258)
                figures.aoDoneMs = double(aoClock.nsecsElapsed()) * 1e-6;
        }
        clock.restart();
        sampleMs.push_back(viewport.visibility().ms);
        visible += viewport.visibility().visibleFraction();
    }
    QObject::disconnect(move);
    document.applyState(receiver, start);
    waitForAnswer(viewport);

    figures.frames = frames;
    figures.medianFrameMs = percentile(frameMs, 0.5);
    figures.p90FrameMs = percentile(frameMs, 0.9);
    figures.medianHz = figures.medianFrameMs > 0.0 ? 1000.0 / figures.medianFrameMs : 0.0;
    figures.medianSampleMs = percentile(sampleMs, 0.5);
    figures.aoFrames = int(aoFrameMs.size());
    figures.aoP90FrameMs = percentile(aoFrameMs, 0.9);
    const double aoMedian = percentile(aoFrameMs, 0.5);
    figures.aoMedianHz = aoMedian > 0.0 ? 1000.0 / aoMedian : 0.0;
    if (withAo)
        viewport.setAmbientOcclusion(false);
    figures.meanVisibleFraction = frames > 0 ? visible / frames : 0.0;
    figures.rays = viewport.visibility().rays;
    figures.raysDrawn = viewport.raysDrawn();
    figures.backend = viewport.backendName();
    return figures;
}

} // namespace sightline::ui
