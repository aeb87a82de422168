#include "editor/ViewSettings.h"

#include <cmath>

namespace sightline::ui {

using nlohmann::json;

json cameraToJson(const Camera& c)
{
    json out = {{"target", {c.target.x, c.target.y, c.target.z}}, {"distance", c.distance}, {"yaw", c.yaw},
                {"pitch", c.pitch}, {"fov_y", c.fovY}};
    if (c.orthographic)
        out["orthographic"] = true;   // absent: perspective (files saved before the key read as they did)
    return out;
}

std::optional<Camera> cameraFromJson(const json& value)
{
    if (!value.is_object())
        return std::nullopt;
    auto number = [&](const char* key, double& out) {
        if (!value.contains(key) || !value.at(key).is_number())
            return false;
        out = value.at(key).get<double>();
        return std::isfinite(out);
    };
    Camera c;
    const json target = value.value("target", json());
    if (!target.is_array() || target.size() != 3)
        return std::nullopt;
    for (int i = 0; i < 3; ++i) {
        if (!target[std::size_t(i)].is_number())
            return std::nullopt;
        c.target[i] = target[std::size_t(i)].get<double>();
        if (!std::isfinite(c.target[i]))
            return std::nullopt;
    }
    if (!number("distance", c.distance) || !number("yaw", c.yaw) || !number("pitch", c.pitch) || c.distance <= 0.0)
        return std::nullopt;
    double fov = c.fovY;
    if (number("fov_y", fov) && fov > 0.05 && fov < 3.0)
        c.fovY = fov;
    if (const auto it = value.find("orthographic"); it != value.end() && it->is_boolean())
        c.orthographic = it->get<bool>();
    return c;
}

Camera shaftView(const Patch& source, const Patch& receiver)
{
    Camera camera;
    const glm::dvec3 axis = receiver.centre() - source.centre();
    glm::dvec3 side = glm::cross(axis, glm::dvec3(0.0, 1.0, 0.0));
    if (glm::length(side) < 1e-9 * std::max(glm::length(axis), 1.0))
        side = glm::dvec3(1.0, 0.0, 0.0);   // a vertical shaft: look at it from +X
    side = glm::normalize(side);
    // forward = -side, tilted down by the default pitch.
    camera.yaw = std::atan2(side.x, side.z);
    camera.pitch = -0.75;   // about 43 degrees down: over the cutaway walls, into the rooms
    Bounds bounds;
    for (const Patch* p : {&source, &receiver})
        for (int k = 0; k < 4; ++k)
            bounds.extend(glm::vec3(p->cornerPoint(k)));
    frame(camera, bounds);
    return camera;
}

Camera projectView(const json& editorSettings, const Patch& source, const Patch& receiver)
{
    if (editorSettings.is_object() && editorSettings.contains("camera"))
        if (auto camera = cameraFromJson(editorSettings.at("camera")))
            return *camera;
    return shaftView(source, receiver);
}

} // namespace sightline::ui
