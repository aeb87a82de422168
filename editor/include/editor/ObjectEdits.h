#pragma once
// The objects a designer edits (the two patches, placed occluders, objects of the scene file) and
// the geometric edits the gizmo and the properties panel apply to them. Plain values and free
// functions: the undo commands store before/after states, the gizmo computes new ones.

#include <array>
#include <cstddef>
#include <variant>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "visibility/Patch.h"

namespace sightline::ui {

enum class ObjectKind { None, Source, Receiver, Occluder, SceneObject, Light };

/// Which object: a patch, occluder `index` of the project, instance `index` of the scene file, or
/// light `index` of the project's "lights" (LightObjects.h).
struct ObjectRef {
    ObjectKind kind = ObjectKind::None;
    std::size_t index = 0;

    bool isPatch() const { return kind == ObjectKind::Source || kind == ObjectKind::Receiver; }
    explicit operator bool() const { return kind != ObjectKind::None; }
    bool operator==(const ObjectRef&) const = default;
};

/// A patch, or an object's column-major world transform.
using ObjectState = std::variant<Patch, glm::mat4>;

/// Centre of a patch; origin of a transform.
glm::dvec3 pivotOf(const ObjectState& state);
/// Unit axes the scale handles use: a patch's u, v and normal; a transform's columns.
std::array<glm::dvec3, 3> localAxesOf(const ObjectState& state);

ObjectState translated(const ObjectState& state, const glm::dvec3& delta);
/// Rotation by `angle` radians about the line through the object's pivot along `axis` (unit).
ObjectState rotated(const ObjectState& state, const glm::dvec3& axis, double angle);
/// Scales along local axis 0, 1 or 2 about the pivot. A patch has no extent along its normal
/// (axis 2), so that is a no-op. `factor` must be positive.
ObjectState scaled(const ObjectState& state, int axis, double factor);

/// Euler angles (degrees, applied X then Y then Z) and scale of a transform, for the panel.
struct Decomposed {
    glm::dvec3 position{0.0};
    glm::dvec3 rotationDegrees{0.0};
    glm::dvec3 scale{1.0};
};
Decomposed decompose(const glm::mat4& transform);
glm::mat4 compose(const Decomposed& parts);

} // namespace sightline::ui
