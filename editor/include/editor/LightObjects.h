#pragma once
// Lights as objects the editor places, moves and picks (the project's "lights" key,
// docs/lights.md): a light's place as the transform the gizmo edits, and back into the light's
// own keys. Plain values and free functions (no Qt), so the tests and the headless renderer use
// them as the editor does.
//
// The transform's origin is where the light is drawn and picked: a point or spot light's
// position, an area light's centre, a sun's anchor above the level (a directional light has no
// place, so moving a sun changes nothing). Column 2 is the way a spot or a sun shines, or an area
// light's emitting normal; an area light's columns 0 and 1 are its edges u and v, so the gizmo's
// scale handles resize it.

#include <optional>
#include <string>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "editor/Camera.h"
#include "lighting/Light.h"
#include "visibility/Scene.h"

namespace sightline::ui {

/// Where the view draws a directional light: over the middle of the level's box (1 m above it;
/// the origin's column for an empty level).
glm::dvec3 sunAnchor(const Bounds& level);

/// The point a light is drawn, picked and pivoted at.
glm::dvec3 lightPivot(const Light& light, const Bounds& level);

glm::mat4 lightTransform(const Light& light, const Bounds& level);

/// One entry of "lights" with its place set from `transform` (position; direction; an area
/// light's corner, u and v), every other key kept as it was. `type` is the entry's type.
nlohmann::json placedLightJson(nlohmann::json light, LightType type, const glm::mat4& transform);

/// A new light of `type` named `name` at `at`; spots and suns shine down, an area light hangs
/// level 0.5 m x 0.5 m facing down, with 4 x 4 samples. Intensities give a few hundred lux a metre
/// or two away, so the light shows at once in the lit view.
nlohmann::json newLightJson(LightType type, const glm::dvec3& at, const std::string& name);

/// A new light of `type` named `name` placed on the surface a click hit at `point` (unit `normal`
/// facing the viewer): a point light 0.3 m out from it, a spot 0.1 m out shining along the normal
/// (mounted on a ceiling it shines down, on a wall into the room), an area light lying on it 1 cm
/// out and emitting along the normal. A sun has no place: newLightJson's. Other keys as newLightJson.
nlohmann::json lightOnSurfaceJson(LightType type, const glm::dvec3& point, const glm::dvec3& normal, const std::string& name);

/// Distance along `ray` to the light's marker when the ray passes within `radius` of its pivot
/// (or, for an area light, crosses its rectangle).
std::optional<double> pickLight(const Light& light, const Bounds& level, const Ray& ray, double radius);

} // namespace sightline::ui
