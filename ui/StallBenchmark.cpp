#include "StallBenchmark.h"

#include <algorithm>
#include <fstream>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <QApplication>
#include <QElapsedTimer>
#include <QEventLoop>
#include <QTimer>

#include "MainWindow.h"
#include "OverlayControls.h"
#include "Viewport.h"
#include "project/Animation.h"

namespace sightline::ui {

namespace {

/// Ticks every millisecond while it lives and keeps the longest gap between ticks.
class StallWatch {
public:
    StallWatch()
    {
        clock_.start();
        timer_.setTimerType(Qt::PreciseTimer);
        timer_.setInterval(1);
        QObject::connect(&timer_, &QTimer::timeout, [this] { tick(); });
        timer_.start();
    }
    /// Ends the phase: the gap up to now counts too.
    StallPhase finish()
    {
        tick();
        phase_.ms = double(clock_.nsecsElapsed()) * 1e-6;
        return phase_;
    }

private:
    void tick()
    {
        const double now = double(clock_.nsecsElapsed()) * 1e-6;
        const double gap = now - last_;
        if (gap > phase_.longestStallMs) {
            phase_.longestStallMs = gap;
            phase_.at = last_;
        }
        phase_.stallsOver50Ms += gap > 50.0;
        last_ = now;
    }
    QElapsedTimer clock_;
    QTimer timer_;
    double last_ = 0.0;
    StallPhase phase_;
};

/// Runs the event loop until `done()` (checked every 5 ms) or `ms` passed.
template <class Done>
void runUntil(Done done, int ms)
{
    QEventLoop loop;
    QTimer poll;
    poll.setInterval(5);
    QObject::connect(&poll, &QTimer::timeout, &loop, [&] {
        if (done())
            loop.quit();
    });
    QTimer::singleShot(ms, &loop, &QEventLoop::quit);
    poll.start();
    loop.exec();
}

} // namespace

std::filesystem::path stallBenchmarkProject(const std::filesystem::path& file, std::optional<std::pair<int, int>> grid,
                                            int frames, const std::filesystem::path& folder, bool* addedAnimation)
{
    nlohmann::json document = nlohmann::json::parse(std::ifstream(file));
    const bool animated = document.contains("animation");
    if (addedAnimation)
        *addedAnimation = !animated;
    if (animated && !grid)
        return file;
    if (document.contains("scene") && document["scene"].is_string()) {
        const std::filesystem::path scene = document["scene"].get<std::string>();
        if (scene.is_relative())
            document["scene"] = std::filesystem::absolute(file.parent_path() / scene).lexically_normal().string();
    }
    if (grid)
        document["receiver"]["samples"] = {grid->first, grid->second};
    if (!animated)
        document["animation"] = {{"frames", frames},
                                 {"tracks", {{{"target", "receiver"}, {"interpolation", "step"}, {"loop", true},
                                              {"keys", {{{"frame", 0}, {"translate", {0, 0, 0}}},
                                                        {{"frame", 1}, {"translate", nlohmann::json::array()}}}}}}}};
    if (!animated) {
        // The step: 0.5 m along the receiver's width.
        const auto& u = document["receiver"]["u"];
        const glm::dvec3 width(u[0].get<double>(), u[1].get<double>(), u[2].get<double>());
        const glm::dvec3 step = 0.5 * glm::normalize(width);
        document["animation"]["tracks"][0]["keys"][1]["translate"] = {step.x, step.y, step.z};
    }
    std::filesystem::create_directories(folder);
    const std::filesystem::path out = folder / file.filename();
    std::ofstream(out) << document.dump(2);
    return out;
}

StallFigures runStallBenchmark(MainWindow& window, const QString& file, int width, int height)
{
    StallFigures figures;
    window.viewportContainer()->setFixedSize(width, height);
    window.show();
    Viewport& viewport = window.viewport();
    runUntil([&] { return viewport.isExposed(); }, 10'000);
    runUntil([] { return false; }, 300);   // the empty window settles

    // The open is posted, as a menu click posts it: the watch sees the loop blocked by it.
    const auto open = [&] {
        StallWatch watch;
        bool opened = false;
        QTimer::singleShot(0, &window, [&] { opened = window.openFile(file); });
        runUntil([&] { return opened && !viewport.resultIsStale() && viewport.visibility().rays > 0 && viewport.levelDrawn(); },
                 600'000);
        const StallPhase phase = watch.finish();
        runUntil([] { return false; }, 300);
        return phase;
    };
    figures.firstOpen = open();
    figures.open = open();

    const Animation animation = parseAnimation(window.document().project(), window.document().displayName().toStdString());
    if (animation.empty())
        return figures;
    figures.frames = defaultFrameCount(animation);
    StallWatch watch;
    bool done = false, drawn = false;
    QTimer::singleShot(0, &window, [&] {
        window.overlayControls().accumulateAnimation();
        done = true;
    });
    runUntil([&] { return done; }, 3'600'000);
    // Until the next frame has drawn the result.
    const auto connection = QObject::connect(&viewport, &QOpenGLWindow::frameSwapped, [&] { drawn = true; });
    viewport.update();
    runUntil([&] { return drawn; }, 10'000);
    QObject::disconnect(connection);
    figures.accumulate = watch.finish();
    figures.shown = viewport.overlay().hasAnimationResult();
    return figures;
}

} // namespace sightline::ui
