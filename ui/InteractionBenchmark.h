#pragma once
// `sightline --benchmark-interaction`: drags the receiver along a scripted path in the real
// editor window (a new position after every frame drawn) and measures the interval between
// answers shown, sampling and drawing included. A benchmark (figures printed), not a test.

#include <string>

#include "visibility/Patch.h"

namespace sightline::ui {

class MainWindow;

struct InteractionFigures {
    int frames = 0;
    int width = 0, height = 0;
    double medianHz = 0.0;
    double medianFrameMs = 0.0;
    double p90FrameMs = 0.0;
    double medianSampleMs = 0.0;
    double meanVisibleFraction = 0.0;
    std::uint64_t rays = 0;
    std::uint64_t raysDrawn = 0;
    std::string backend;
};

/// Frame `frame` of `frames` of the scripted drag: the receiver slides within its own plane
/// (so a valid pair stays valid), a Lissajous figure of 30% of its width and 20% of its height.
Patch scriptedReceiver(const Patch& start, int frame, int frames);

/// Shows the window with a width x height viewport, runs `frames` frames (after 10 of warm-up)
/// and restores the receiver.
InteractionFigures runInteractionBenchmark(MainWindow& window, int frames, int width = 1280, int height = 720);

} // namespace sightline::ui
