#include "project/ProjectLights.h"

#include <cmath>
#include <cstdint>

#include "plugins/GltfLights.h"
#include "project/SceneImport.h"
#include "base/Error.h"

namespace sightline {

using nlohmann::json;

namespace {

struct LightReader {
    const std::string& what;
    const json& object;
    std::string key;

    [[noreturn]] void fail(const std::string& field, const std::string& problem) const
    {
        throw Error(what + ": '" + key + (field.empty() ? "" : "." + field) + "' " + problem);
    }

    double number(const std::string& field, double fallback) const
    {
        if (!object.contains(field))
            return fallback;
        const json& value = object.at(field);
        if (!value.is_number())
            fail(field, "must be a number");
        const double x = value.get<double>();
        if (!std::isfinite(x))
            fail(field, "must be finite");
        return x;
    }

    glm::dvec3 vec3(const std::string& field, const glm::dvec3* fallback = nullptr) const
    {
        if (!object.contains(field)) {
            if (fallback)
                return *fallback;
            fail(field, "is missing");
        }
        const json& value = object.at(field);
        if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() ||
            !value[2].is_number())
            fail(field, "must be an array of 3 numbers");
        const glm::dvec3 v(value[0].get<double>(), value[1].get<double>(), value[2].get<double>());
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
            fail(field, "must be finite");
        return v;
    }

    int sampleSide(const json& n) const
    {
        // Range-checked in the JSON's own type: a count above 2^63 is unsigned there.
        const bool ok = n.is_number_unsigned() ? n.get<std::uint64_t>() >= 1 && n.get<std::uint64_t>() <= kMaxAreaLightSide
                                               : n.get<long long>() >= 1 && n.get<long long>() <= kMaxAreaLightSide;
        if (!ok)
            fail("samples", "must be two integers in [1, " + std::to_string(kMaxAreaLightSide) + "], got " + n.dump());
        return int(n.get<long long>());
    }

    Light light() const
    {
        if (!object.is_object())
            fail("", "must be an object with a \"type\" (point, spot, directional or area)");
        if (!object.contains("type") || !object.at("type").is_string())
            fail("type", "must be \"point\", \"spot\", \"directional\" or \"area\"");
        const std::string type = object.at("type").get<std::string>();
        Light light;
        if (type == "point")
            light.type = LightType::Point;
        else if (type == "spot")
            light.type = LightType::Spot;
        else if (type == "directional")
            light.type = LightType::Directional;
        else if (type == "area")
            light.type = LightType::Area;
        else
            fail("type", "must be \"point\", \"spot\", \"directional\" or \"area\", not \"" + type + "\"");
        if (object.contains("name")) {
            if (!object.at("name").is_string())
                fail("name", "must be a string");
            light.name = object.at("name").get<std::string>();
        }
        const glm::dvec3 white(1.0);
        light.colour = vec3("colour", &white);
        switch (light.type) {
        case LightType::Spot:
            light.innerAngle = number("inner_angle", light.innerAngle);
            light.outerAngle = number("outer_angle", light.outerAngle);
            light.direction = vec3("direction");
            [[fallthrough]];
        case LightType::Point:
            light.position = vec3("position");
            light.intensity = number("intensity", 1.0);
            if (object.contains("range")) {
                light.range = number("range", 0.0);
                if (!(light.range > 0.0))
                    fail("range", "must be a number > 0 (leave it out for no range)");
            }
            break;
        case LightType::Directional:
            light.direction = vec3("direction");
            light.intensity = number("intensity", 1.0);
            break;
        case LightType::Area:
            light.area.corner = vec3("corner");
            light.area.u = vec3("u");
            light.area.v = vec3("v");
            light.area.na = light.area.nb = 32;
            if (object.contains("samples")) {
                const json& s = object.at("samples");
                if (!s.is_array() || s.size() != 2 || !s[0].is_number_integer() || !s[1].is_number_integer())
                    fail("samples", "must be two integers [na, nb]");
                light.area.na = sampleSide(s[0]);
                light.area.nb = sampleSide(s[1]);
            }
            light.radiance = number("radiance", 1.0);
            if (object.contains("two_sided")) {
                if (!object.at("two_sided").is_boolean())
                    fail("two_sided", "must be true or false");
                light.twoSided = object.at("two_sided").get<bool>();
            }
            break;
        }
        return light;
    }
};

json vec(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

} // namespace

std::vector<Light> parseLights(const json& value, const std::string& what)
{
    if (!value.is_array())
        throw Error(what + ": 'lights' must be an array of lights");
    if (value.size() > kMaxLights)
        throw Error(what + ": 'lights' holds " + std::to_string(value.size()) + " lights; at most " +
                    std::to_string(kMaxLights) + " are supported");
    std::vector<Light> lights;
    lights.reserve(value.size());
    for (std::size_t i = 0; i < value.size(); ++i)
        lights.push_back(LightReader{what, value[i], "lights[" + std::to_string(i) + "]"}.light());
    validateLights(lights, what);
    return lights;
}

std::vector<Light> projectLights(const Project& project)
{
    if (!project.extra.contains("lights"))
        return {};
    return parseLights(project.extra.at("lights"), project.name);
}

std::vector<Light> sceneFileLights(const Project& project, std::vector<std::string>* warnings)
{
    if (project.scene.empty())
        return {};
    const std::filesystem::path file = project.resolve(project.scene, "scene");
    const SceneImport settings = sceneImport(project);
    const glm::dmat4 turn = settings.transform();
    std::vector<Light> lights;
    for (const PunctualLight& source : loadGltfLights(file, warnings)) {
        Light light;
        light.type = source.type == "spot" ? LightType::Spot : source.type == "directional" ? LightType::Directional : LightType::Point;
        light.name = source.name;
        light.colour = source.colour;
        light.intensity = source.intensity;
        light.range = source.range;
        light.innerAngle = source.innerAngle;
        light.outerAngle = source.outerAngle;
        // In the turned and scaled world, as the level's objects.
        light.position = glm::dvec3(turn * glm::dvec4(source.position, 1.0));
        light.direction = glm::dvec3(turn * glm::dvec4(source.direction, 0.0)) / settings.scale;
        light.range = source.range * settings.scale;
        lights.push_back(light);
    }
    validateLights(lights, file.filename().string() + " (KHR_lights_punctual)");
    return lights;
}

std::vector<Light> lightsToUse(const Project& project, bool* fromScene)
{
    const bool useScene = !project.extra.contains("lights");
    if (fromScene)
        *fromScene = useScene;
    return useScene ? sceneFileLights(project) : projectLights(project);
}

json lightJson(const Light& light)
{
    json object = json::object();
    object["type"] = toString(light.type);
    if (!light.name.empty())
        object["name"] = light.name;
    object["colour"] = vec(light.colour);
    switch (light.type) {
    case LightType::Spot:
        object["direction"] = vec(light.direction);
        object["inner_angle"] = light.innerAngle;
        object["outer_angle"] = light.outerAngle;
        [[fallthrough]];
    case LightType::Point:
        object["position"] = vec(light.position);
        object["intensity"] = light.intensity;
        if (light.range > 0.0)
            object["range"] = light.range;
        break;
    case LightType::Directional:
        object["direction"] = vec(light.direction);
        object["intensity"] = light.intensity;
        break;
    case LightType::Area:
        object["corner"] = vec(light.area.corner);
        object["u"] = vec(light.area.u);
        object["v"] = vec(light.area.v);
        object["samples"] = json::array({light.area.na, light.area.nb});
        object["radiance"] = light.radiance;
        if (light.twoSided)
            object["two_sided"] = true;
        break;
    }
    return object;
}

} // namespace sightline
