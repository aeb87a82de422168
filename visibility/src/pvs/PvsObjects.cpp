#include "visibility/pvs/PvsObjects.h"

#include <map>

namespace sightline::pvs {

std::vector<PvsObject> sceneObjects(const Scene& scene, bool groupByName)
{
    std::vector<PvsObject> objects;
    std::map<std::string, std::size_t> byName;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const Bounds box = scene.meshes[instance.mesh].triangleCount() ? scene.instanceBounds(instance) : Bounds{};
        if (groupByName) {
            const auto [it, added] = byName.try_emplace(instance.name, objects.size());
            if (!added) {
                objects[it->second].instances.push_back(std::uint32_t(i));
                objects[it->second].bounds.extend(box);
                continue;
            }
        }
        objects.push_back({instance.name, std::uint32_t(i), {std::uint32_t(i)}, box});
    }
    return objects;
}

} // namespace sightline::pvs
