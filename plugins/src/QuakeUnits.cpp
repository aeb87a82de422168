#include "QuakeUnits.h"

#include "plugins/MeshTopology.h"

namespace sightline {

Scene quakeLevelScene(const std::vector<glm::vec3>& corners, const std::filesystem::path& file)
{
    Mesh mesh;
    mesh.name = file.stem().string();
    std::vector<std::uint32_t> representative;
    mesh.indices = weldPositions(corners.data(), corners.size(), &representative);
    for (std::uint32_t r : representative)
        mesh.positions.push_back(corners[r]);
    mesh.watertight = meshTopology(mesh).closedAndOutward();
    Scene scene;
    scene.addMeshInstance(std::move(mesh));
    validate(scene, file.string());
    return scene;
}

} // namespace sightline
