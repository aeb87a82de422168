// libFuzzer harness for one scene reader, chosen at build time by SIGHTLINE_FUZZ_EXTENSION
// (".gltf", ".glb", ".obj", ".ply", ".off", ".stl", ".map"; ".bsp" has fuzz_bsp.cpp). Bad input must end in sightline::Error; any
// other exception, a crash, a sanitizer report, a hang or runaway memory is a finding. A scene
// that loads must hold what Scene's contract promises (finite coordinates in range, valid indices,
// albedos in [0, 1] or unknown, one per triangle). An OBJ's bytes are also written as input.mtl, so
// an input that names that library (`mtllib input.mtl`) fuzzes the material reader too.

#include <cmath>

#include "FuzzInput.h"
#include "plugins/SceneFormats.h"
#include "base/Error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string extension = SIGHTLINE_FUZZ_EXTENSION;
    if (extension == ".obj")
        sightline::fuzz::inputFile("input.mtl", data, size);
    const auto file = sightline::fuzz::inputFile("input" + extension, data, size);
    try {
        std::vector<std::string> warnings;
        const sightline::Scene scene = sightline::loadScene(file, &warnings, {.textureAlbedos = true});   // every path, textures too
        for (const sightline::Mesh& mesh : scene.meshes) {
            if (!mesh.albedo.empty() && mesh.albedo.size() != mesh.triangleCount())
                __builtin_trap();
            for (const glm::vec3& a : mesh.albedo)
                if (a != sightline::kUnknownAlbedo && !(a.x >= 0.0f && a.x <= 1.0f && a.y >= 0.0f && a.y <= 1.0f && a.z >= 0.0f && a.z <= 1.0f))
                    __builtin_trap();
            for (const glm::vec3& p : mesh.positions)
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                    __builtin_trap();
            if (mesh.indices.size() % 3 != 0)
                __builtin_trap();
            for (const std::uint32_t index : mesh.indices)
                if (index >= mesh.positions.size())
                    __builtin_trap();
        }
    } catch (const sightline::Error&) {
    }
    return 0;
}
