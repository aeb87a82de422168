#include "demo/PvsLevel.h"

#include <glm/gtc/matrix_transform.hpp>

#include "demo/LevelParts.h"
#include "base/Error.h"

namespace sightline::demo {

using namespace parts;

PvsLevel makePvsLevel(int roomsX, int roomsZ, int objects, std::uint64_t seed)
{
    if (roomsX < 1 || roomsX > 256 || roomsZ < 1 || roomsZ > 256)
        throw Error("pvs level: rooms must be in [1, 256]");
    constexpr float kRoom = 8.0f, kHeight = 3.0f;
    Rng rng(seed * 0x9E3779B97F4A7C15ull + 17);
    PvsLevel level;
    const float sizeX = kRoom * float(roomsX), sizeZ = kRoom * float(roomsZ);
    {
        Builder floor("floor");
        box(floor, {0.0f, -0.2f, 0.0f}, {sizeX, 0.0f, sizeZ});
        level.scene.addMeshInstance(floor.mesh);
    }
    // Walls along z (x = i * room) and along x (z = j * room), one instance per room side.
    for (int i = 0; i <= roomsX; ++i)
        for (int j = 0; j < roomsZ; ++j) {
            const float x = kRoom * float(i), z0 = kRoom * float(j);
            std::vector<Opening> doors;
            if (i > 0 && i < roomsX && rng.unit() < 0.6f) {
                const float s = z0 + rng.range(1.0f, kRoom - 2.0f);
                doors.push_back({s, s + 1.0f, 0.0f, 2.1f});
            }
            level.scene.addMeshInstance(wall("wall_x" + std::to_string(i) + "_z" + std::to_string(j), {x, z0}, {x, z0 + kRoom},
                                             doors, kHeight, kWall));
        }
    for (int j = 0; j <= roomsZ; ++j)
        for (int i = 0; i < roomsX; ++i) {
            const float z = kRoom * float(j), x0 = kRoom * float(i);
            std::vector<Opening> doors;
            if (j > 0 && j < roomsZ && rng.unit() < 0.6f) {
                const float s = x0 + rng.range(1.0f, kRoom - 2.0f);
                doors.push_back({s, s + 1.0f, 0.0f, 2.1f});
            }
            level.scene.addMeshInstance(wall("wall_z" + std::to_string(j) + "_x" + std::to_string(i), {x0, z}, {x0 + kRoom, z},
                                             doors, kHeight, kWall));
        }
    // Props: unit boxes, scaled and placed inside the rooms.
    Builder unit("prop");
    box(unit, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f});
    const std::uint32_t propMesh = level.scene.addMesh(unit.mesh);
    const int props = std::max(0, objects - int(level.scene.instances.size()));
    for (int k = 0; k < props; ++k) {
        const int room = rng.between(0, roomsX * roomsZ - 1);
        const float x0 = kRoom * float(room % roomsX), z0 = kRoom * float(room / roomsX);
        const float w = rng.range(0.3f, 1.0f), d = rng.range(0.3f, 1.0f), h = rng.range(0.4f, 2.5f);
        const glm::vec3 at{x0 + rng.range(0.5f + w, kRoom - 0.5f - w), 0.0f, z0 + rng.range(0.5f + d, kRoom - 0.5f - d)};
        Instance instance;
        instance.name = "prop" + std::to_string(k);
        instance.mesh = propMesh;
        instance.transform = glm::scale(glm::translate(glm::mat4(1.0f), at), glm::vec3(w, h, d));
        level.scene.instances.push_back(instance);
    }
    // Cells: 4 x 4 per room, inset from the walls.
    for (int i = 0; i < roomsX; ++i)
        for (int j = 0; j < roomsZ; ++j)
            for (int a = 0; a < 4; ++a)
                for (int b = 0; b < 4; ++b) {
                    const float inner = kRoom - 0.3f, step = inner / 4.0f;
                    Bounds cell;
                    cell.min = {kRoom * float(i) + 0.15f + step * float(a), 0.1f, kRoom * float(j) + 0.15f + step * float(b)};
                    cell.max = {cell.min.x + step, 1.9f, cell.min.z + step};
                    level.cells.push_back(cell);
                }
    level.source.corner = {1.0, 0.5, 1.0};
    level.source.u = {1.0, 0.0, 0.0};
    level.source.v = {0.0, 1.0, 0.0};
    level.receiver.corner = {1.0, 0.5, 6.0};
    level.receiver.u = {1.0, 0.0, 0.0};
    level.receiver.v = {0.0, 1.0, 0.0};
    return level;
}

} // namespace sightline::demo
