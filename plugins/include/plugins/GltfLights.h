#pragma once
// Lights a glTF file places with KHR_lights_punctual (Blender, babylon.js and 3ds Max write them):
// a light in the extension's list, placed by every node of the default scene's trees that names
// it, at the node's world origin, shining along the node's world -Z.
//
// The extension's units are photometric (candela for point and spot lights, lux for directional
// ones); Sightline reads the same numbers radiometrically (W/sr, W/m²), which is what a glTF
// viewer that treats them as linear renderer units does too.

#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sightline {

struct PunctualLight {
    std::string type;                     ///< "point", "spot" or "directional"
    std::string name;                     ///< the light's name, else its node's
    glm::dvec3 colour{1.0};
    double intensity = 1.0;
    double range = 0.0;                   ///< 0: none
    double innerAngle = 0.0, outerAngle = 0.7853981633974483;   ///< spot, radians
    glm::dvec3 position{0.0};             ///< world
    glm::dvec3 direction{0.0, 0.0, -1.0}; ///< world, unit
};

/// The lights of a .gltf or .glb file, in node order (empty for other files and for files with
/// none). Throws sightline::Error naming the file and node for a light index out of range, an
/// unknown type or a direction the node's transform collapses.
std::vector<PunctualLight> loadGltfLights(const std::filesystem::path& file, std::vector<std::string>* warnings = nullptr);

} // namespace sightline
