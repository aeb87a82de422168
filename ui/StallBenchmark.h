#pragma once
// `sightline --benchmark-stalls PROJECT`: the longest time the editor's event loop goes without
// running (a window that neither repaints nor answers input) while it opens a project, until the
// first answer for it is shown, and while it accumulates the project's animation (at
// most 100 ms on the demo floor with a 512x512 receiver). A 1 ms timer ticks throughout; a stall
// is the longest interval between two ticks. A benchmark (figures printed), not a test; the GUI
// test `aSlowUpdateLeavesTheEventLoopFree` keeps a generous bound.

#include <filesystem>
#include <optional>
#include <utility>

#include <QString>

namespace sightline::ui {

class MainWindow;

struct StallPhase {
    double ms = 0.0;              ///< how long the phase took
    double longestStallMs = 0.0;  ///< the longest interval between ticks in it
    double at = 0.0;              ///< when that stall began, ms from the start of the phase
    int stallsOver50Ms = 0;
};

struct StallFigures {
    /// The first open after the window appeared (software GL compiles its shaders on first use),
    /// and the same file opened again; each until the first answer for it is shown.
    StallPhase firstOpen, open;
    StallPhase accumulate;   ///< Accumulate Animation, from the click to the result drawn
    int frames = 0;          ///< animation frames accumulated
    bool shown = false;      ///< the accumulation's result was shown
};

/// The project the benchmark opens: `file` with the receiver's grid replaced by `grid` (when
/// given) and, when it has no animation, one of `frames` frames in which the receiver steps 0.5 m
/// along its width every other frame. Written into `folder` with the scene's path made absolute.
/// Returns the path written, or `file` itself when nothing needs changing.
std::filesystem::path stallBenchmarkProject(const std::filesystem::path& file, std::optional<std::pair<int, int>> grid,
                                            int frames, const std::filesystem::path& folder, bool* addedAnimation = nullptr);

/// Shows the window (width x height viewport), opens `file` twice, waiting for its first answer
/// each time, then accumulates its animation.
StallFigures runStallBenchmark(MainWindow& window, const QString& file, int width = 1280, int height = 720);

} // namespace sightline::ui
