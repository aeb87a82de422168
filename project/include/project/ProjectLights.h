#pragma once
// The project's "lights" key (docs/lights.md, a contract): a list of point, spot, directional and
// area lights, read into lighting/Light.h's model and written back from it.
//
//   {"type": "point", "position": p, "colour": c, "intensity": I, "range": R}
//   {"type": "spot", ...point..., "direction": d, "inner_angle": a, "outer_angle": b}
//   {"type": "directional", "direction": d, "colour": c, "intensity": E}
//   {"type": "area", "corner": o, "u": u, "v": v, "samples": [na, nb], "colour": c, "radiance": L,
//    "two_sided": false}
//
// Every light may carry a "name"; "colour" defaults to [1, 1, 1], "intensity" and "radiance" to 1,
// a spot's angles to glTF's 0 and pi/4, an area light's samples to [32, 32] (a patch's default),
// "range" to none. Keys a light does not know are kept (the whole list stays in Project::extra,
// so a load/save round trip writes it back as read).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lighting/Light.h"
#include "project/Project.h"

namespace sightline {

/// Parses a "lights" value. Throws sightline::Error naming `what` and the key
/// ("p.json: 'lights[2].intensity' must be a finite number >= 0").
std::vector<Light> parseLights(const nlohmann::json& value, const std::string& what);

/// The project's lights (none without the key), validated.
std::vector<Light> projectLights(const Project& project);

/// The lights a glTF scene file places with KHR_lights_punctual (plugins/GltfLights.h), as lights
/// of the project, validated (keys "<file>: KHR light i"); none for other formats.
std::vector<Light> sceneFileLights(const Project& project, std::vector<std::string>* warnings = nullptr);

/// The project's "lights" when it has the key, else the scene file's own lights (a level exported
/// with its lights lights itself until the designer writes a list). `fromScene` says which.
std::vector<Light> lightsToUse(const Project& project, bool* fromScene = nullptr);

/// One light as the "lights" key writes it (defaults written out, so the file says what it means).
nlohmann::json lightJson(const Light& light);

} // namespace sightline
