#pragma once
// What moves a project from frame to frame when importance is accumulated over time (Eisemann &
// Décoret §9): its scripted animation (project/Animation.h), or the path the designer recorded in
// the editor (project/RecordedPath.h: frame f of the run is frame f of the path, its edits to the
// patches and placed occluders applied; the camera plays no part in sampling). The CLI's
// `importance` (`--path`), the editor's Accumulate Animation / Accumulate Recorded Path and
// ImportanceRun all read a project's frames through this, so one project gives one answer.

#include <string>

#include "project/Animation.h"
#include "project/RecordedPath.h"

namespace sightline {

struct ProjectMotion {
    enum class Kind { Animation, RecordedPath };
    Kind kind = Kind::Animation;
    Animation animation;   ///< Kind::Animation
    RecordedPath path;     ///< Kind::RecordedPath

    static ProjectMotion of(Animation animation);
    static ProjectMotion of(RecordedPath path);

    /// Nothing moves: no animation track, or no recorded frame.
    bool empty() const;
    /// The frames a run takes when the user names no count: the animation's defaultFrameCount, or
    /// the path's length (one run frame per recorded frame); 1 when empty.
    int defaultFrames() const;
    /// The project at `frame` (>= 0; a path holds its last frame past its end).
    Project at(const Project& project, int frame) const;
    /// Whether what sampling sees (the patches, the occluders' transforms) may differ at `frame`
    /// from `frame - 1`. False only where that is certain: a path frame with no edit key. A run
    /// reuses the previous frame's map there, which the exact, deterministic sampler would
    /// have answered anyway (a recorded path holds most objects still most of the time).
    bool mayChangeAt(int frame) const;
    /// "animation" or "recorded path", for messages.
    std::string name() const;
};

/// `project` without its "animation" and "recorded_path" keys, which sampling does not read: what
/// a run copies for each frame (a long recorded path is most of the document).
Project withoutMotionKeys(Project project);

/// Throws sightline::Error when the patches at any of frames [0, frames) of `motion` over `base`
/// are not a valid pair (validatePatchPair: degenerate, a receiver across the source's plane, out
/// of range), naming the frame ("frame 12: ...") when there is more than one. What every run over a
/// motion checks before its expensive work (`importance`, `sightline --record`), so that no run
/// renders or accumulates what another refuses. `base` is withoutMotionKeys of the project.
void validateMotionFrames(const Project& base, const ProjectMotion& motion, int frames);

/// The project's motion of `kind`: parseAnimation or parseRecordedPath (throws sightline::Error
/// naming the key when it is malformed; an absent key gives an empty motion).
ProjectMotion parseProjectMotion(const Project& project, ProjectMotion::Kind kind, const std::string& what);

} // namespace sightline
