#include "lighting/LightEmission.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace sightline {

std::vector<Emitter> lightEmitters(const std::vector<Light>& lights)
{
    std::size_t total = 0;
    for (const Light& light : lights)
        total += std::size_t(light.sampleCount());
    std::vector<Emitter> emitters;
    emitters.reserve(total);
    for (std::size_t k = 0; k < lights.size(); ++k) {
        const Light& light = lights[k];
        if (light.type == LightType::Area) {
            for (int i = 0; i < light.area.sampleCount(); ++i)
                emitters.push_back({light.area.sample(i), std::uint32_t(k)});
        } else {
            emitters.push_back({light.position, std::uint32_t(k)});
        }
    }
    return emitters;
}

double emitterTerm(const Light& light, const glm::dvec3& position, const glm::dvec3& x, const glm::dvec3& n)
{
    return EmitterTerm(light)(position, x, n);
}

EmitterTerm::EmitterTerm(const Light& light) : light_(&light)
{
    if (light.type == LightType::Area) {
        const glm::dvec3 cross = glm::cross(light.area.u, light.area.v);
        const double area = glm::length(cross);
        areaNormal_ = cross / area;
        sampleRadiance_ = light.radiance * (area / double(light.area.sampleCount()));
        clamp2_ = light.clampMetres * light.clampMetres;
    }
    if (light.type == LightType::Spot)
        cosInner_ = std::cos(light.innerAngle), cosOuter_ = std::cos(light.outerAngle);
}

DirectionalReach::DirectionalReach(const Bounds& bounds)
{
    if (bounds.empty()) {
        radius = 1.0;
        return;
    }
    centre = 0.5 * (glm::dvec3(bounds.min) + glm::dvec3(bounds.max));
    radius = 0.5 * glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min)) + 1.0;
}

glm::dvec3 DirectionalReach::end(const Light& light, const glm::dvec3& x) const
{
    return x - light.direction * (glm::length(x - centre) + radius);
}

} // namespace sightline
