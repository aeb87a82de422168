#pragma once
// Scripted motion in a project file, for importance maps accumulated over time (Eisemann &
// Décoret §9: "accumulation over time ... allows to investigate the impact of moving objects").
//
// Optional key "animation" of the project document (kept verbatim on save like any extra key):
//
//   "animation": {
//     "frames": 60,                                 // optional: frames an accumulation runs
//     "tracks": [
//       {"target": "occluder", "name": "door",      // or "source" / "receiver" (no name)
//        "interpolation": "linear",                 // or "step"
//        "loop": true,                              // repeat every (last key frame + 1) frames
//        "keys": [{"frame": 0, "translate": [0, 0, 0]},
//                 {"frame": 30, "translate": [0, 0, 1.5]}]}
//     ]
//   }
//
// A track moves its target by the interpolated translation, added to the position the project
// gives it (a patch's corner; an occluder's transform, applied after it). Before the first key
// and after the last (without loop) the nearest key holds. Two step keys at frames 0 and 1 with a
// loop alternate between two configurations, which is how the tests check accumulation.

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "project/Project.h"

namespace sightline {

struct AnimationKey {
    int frame = 0;
    glm::dvec3 translate{0.0};
};

struct AnimationTrack {
    enum class Target { Source, Receiver, Occluder };
    Target target = Target::Occluder;
    std::string name;   ///< the occluder's name (Target::Occluder)
    bool step = false;  ///< hold each key until the next instead of interpolating
    bool loop = false;
    std::vector<AnimationKey> keys;   ///< sorted by frame, at least one

    /// The translation at `frame` (>= 0).
    glm::dvec3 offsetAt(int frame) const;
};

struct Animation {
    int frames = 0;   ///< 0: not given
    std::vector<AnimationTrack> tracks;
    bool empty() const { return tracks.empty(); }
    /// Whether any track moves an occluder (the scene must be rebuilt per frame).
    bool movesOccluders() const;
};

inline constexpr int kMaxAnimationFrames = 100000;

/// The frames an accumulation runs when the user names no count (the CLI's `importance` without
/// --frames, the editor's Accumulate Animation; both call this so that one project gives one
/// answer): the animation's "frames" when given; else the last key frame + 1 over all tracks, so
/// that every keyed motion plays to its end once (a looping track's whole cycle) and nothing the
/// author keyed is left out; else 1 (no tracks: the project does not move).
int defaultFrameCount(const Animation& animation);

/// Reads project.extra["animation"] (an empty Animation when absent). Throws sightline::Error
/// naming the key: unknown target, a name that matches no occluder, keys out of order, ...
Animation parseAnimation(const Project& project, const std::string& what);

/// The project with every track applied at `frame`.
Project projectAtFrame(const Project& project, const Animation& animation, int frame);

} // namespace sightline
