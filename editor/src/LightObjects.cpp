#include "editor/LightObjects.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "editor/Picking.h"
#include "project/ProjectLights.h"

namespace sightline::ui {

namespace {

/// A unit vector at right angles to unit `d`.
glm::dvec3 perpendicular(const glm::dvec3& d)
{
    const glm::dvec3 other = std::abs(d.y) < 0.9 ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(1.0, 0.0, 0.0);
    return glm::normalize(glm::cross(other, d));
}

nlohmann::json vec(const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

} // namespace

glm::dvec3 sunAnchor(const Bounds& level)
{
    if (level.empty())
        return {0.0, 3.0, 0.0};
    const glm::dvec3 lo(level.min), hi(level.max);
    return {0.5 * (lo.x + hi.x), hi.y + 1.0, 0.5 * (lo.z + hi.z)};
}

glm::dvec3 lightPivot(const Light& light, const Bounds& level)
{
    switch (light.type) {
    case LightType::Area: return light.area.centre();
    case LightType::Directional: return sunAnchor(level);
    case LightType::Point:
    case LightType::Spot: break;
    }
    return light.position;
}

glm::mat4 lightTransform(const Light& light, const Bounds& level)
{
    glm::dvec3 x, y, z;
    if (light.type == LightType::Area) {
        x = light.area.u;
        y = light.area.v;
        z = glm::normalize(glm::cross(x, y));
    } else {
        z = glm::length(light.direction) > 0.0 ? glm::normalize(light.direction) : glm::dvec3(0.0, -1.0, 0.0);
        x = perpendicular(z);
        y = glm::cross(z, x);
    }
    glm::mat4 t(1.0f);
    t[0] = glm::vec4(glm::vec3(x), 0.0f);
    t[1] = glm::vec4(glm::vec3(y), 0.0f);
    t[2] = glm::vec4(glm::vec3(z), 0.0f);
    t[3] = glm::vec4(glm::vec3(lightPivot(light, level)), 1.0f);
    return t;
}

nlohmann::json placedLightJson(nlohmann::json light, LightType type, const glm::mat4& transform)
{
    const glm::dvec3 x(transform[0]), y(transform[1]), z(transform[2]), origin(transform[3]);
    switch (type) {
    case LightType::Point: light["position"] = vec(origin); break;
    case LightType::Spot:
        light["position"] = vec(origin);
        light["direction"] = vec(glm::normalize(z));
        break;
    case LightType::Directional: light["direction"] = vec(glm::normalize(z)); break;
    case LightType::Area:
        light["u"] = vec(x);
        light["v"] = vec(y);
        light["corner"] = vec(origin - 0.5 * x - 0.5 * y);
        break;
    }
    return light;
}

nlohmann::json newLightJson(LightType type, const glm::dvec3& at, const std::string& name)
{
    Light light;
    light.type = type;
    light.name = name;
    light.position = at;
    switch (type) {
    case LightType::Point:
        light.intensity = 20.0;
        light.range = 10.0;
        break;
    case LightType::Spot:
        light.intensity = 60.0;
        light.range = 15.0;
        light.innerAngle = 0.3;
        light.outerAngle = 0.6;
        break;
    case LightType::Directional: light.intensity = 3.0; light.direction = glm::normalize(glm::dvec3(0.3, -1.0, 0.2)); break;
    case LightType::Area:
        light.radiance = 60.0;
        light.area.corner = at + glm::dvec3(-0.25, 0.0, 0.25);
        light.area.u = {0.0, 0.0, -0.5};   // u x v points down
        light.area.v = {0.5, 0.0, 0.0};
        light.area.na = light.area.nb = 4;
        break;
    }
    return lightJson(light);
}

nlohmann::json lightOnSurfaceJson(LightType type, const glm::dvec3& point, const glm::dvec3& normal, const std::string& name)
{
    constexpr double kPointOut = 0.3, kSpotOut = 0.1, kAreaOut = 0.01, kAreaSide = 0.5;
    switch (type) {
    case LightType::Point: return newLightJson(type, point + kPointOut * normal, name);
    case LightType::Directional: return newLightJson(type, point, name);
    case LightType::Spot: {
        nlohmann::json light = newLightJson(type, point + kSpotOut * normal, name);
        light["direction"] = vec(normal);
        return light;
    }
    case LightType::Area: break;
    }
    // Edges in the surface's plane with u x v along the normal: u level where the surface is not.
    const glm::dvec3 across = std::abs(normal.y) < 0.9 ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 u = kAreaSide * glm::normalize(glm::cross(across, normal));
    const glm::dvec3 v = glm::cross(normal, u);
    const glm::dvec3 centre = point + kAreaOut * normal;
    nlohmann::json light = newLightJson(type, centre, name);
    light["corner"] = vec(centre - 0.5 * u - 0.5 * v);
    light["u"] = vec(u);
    light["v"] = vec(v);
    return light;
}

std::optional<double> pickLight(const Light& light, const Bounds& level, const Ray& ray, double radius)
{
    if (light.type == LightType::Area)
        if (const auto d = pickPatch(light.area, ray))
            return d;
    const glm::dvec3 p = lightPivot(light, level);
    const glm::dvec3 dir = glm::normalize(ray.direction);
    const double t = glm::dot(p - ray.origin, dir);
    if (t <= 0.0 || glm::length(ray.origin + t * dir - p) > radius)
        return std::nullopt;
    return t;
}

} // namespace sightline::ui
