#pragma once
// What the Quake importers (.bsp, .map) share: Quake's units and axes to the scene's, and the
// level's one mesh from its triangles' corners.

#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline {

/// Quake units (1 = an inch) with Z up to metres with Y up: Quake's Z becomes Y, its Y becomes -Z
/// (a rotation, so windings keep their sense).
inline glm::vec3 quakeToYUpMetres(const glm::dvec3& q)
{
    constexpr double kMetresPerUnit = 0.0254;
    return glm::vec3(glm::dvec3(q.x, q.z, -q.y) * kMetresPerUnit);
}

/// One instance of one mesh named after the file: `corners` three per triangle, positions welded;
/// watertight where closedAndOutward holds. Validated (Scene.h).
Scene quakeLevelScene(const std::vector<glm::vec3>& corners, const std::filesystem::path& file);

} // namespace sightline
