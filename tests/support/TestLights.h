#pragma once
// Lights for the lighting tests, one line each.

#include <glm/vec3.hpp>

#include "lighting/Light.h"
#include "visibility/Patch.h"

namespace sightline::test {

inline Light pointLight(const glm::dvec3& position, double intensity, glm::dvec3 colour = glm::dvec3(1.0))
{
    Light light;
    light.type = LightType::Point;
    light.position = position;
    light.intensity = intensity;
    light.colour = colour;
    return light;
}

inline Light areaLight(const Patch& patch, double radiance)
{
    Light light;
    light.type = LightType::Area;
    light.area = patch;
    light.radiance = radiance;
    return light;
}

inline Light directionalLight(const glm::dvec3& direction, double intensity)
{
    Light light;
    light.type = LightType::Directional;
    light.direction = direction;
    light.intensity = intensity;
    return light;
}

inline Light spotLight(const glm::dvec3& position, const glm::dvec3& direction, double inner, double outer, double intensity)
{
    Light light = pointLight(position, intensity);
    light.type = LightType::Spot;
    light.direction = direction;
    light.innerAngle = inner;
    light.outerAngle = outer;
    return light;
}

} // namespace sightline::test
