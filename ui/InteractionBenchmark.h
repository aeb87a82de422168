#pragma once
// `sightline --benchmark-interaction`: moves things in the real editor window as a designer does
// (a new pose after every frame drawn) and measures the interval between answers shown, sampling
// and drawing included. A benchmark (figures printed), not a test. Two motions:
//   - the scripted drag: the receiver slides along a Lissajous figure within its plane;
//   - the project's recorded path (project/RecordedPath.h): its camera and edits, frame after
//     frame, as "Play Recorded Path" shows them (ui/PathPlayback.h), but one path frame per frame
//     drawn instead of at the path's own rate.

#include <cstdint>
#include <functional>
#include <string>

#include "project/RecordedPath.h"
#include "visibility/Patch.h"

namespace sightline::ui {

class MainWindow;

enum class InteractionReplay { Drag, RecordedPath };

struct InteractionOptions {
    int frames = 300;   ///< measured frames: answers (drag) or path frames drawn (recorded path)
    int width = 1280, height = 720;
    InteractionReplay replay = InteractionReplay::Drag;
    /// RecordedPath: called once each path frame is shown (before it is drawn), with its index.
    std::function<void(int pathFrame)> posed;
    /// The level's AO preview starts at the first counted frame (the editor stays live
    /// while k = 258 completes).
    bool withAo = false;
};

struct InteractionFigures {
    int frames = 0;
    int width = 0, height = 0;
    std::string replay;            ///< "scripted drag" or "recorded path, 312 frames"
    double medianHz = 0.0;         ///< answers shown per second (from the median interval)
    double medianFrameMs = 0.0;    ///< interval between answers shown: median, 90th percentile
    double p90FrameMs = 0.0;
    double medianSampleMs = 0.0;   ///< the sampler's time per answer (on its worker thread)
    /// Frames drawn: their rate, the time from the start of painting to the swap (median, 90th
    /// percentile) and how many were drawn per answer shown.
    double drawnHz = 0.0;
    double medianDrawMs = 0.0, p90DrawMs = 0.0;
    double framesPerAnswer = 0.0;
    int answers = 0;
    /// Processor time of the whole process (GUI thread, sampler, software rasteriser) per answer
    /// shown, and per second: on n cores an update cannot come faster than every cpuMsPerAnswer / n.
    double cpuMsPerAnswer = 0.0;
    double cpuLoad = 0.0;
    double meanVisibleFraction = 0.0;
    std::uint64_t rays = 0;
    std::uint64_t raysDrawn = 0;
    std::string backend;
    /// With the AO preview (InteractionOptions::withAo): the updates shown while it was computing,
    /// their median rate and 90th percentile, and when k = 258 was shown (0: not within the run).
    int aoFrames = 0;
    double aoMedianHz = 0.0;
    double aoP90FrameMs = 0.0;
    double aoDoneMs = 0.0;
};

/// The lit view measured as a designer uses it (View > Lit View): turned on (its first exact frame),
/// the camera orbited around the lit level, the project's first light dragged along a scripted path (lit frames shown a second while it
/// moves: each refreshes the lights the budget allows, the moved one first), then let go (how soon
/// the view is exact again); then an occluder moved a few times (how many lit frames until all
/// lights are fresh); then with one bounce of indirect light, the light moved once.
struct LitFigures {
    std::size_t lights = 0, texels = 0;
    std::string dragged;          ///< the light's name
    double firstExactMs = 0.0;    ///< lit view on -> its first exact frame shown (0: not within 5 min)
    /// The camera orbiting the exact lit view (the texels' light does not depend on the camera, so
    /// every frame drawn is exact): frames drawn a second, median and 90th percentile frame.
    int orbitFrames = 0;
    double orbitHz = 0.0, orbitP90FrameMs = 0.0;
    int frames = 0;               ///< lit frames shown while dragging
    double medianHz = 0.0, medianFrameMs = 0.0, p90FrameMs = 0.0;
    double exactAgainMs = 0.0;    ///< let go -> an exact frame shown (0: not within 5 min)
    /// An occluder moved (the project's first, or a box added under the dragged light), once per
    /// step: lit frames shown from the move to the first exact one, the most over the steps, and
    /// the median time.
    std::string occluder;
    int occluderMoves = 0;
    int occluderMostFrames = 0;
    double occluderMedianMs = 0.0;
    /// With one bounce of indirect light turned on: its first exact frame, then the dragged light
    /// moved once (0: not within 5 min).
    std::size_t vpls = 0;
    double bounceFirstExactMs = 0.0, bounceExactAgainMs = 0.0;
};
/// Throws sightline::Error when the project has no light to drag.
LitFigures runLitBenchmark(MainWindow& window, int frames, int width, int height);

/// Frame `frame` of `frames` of the scripted drag: the receiver slides within its own plane
/// (so a valid pair stays valid), a Lissajous figure of 30% of its width and 20% of its height.
Patch scriptedReceiver(const Patch& start, int frame, int frames);

/// Shows the window with a width x height viewport, runs the options' frames (after 10 of
/// warm-up) and restores the patches, occluders and camera. RecordedPath needs the project to
/// have one (throws sightline::Error otherwise, naming the key).
InteractionFigures runInteractionBenchmark(MainWindow& window, const InteractionOptions& options);

} // namespace sightline::ui
