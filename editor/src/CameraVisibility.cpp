#include "editor/CameraVisibility.h"

#include <algorithm>

#include <glm/geometric.hpp>

namespace sightline::ui {

std::vector<std::uint32_t> visibleInstances(const Camera& camera, const LightingScene& lighting, int width, int height)
{
    const double reach = 4.0 * lighting.reach().radius + glm::length(camera.eye() - lighting.reach().centre);
    std::vector<std::uint32_t> seen;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const Ray ray = pixelRay(camera, x + 0.5, y + 0.5, width, height);
            const pvs::RayHit hit = lighting.firstHits().cast(glm::vec3(ray.origin), glm::vec3(ray.direction * reach), 1.0f);
            if (hit.instance >= 0)
                seen.push_back(std::uint32_t(hit.instance));
        }
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    return seen;
}

} // namespace sightline::ui
