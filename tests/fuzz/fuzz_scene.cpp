// libFuzzer harness for one scene reader, chosen at build time by SIGHTLINE_FUZZ_EXTENSION
// (".gltf", ".glb", ".obj", ".ply", ".off", ".stl", ".map"; ".bsp" has fuzz_bsp.cpp). Bad input must end in sightline::Error; any
// other exception, a crash, a sanitizer report, a hang or runaway memory is a finding. A scene
// that loads must hold what Scene's contract promises (finite coordinates in range, valid indices).

#include <cmath>

#include "FuzzInput.h"
#include "plugins/SceneFormats.h"
#include "base/Error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto file = sightline::fuzz::inputFile(std::string("input") + SIGHTLINE_FUZZ_EXTENSION, data, size);
    try {
        std::vector<std::string> warnings;
        const sightline::Scene scene = sightline::loadScene(file, &warnings);
        for (const sightline::Mesh& mesh : scene.meshes) {
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
