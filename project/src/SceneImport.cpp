#include "project/SceneImport.h"

#include <array>
#include <cmath>

#include <glm/geometric.hpp>

#include "plugins/SceneFormats.h"
#include "base/Error.h"

namespace sightline {

namespace {

constexpr std::array<const char*, 6> kUps = {"+y", "-y", "+z", "-z", "+x", "-x"};

/// The turn as columns: the world images of the file's x, y and z axes.
glm::dmat4 turn(const std::string& up)
{
    const auto columns = [](glm::dvec3 x, glm::dvec3 y, glm::dvec3 z) {
        glm::dmat4 m(1.0);
        m[0] = glm::dvec4(x, 0.0);
        m[1] = glm::dvec4(y, 0.0);
        m[2] = glm::dvec4(z, 0.0);
        return m;
    };
    if (up == "-y")   // (x, y, z) -> (x, -y, -z)
        return columns({1, 0, 0}, {0, -1, 0}, {0, 0, -1});
    if (up == "+z")   // (x, y, z) -> (x, z, -y)
        return columns({1, 0, 0}, {0, 0, -1}, {0, 1, 0});
    if (up == "-z")   // (x, y, z) -> (x, -z, y)
        return columns({1, 0, 0}, {0, 0, 1}, {0, -1, 0});
    if (up == "+x")   // (x, y, z) -> (-y, x, z)
        return columns({0, 1, 0}, {-1, 0, 0}, {0, 0, 1});
    if (up == "-x")   // (x, y, z) -> (y, -x, z)
        return columns({0, -1, 0}, {1, 0, 0}, {0, 0, 1});
    return glm::dmat4(1.0);
}

} // namespace

glm::dmat4 SceneImport::transform() const
{
    glm::dmat4 m = turn(up);
    for (int c = 0; c < 3; ++c)
        m[c] *= scale;
    return m;
}

SceneImport sceneImport(const Project& project)
{
    SceneImport settings;
    const auto fail = [&](const char* key, const std::string& why) { throw Error(project.name + ": '" + key + "' " + why); };
    if (const auto it = project.extra.find(kSceneUpKey); it != project.extra.end()) {
        if (!it->is_string())
            fail(kSceneUpKey, "must be one of +y, -y, +z, -z, +x, -x (the direction that is up in the scene file)");
        settings.up = it->get<std::string>();
        bool known = false;
        for (const char* up : kUps)
            known = known || settings.up == up;
        if (!known)
            fail(kSceneUpKey, "must be one of +y, -y, +z, -z, +x, -x, not '" + settings.up + "'");
    }
    if (const auto it = project.extra.find(kSceneScaleKey); it != project.extra.end()) {
        if (!it->is_number())
            fail(kSceneScaleKey, "must be a number of metres per file unit (0.0254 for inches)");
        settings.scale = it->get<double>();
        if (!std::isfinite(settings.scale) || settings.scale < kMinSceneScale || settings.scale > kMaxSceneScale)
            fail(kSceneScaleKey, "must be metres per file unit between 1e-6 and 1000 (0.01 for centimetres, 0.0254 for inches)");
    }
    return settings;
}

void setSceneImport(Project& project, const SceneImport& settings)
{
    if (settings.up == "+y")
        project.extra.erase(kSceneUpKey);
    else
        project.extra[kSceneUpKey] = settings.up;
    if (settings.scale == 1.0)
        project.extra.erase(kSceneScaleKey);
    else
        project.extra[kSceneScaleKey] = settings.scale;
}

void applySceneImport(const SceneImport& settings, Scene& scene)
{
    if (settings.identity())
        return;
    const glm::mat4 m(settings.transform());
    for (Instance& instance : scene.instances)
        instance.transform = m * instance.transform;
}

Scene loadLevel(const Project& project, std::vector<std::string>* warnings)
{
    const SceneImport settings = sceneImport(project);
    if (project.scene.empty())
        return {};
    Scene scene = loadScene(project.resolve(project.scene, "scene"), warnings, {.textureAlbedos = project.textureAlbedos});
    applySceneImport(settings, scene);
    return scene;
}

std::string guessSceneUp(const Scene& scene, std::span<const glm::mat4> transforms)
{
    // Area facing each of +x, -x, +y, -y, +z, -z (normals within about 30 degrees).
    std::array<double, 6> area{};
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const Mesh& mesh = scene.meshes[instance.mesh];
        const glm::dmat4 m(i < transforms.size() ? transforms[i] : instance.transform);
        for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
            const glm::dvec3 a(m * glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[t]]), 1.0));
            const glm::dvec3 b(m * glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[t + 1]]), 1.0));
            const glm::dvec3 c(m * glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[t + 2]]), 1.0));
            const glm::dvec3 n = glm::cross(b - a, c - a);
            const double twice = glm::length(n);
            if (!(twice > 0.0) || !std::isfinite(twice))
                continue;
            const glm::dvec3 unit = n / twice;
            for (int axis = 0; axis < 3; ++axis)
                if (std::abs(unit[axis]) > 0.866)
                    area[std::size_t(2 * axis + (unit[axis] < 0.0 ? 1 : 0))] += 0.5 * twice;
        }
    }
    int best = 1;   // y
    for (int axis = 0; axis < 3; ++axis)
        if (area[std::size_t(2 * axis)] + area[std::size_t(2 * axis + 1)] >
            1.05 * (area[std::size_t(2 * best)] + area[std::size_t(2 * best + 1)]))
            best = axis;   // clearly more than y's: y wins ties
    const bool down = area[std::size_t(2 * best + 1)] > area[std::size_t(2 * best)];
    return std::string(down ? "-" : "+") + "xyz"[best];
}

} // namespace sightline
