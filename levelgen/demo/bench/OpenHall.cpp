// open-hall: a 20-40 m hall with a few large occluders (under 2k triangles), the bitmask's case.

#include <algorithm>
#include <cmath>
#include <vector>

#include "demo/bench/SceneKinds.h"
#include "demo/bench/Rooms.h"
#include "demo/bench/Stage.h"

namespace sightline::demo::bench {
namespace {

/// Large loading doors low in the end walls, clerestory windows high in the long ones.
std::vector<WallPlan> hallWalls(Rng& rng, float length, float width, float height)
{
    auto doorsIn = [&](float span) {
        std::vector<Opening> doors;
        const int count = rng.between(1, 2);
        for (int k = 0; k < count; ++k) {
            const float w = rng.range(3.0f, 4.0f), c = span * (float(k) + 0.5f) / float(count) + rng.range(-1.0f, 1.0f);
            doors.push_back(door(c - 0.5f * w, c + 0.5f * w, std::min(height - 0.6f, rng.range(3.5f, 4.5f))));
        }
        return doors;
    };
    auto clerestory = [&](float span) {
        std::vector<Opening> windows;
        const int count = rng.between(2, 4);
        for (int k = 0; k < count; ++k) {
            const float c = span * (float(k) + 0.5f) / float(count);
            windows.push_back(window(c - 1.2f, c + 1.2f, height - 2.0f, height - 0.6f));
        }
        return windows;
    };
    return {
        {{-0.1f, 0.0f}, {length + 0.1f, 0.0f}, {}, clerestory(length), true},
        {{-0.1f, width}, {length + 0.1f, width}, {}, clerestory(length), true},
        {{0.0f, 0.05f}, {0.0f, width - 0.05f}, doorsIn(width), {}, true},
        {{length, 0.05f}, {length, width - 0.05f}, doorsIn(width), {}, true},
    };
}

/// A stack of `minLevels` to three large crates (scaled 1 m crates) on the floor at `at`.
void crateStack(Stage& stage, std::uint32_t crateMesh, vec2 at, float size, int minLevels = 1)
{
    const int levels = stage.rng.between(minLevels, 3);
    float y = 0.0f;
    for (int k = 0; k < levels; ++k) {
        const float s = size * (1.0f - 0.15f * float(k));
        stage.put(crateMesh, place({at.x + stage.rng.range(-0.05f, 0.05f), y, at.y}, stage.rng.range(-0.03f, 0.03f), s));
        y += s;
    }
    stage.take(Rect::around(at, vec2(0.75f * size)));
}

/// A free-standing partition wall from `a` to `b` (along +x or +z), maybe with an opening.
void partition(Stage& stage, int index, vec2 a, vec2 b, float height, bool opening)
{
    std::vector<Opening> openings;
    if (opening) {
        const bool alongX = b.x - a.x > b.y - a.y;
        const float s0 = alongX ? a.x : a.y, s1 = alongX ? b.x : b.y;
        const float c = stage.rng.range(s0 + 1.2f, s1 - 1.2f), w = stage.rng.range(0.8f, 1.6f);
        const bool isDoor = stage.rng.unit() < 0.5f;
        openings.push_back(isDoor ? door(c - 0.5f * w, c + 0.5f * w, std::min(height - 0.3f, 2.2f))
                                  : window(c - 0.5f * w, c + 0.5f * w, 0.9f, std::min(height - 0.3f, 2.0f)));
    }
    stage.putNew(wall("partition_" + std::to_string(index), a, b, openings, height, 0.15f));
    stage.take({glm::min(a, b) - vec2(0.2f), glm::max(a, b) + vec2(0.2f)});
}

} // namespace

BenchScene openHall(std::uint64_t seed)
{
    Stage stage(seed, 0x0BE4A11ull);
    Rng& rng = stage.rng;
    const bool pillars = seed % 2 == 1;
    const float length = rng.range(20.0f, 40.0f), width = rng.range(15.0f, 30.0f), height = rng.range(5.0f, 8.0f);
    const float distance = rng.range(10.0f, std::min(25.0f, length - 6.0f));
    const float x0 = rng.range(3.0f, length - distance - 3.0f);
    const float zs = rng.range(0.3f * width, 0.7f * width);
    const float zr = std::clamp(zs + rng.range(-3.0f, 3.0f), 3.0f, width - 3.0f);
    auto size = [&] { return PatchSize{rng.range(1.0f, 2.0f), rng.range(1.2f, 2.0f), rng.range(0.2f, 0.6f)}; };
    const PatchSize sourceSize = size(), receiverSize = size();
    stage.setPatches({x0, zs}, sourceSize, {x0 + distance, zr}, receiverSize, 0.04f);
    addShell(stage, hallWalls(rng, length, width, height), {{0.0f, 0.0f}, {length, width}}, height, 4.0f, 8.0f);

    Builder crateBuilder("crate_big");   // plain boxes: the occluders stay few and large
    box(crateBuilder, {-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f});
    const std::uint32_t crateMesh = stage.add(std::move(crateBuilder.mesh));
    if (pillars) {
        // One stack in the shaft, off its middle, so the view is partly cut whatever else lands
        // there.
        const float t = rng.range(0.3f, 0.7f);
        const float lateral = (rng.unit() < 0.5f ? -1.0f : 1.0f) * stage.halfWidth(t) * rng.range(0.35f, 0.85f);
        crateStack(stage, crateMesh, stage.along(t, lateral), rng.range(0.7f, 1.1f), 2);
        const float spacing = rng.range(5.0f, 8.0f), side = rng.range(0.35f, 0.6f);
        Builder pillarBuilder("pillar_square");
        box(pillarBuilder, {-0.5f * side, 0.0f, -0.5f * side}, {0.5f * side, height, 0.5f * side});
        const std::uint32_t pillarMesh = stage.add(std::move(pillarBuilder.mesh));
        const vec2 offset(rng.range(0.5f, spacing - 0.5f), rng.range(0.5f, spacing - 0.5f));
        for (float x = offset.x; x < length - 1.0f; x += spacing)
            for (float z = offset.y; z < width - 1.0f; z += spacing) {
                const Rect r = Rect::around({x, z}, vec2(0.5f * side));
                if (x > 1.0f && z > 1.0f && stage.isFree(r.grown(0.2f))) {
                    stage.put(pillarMesh, translate({x, 0.0f, z}));
                    stage.take(r);
                }
            }
        stage.reserveShaft(0.3f);   // what lands in the shaft beyond this is the grid's doing
        for (int k = rng.between(2, 6), tries = 0; k > 0 && tries < 200; ++tries) {
            const vec2 at(rng.range(2.0f, length - 2.0f), rng.range(2.0f, width - 2.0f));
            const float s = rng.range(0.8f, 1.5f);
            if (stage.isFree(Rect::around(at, vec2(0.8f * s)))) {
                crateStack(stage, crateMesh, at, s);
                --k;
            }
        }
        return std::move(stage).finish("pillars");
    }
    // Partitions: one across the shaft ending inside it (covering a third to two thirds of its
    // width there, so 20-80% of the rays), the others anywhere free outside it.
    const float h = rng.range(2.4f, std::min(3.5f, height - 0.5f));
    const float across = rng.range(0.3f, 0.7f);
    const vec2 at = stage.along(across);
    const float reach = stage.halfWidth(across) * rng.range(-0.35f, 0.35f);
    if (rng.unit() < 0.5f)
        partition(stage, 0, {at.x, at.y - rng.range(2.5f, 5.0f)}, {at.x, at.y + reach}, h, false);
    else
        partition(stage, 0, {at.x, at.y - reach}, {at.x, at.y + rng.range(2.5f, 5.0f)}, h, false);
    stage.reserveShaft(0.3f);
    int index = 1;
    for (int k = rng.between(2, 5), tries = 0; k > 0 && tries < 200; ++tries) {
        const float len = rng.range(3.0f, 8.0f);
        const bool alongX = rng.unit() < 0.5f;
        const vec2 a(rng.range(1.5f, length - 1.5f - (alongX ? len : 0.0f)), rng.range(1.5f, width - 1.5f - (alongX ? 0.0f : len)));
        const vec2 b = a + (alongX ? vec2(len, 0.0f) : vec2(0.0f, len));
        if (!stage.isFree({glm::min(a, b) - vec2(0.3f), glm::max(a, b) + vec2(0.3f)}))
            continue;
        partition(stage, index++, a, b, rng.range(2.4f, std::min(3.5f, height - 0.5f)), len > 3.5f && rng.unit() < 0.6f);
        --k;
    }
    for (int k = rng.between(1, 3), tries = 0; k > 0 && tries < 200; ++tries) {
        const vec2 c(rng.range(2.0f, length - 2.0f), rng.range(2.0f, width - 2.0f));
        const float s = rng.range(0.8f, 1.4f);
        if (stage.isFree(Rect::around(c, vec2(0.8f * s)))) {
            crateStack(stage, crateMesh, c, s);
            --k;
        }
    }
    return std::move(stage).finish("partitions");
}

} // namespace sightline::demo::bench
