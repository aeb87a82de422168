#include "demo/DemoLights.h"

#include <glm/geometric.hpp>

#include "demo/LevelParts.h"

namespace sightline::demo {

namespace {

using parts::kCeiling;
using parts::Rng;

struct Room {
    glm::dvec2 lo, hi;   // x, z
};

// DemoLevel.h's rooms A-E, 0.4 m inside their walls.
constexpr Room kRooms[] = {{{0.4, 0.4}, {9.6, 9.6}},     {{10.4, 0.4}, {21.6, 9.6}},  {{22.4, 0.4}, {29.6, 9.6}},
                           {{0.4, 10.4}, {13.6, 19.6}}, {{14.4, 10.4}, {29.6, 19.6}}};

} // namespace

std::vector<Light> demoLights()
{
    Rng rng(0x11647);
    std::vector<Light> lights;
    const double ceiling = double(kCeiling) - 0.1;
    int index = 0;
    for (const Room& room : kRooms) {
        const glm::dvec2 centre = 0.5 * (room.lo + room.hi), size = room.hi - room.lo;
        const bool alongX = size.x >= size.y;
        for (int k = 0; k < 2; ++k) {
            const double offset = (k == 0 ? -0.25 : 0.25) * (alongX ? size.x : size.y);
            const glm::dvec2 at = centre + (alongX ? glm::dvec2(offset, 0.0) : glm::dvec2(0.0, offset));
            Light panel;
            panel.type = LightType::Area;
            panel.name = "panel " + std::to_string(++index);
            panel.area.corner = {at.x - 0.4, ceiling, at.y - 0.4};
            panel.area.u = {0.8, 0.0, 0.0};
            panel.area.v = {0.0, 0.0, 0.8};   // u x v = -y: facing down
            panel.area.na = panel.area.nb = 4;
            panel.radiance = 40.0;
            panel.colour = {1.0, 0.93, 0.82};
            lights.push_back(panel);
        }
    }
    for (const Room& room : kRooms)
        for (int k = 0; k < 20; ++k) {
            Light lamp;
            lamp.type = LightType::Point;
            lamp.name = "lamp " + std::to_string(lights.size() - 9);
            lamp.position = {rng.range(float(room.lo.x), float(room.hi.x)), rng.range(1.6f, 2.8f),
                             rng.range(float(room.lo.y), float(room.hi.y))};
            lamp.intensity = rng.range(2.0f, 6.0f);
            lamp.range = 8.0;
            lamp.colour = {1.0, rng.range(0.7f, 0.95f), rng.range(0.45f, 0.8f)};
            lights.push_back(lamp);
        }
    for (int k = 0; k < 39; ++k) {
        const Room& room = kRooms[std::size_t(k) % 5];
        const glm::dvec2 centre = 0.5 * (room.lo + room.hi);
        // On one of the room's walls, aimed at a point of its floor.
        const int side = rng.between(0, 3);
        const double t = double(rng.range(0.1f, 0.9f));
        const glm::dvec2 onWall = side == 0   ? glm::dvec2(room.lo.x, room.lo.y + t * (room.hi.y - room.lo.y))
                                  : side == 1 ? glm::dvec2(room.hi.x, room.lo.y + t * (room.hi.y - room.lo.y))
                                  : side == 2 ? glm::dvec2(room.lo.x + t * (room.hi.x - room.lo.x), room.lo.y)
                                              : glm::dvec2(room.lo.x + t * (room.hi.x - room.lo.x), room.hi.y);
        Light spot;
        spot.type = LightType::Spot;
        spot.name = "spot " + std::to_string(k + 1);
        spot.position = {onWall.x, 2.6, onWall.y};
        const glm::dvec2 target = onWall + double(rng.range(0.2f, 0.6f)) * (centre - onWall);
        spot.direction = glm::normalize(glm::dvec3(target.x, 0.0, target.y) - spot.position);
        spot.innerAngle = 0.3;
        spot.outerAngle = 0.7;
        spot.intensity = rng.range(8.0f, 20.0f);
        spot.range = 10.0;
        lights.push_back(spot);
    }
    Light sun;
    sun.type = LightType::Directional;
    sun.name = "sun";
    sun.direction = glm::normalize(glm::dvec3(0.35, -0.8, 0.45));
    sun.intensity = 3.0;
    sun.colour = {1.0, 0.96, 0.9};
    lights.push_back(sun);
    return lights;
}

Patch demoFloor(int side)
{
    Patch floor;
    floor.corner = {0.1, 0.01, 19.9};
    floor.u = {29.8, 0.0, 0.0};
    floor.v = {0.0, 0.0, -19.8};   // u x v = +y: facing up
    floor.na = floor.nb = side;
    return floor;
}

} // namespace sightline::demo
