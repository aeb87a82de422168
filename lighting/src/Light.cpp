#include "lighting/Light.h"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "base/Error.h"
#include "visibility/ExactSegment.h"

namespace sightline {

namespace {

[[noreturn]] void fail(const std::string& key, const std::string& problem) { throw Error("'" + key + "' " + problem); }

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void requirePosition(const glm::dvec3& p, const std::string& key)
{
    if (!finite(p))
        fail(key, "must be finite");
    if (std::abs(p.x) > kMaxCoordinateMetres || std::abs(p.y) > kMaxCoordinateMetres || std::abs(p.z) > kMaxCoordinateMetres)
        fail(key, "lies beyond 1e6 m from the origin");
}

void requireNonNegative(double x, const std::string& key)
{
    if (!std::isfinite(x) || x < 0.0)
        fail(key, "must be a finite number >= 0");
}

} // namespace

const char* toString(LightType type)
{
    switch (type) {
    case LightType::Point: return "point";
    case LightType::Spot: return "spot";
    case LightType::Directional: return "directional";
    case LightType::Area: return "area";
    }
    return "?";
}

void validateLight(Light& light, const std::string& key)
{
    if (!finite(light.colour) || light.colour.x < 0.0 || light.colour.y < 0.0 || light.colour.z < 0.0)
        fail(key + ".colour", "must be three finite numbers >= 0");
    switch (light.type) {
    case LightType::Spot:
        if (!(light.innerAngle >= 0.0 && light.outerAngle <= std::numbers::pi / 2 && light.innerAngle < light.outerAngle))
            fail(key + ".inner_angle", "and outer_angle must satisfy 0 <= inner_angle < outer_angle <= pi/2 (radians), got " +
                                           std::to_string(light.innerAngle) + " and " + std::to_string(light.outerAngle));
        [[fallthrough]];
    case LightType::Point:
        requirePosition(light.position, key + ".position");
        requireNonNegative(light.intensity, key + ".intensity");
        if (!std::isfinite(light.range) || light.range < 0.0)
            fail(key + ".range", "must be a finite number > 0");
        break;
    case LightType::Directional:
        requireNonNegative(light.intensity, key + ".intensity");
        break;
    case LightType::Area: {
        requireNonNegative(light.radiance, key + ".radiance");
        for (int k = 0; k < 4; ++k)
            requirePosition(light.area.cornerPoint(k), key + (k == 0 ? ".corner" : ".corner + u, v"));
        if (light.area.na < 1 || light.area.nb < 1 || light.area.na > kMaxAreaLightSide || light.area.nb > kMaxAreaLightSide)
            fail(key + ".samples", "must be two integers in [1, " + std::to_string(kMaxAreaLightSide) + "]");
        const glm::dvec3 normal = glm::cross(light.area.u, light.area.v);
        if (!finite(light.area.u) || !finite(light.area.v) || !(glm::length(normal) > 0.0) || !std::isfinite(glm::length(normal)))
            fail(key, "is a degenerate area light: u and v must be finite, non-zero and not parallel");
        break;
    }
    }
    if (light.type == LightType::Spot || light.type == LightType::Directional) {
        const double length = glm::length(light.direction);
        if (!finite(light.direction) || !(length > 0.0) || !std::isfinite(length))
            fail(key + ".direction", "must be a finite, non-zero vector");
        light.direction /= length;
    }
}

void validateLights(std::vector<Light>& lights, const std::string& what)
{
    if (lights.size() > kMaxLights)
        throw Error(what + ": 'lights' holds " + std::to_string(lights.size()) + " lights; at most " +
                    std::to_string(kMaxLights) + " are supported");
    std::size_t samples = 0;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        try {
            validateLight(lights[i], "lights[" + std::to_string(i) + "]");
        } catch (const Error& e) {
            throw Error(what + ": " + e.what());
        }
        samples += std::size_t(lights[i].sampleCount());
        if (samples > kMaxLightSamples)
            throw Error(what + ": 'lights' ask for more than " + std::to_string(kMaxLightSamples) +
                        " light samples in all (area lights' samples); use coarser sample grids");
    }
}

std::string displayName(const std::vector<Light>& lights, std::size_t index)
{
    if (index < lights.size() && !lights[index].name.empty())
        return lights[index].name;
    return "light " + std::to_string(index);
}

} // namespace sightline
