#pragma once
// A recorded path: the camera, and the edits to the patches and placed occluders, sampled at a
// fixed rate while the designer worked in the editor. It is kept in the project
// file under the key "recorded_path" (the CLI keeps unknown keys, docs/design.md §3; this one it reads)
// and played back by the editor, and by `sightline --record`, which renders it to a video.
//
//   "recorded_path": {
//     "fps": 30,                                  // samples per second of the recording
//     "frames": 312,                              // its length (the last sample + 1)
//     "camera": [                                 // a key where the camera changed
//       {"frame": 0, "target": [x, y, z], "distance": 9.5, "yaw": 1.2, "pitch": -0.6, "fov_y": 0.87},
//       {"frame": 90, ..., "orthographic": true},   // only where it is (absent: perspective)
//       ...],
//     "edits": [                                  // a key where an object changed
//       {"frame": 0,  "object": "receiver", "corner": [x, y, z], "u": [...], "v": [...]},
//       {"frame": 40, "object": "occluder", "index": 0, "name": "box 1", "transform": [16 numbers]},
//       ...]
//   }
//
// Keys hold (step interpolation): at frame f the camera is its last key at or before f, and each
// object is its last edit at or before f (its first one before that). Keys are written only where
// something changed, so a recording of mostly still work stays small, and the playback is exact at
// every recorded frame. The recorder writes each edited object's state at the start as a frame-0
// key; objects without edits keep the project's state. An occluder key applies to occluder `index`
// of the project only while that occluder still has the recorded `name` (one deleted or renamed
// after recording is left alone); patch keys move corner, u and v, never the sample counts.
// Camera fields are those of the editor's saved view ("editor": {"camera": ...}).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "project/Project.h"

namespace sightline {

inline constexpr const char* kRecordedPathKey = "recorded_path";
inline constexpr int kMaxRecordedFrames = 1'000'000;   ///< about 9 hours at 30 fps
/// The most keys in each of "camera" and "edits" (a key where something changed: a long session of
/// constant dragging at 30 fps is about 20,000), checked on the arrays' sizes before a key is read.
inline constexpr std::size_t kMaxPathKeys = 100'000;

/// An orbit camera, in the fields of ui::Camera (target, eye distance, yaw, pitch, vertical fov).
struct PathCamera {
    glm::dvec3 target{0.0};
    double distance = 10.0;
    double yaw = 0.0;
    double pitch = -0.3;
    double fovY = 0.8727;
    bool orthographic = false;   ///< top / front / side and 5
    bool operator==(const PathCamera&) const = default;
};

struct PathCameraKey {
    int frame = 0;
    PathCamera camera;
};

struct PathEdit {
    enum class Object { Source, Receiver, Occluder };
    int frame = 0;
    Object object = Object::Source;
    Patch patch;                     ///< Source, Receiver: corner, u and v
    std::size_t index = 0;           ///< Occluder: its index in the project
    std::string name;                ///< Occluder: its name when recorded
    glm::mat4 transform{1.0f};       ///< Occluder
};

struct RecordedPath {
    double fps = 30.0;
    int frames = 0;
    std::vector<PathCameraKey> camera;   ///< by frame, increasing
    std::vector<PathEdit> edits;         ///< by frame, non-decreasing

    bool empty() const { return frames <= 0; }
    double seconds() const { return fps > 0.0 ? frames / fps : 0.0; }
    /// The camera at `frame`, or nullopt when the path has no camera key.
    std::optional<PathCamera> cameraAt(int frame) const;
    /// The path's frame shown at `seconds` (held at the last frame past the end).
    int frameAtTime(double seconds) const;
};

/// project.extra["recorded_path"], or an empty path when absent. Throws sightline::Error naming
/// the key: "demo.json: 'recorded_path.camera[3].frame' must be greater than the previous key's";
/// also for more than kMaxPathKeys keys, and an occluder transform that is not affine (last row
/// 0, 0, 0, 1: a projective one would warp the occluder). The patches' validity per frame is
/// checked where a run plays the path (validateMotionFrames, project/ProjectMotion.h).
RecordedPath parseRecordedPath(const Project& project, const std::string& what);
nlohmann::json toJson(const RecordedPath& path);
/// Stores the path under "recorded_path" (an empty path removes the key).
void setRecordedPath(Project& project, const RecordedPath& path);

/// The project with the path's edits applied at `frame`.
Project projectAtPathFrame(const Project& project, const RecordedPath& path, int frame);

} // namespace sightline
