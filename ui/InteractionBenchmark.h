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
    /// With the AO preview started at the first counted frame (issue 18: the editor stays live
    /// while k = 258 completes): the frames shown while it was computing, their median rate and
    /// 90th percentile, and when k = 258 was shown (0: not within the run).
    int aoFrames = 0;
    double aoMedianHz = 0.0;
    double aoP90FrameMs = 0.0;
    double aoDoneMs = 0.0;
};

/// Frame `frame` of `frames` of the scripted drag: the receiver slides within its own plane
/// (so a valid pair stays valid), a Lissajous figure of 30% of its width and 20% of its height.
Patch scriptedReceiver(const Patch& start, int frame, int frames);

/// Shows the window with a width x height viewport, runs `frames` frames (after 10 of warm-up)
/// and restores the receiver. `withAo`: the level's AO preview starts at the first counted frame.
InteractionFigures runInteractionBenchmark(MainWindow& window, int frames, int width = 1280, int height = 720,
                                           bool withAo = false);

} // namespace sightline::ui
