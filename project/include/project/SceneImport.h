#pragma once
// The project's import settings (docs/design.md §3): "scene_up", the direction that is up in the scene
// file ("+y" by default, or "-y", "+z", "-z", "+x", "-x"), and "scene_scale", metres per file unit
// (1 by default; 0.0254 for Quake's inches). They turn and scale the scene file's objects (and the
// lights it places) before anything else: patches, occluders, lights, cells and moved objects'
// transforms are all in the turned and scaled world.
//
// The turn is the rotation taking the file's up to +Y about one axis: about X for ±z and -y
// (+z: (x, y, z) -> (x, z, -y), glTF's convention for a Z-up file; -z: (x, -z, y); -y: (x, -y, -z)),
// about Z for ±x (+x: (-y, x, z); -x: (y, -x, z)). Every one is a proper rotation (no mirror).

#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "project/Project.h"

namespace sightline {

inline constexpr const char* kSceneUpKey = "scene_up";
inline constexpr const char* kSceneScaleKey = "scene_scale";
/// The smallest and largest metres per file unit read (a micrometre to a kilometre).
inline constexpr double kMinSceneScale = 1e-6;
inline constexpr double kMaxSceneScale = 1e3;

struct SceneImport {
    std::string up = "+y";
    double scale = 1.0;
    bool identity() const { return up == "+y" && scale == 1.0; }
    /// world = transform * file: the turn times the scale.
    glm::dmat4 transform() const;
};

/// The project's settings; throws sightline::Error naming the key ("level.json: 'scene_up' must
/// be one of +y, -y, +z, -z, +x, -x, not 'up'") for anything else.
SceneImport sceneImport(const Project& project);
/// Writes them into the project's keys (the defaults remove the keys).
void setSceneImport(Project& project, const SceneImport& settings);

/// The scene file of `project` (empty when it names none), turned and scaled by its settings;
/// the objects the project moved are not applied (applySceneTransforms).
Scene loadLevel(const Project& project, std::vector<std::string>* warnings = nullptr);
/// Turns and scales a scene as `settings` say (every instance's transform).
void applySceneImport(const SceneImport& settings, Scene& scene);

/// A guess of the up axis of a level from its geometry, for a level that says nothing: the axis
/// along which the most triangle area faces (floors and ceilings, in a level whose walls spread
/// over the other two), pointing the way more of that area faces (floors, table tops and terrain
/// outweigh ceilings and undersides). "+y" for an empty scene. `transforms`, when given (one per
/// instance), stand for the instances' own: the level as its file has it, before the turn.
std::string guessSceneUp(const Scene& scene, std::span<const glm::mat4> transforms = {});

} // namespace sightline
