// architectural-interior: 15-30k triangles of rooms, doorways, columns, stairs, a balcony and
// window frames with a few small objects and no plants; the shaft goes through doorways or
// between columns.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/common.hpp>

#include "demo/Props.h"
#include "demo/bench/Fittings.h"
#include "demo/bench/SceneKinds.h"
#include "demo/bench/Rooms.h"
#include "demo/bench/Stage.h"

namespace sightline::demo::bench {
namespace {

/// A few vases on plinths and small crates at free spots of `floor` (the shaft is reserved first).
void smallObjects(Stage& stage, const Rect& floor)
{
    Rng& rng = stage.rng;
    const std::uint32_t vase = stage.add(vaseOnPlinth()), box = stage.add(crate("crate_small", 0.5f));
    for (int k = rng.between(2, 4), tries = 0; k > 0 && tries < 300; ++tries) {
        const vec2 at(rng.range(floor.lo.x + 0.5f, floor.hi.x - 0.5f), rng.range(floor.lo.y + 0.5f, floor.hi.y - 0.5f));
        const Rect r = Rect::around(at, vec2(0.3f));
        if (!stage.isFree(r.grown(0.2f)))
            continue;
        stage.put(rng.unit() < 0.6f ? vase : box, place({at.x, 0.0f, at.y}, rng.range(-0.05f, 0.05f)));
        stage.take(r);
        --k;
    }
}

/// A column at `at` (stretched pillar) unless its floor is taken; a pilaster, which stands against
/// a wall (whose floor is taken) on purpose, only needs the floor on its room side (`inward`: the
/// direction into the room, zero for a free-standing column).
void column(Stage& stage, std::uint32_t mesh, vec2 at, float height, vec2 inward = vec2(0.0f))
{
    const Rect r = Rect::around(at, vec2(0.33f));
    const Rect probe = inward == vec2(0.0f) ? r : Rect::around(at + 0.2f * inward, vec2(0.28f) - 0.18f * glm::abs(inward));
    if (!stage.isFree(probe))
        return;
    stage.put(mesh, columnAt(at, height));
    stage.take(r);
}

/// Pilasters at z against a wall along x, on the piers between its lowest row of windows (the
/// piers wide enough for one).
void pierPilasters(Stage& stage, std::uint32_t mesh, const std::vector<Opening>& windows, float z, float inward,
                   float height)
{
    for (std::size_t k = 0; k + 1 < windows.size(); ++k) {
        const Opening &a = windows[k], &b = windows[k + 1];
        if (a.y0 == windows.front().y0 && b.y0 == a.y0 && b.s0 - a.s1 > 0.9f)
            column(stage, mesh, {0.5f * (a.s1 + b.s0), z}, height, {0.0f, inward});
    }
}

/// A coffered ceiling over `floor`: beams both ways every `pitch` m, the cross ones shallower so
/// that no two beams share an edge.
void coffers(Stage& stage, const Rect& floor, float height, float pitch)
{
    Builder b("coffers");
    for (float x = floor.lo.x + pitch; x < floor.hi.x - 0.3f; x += pitch)
        box(b, {x - 0.06f, height - 0.3f, floor.lo.y + 0.1f}, {x + 0.06f, height, floor.hi.y - 0.1f});
    for (float z = floor.lo.y + pitch; z < floor.hi.y - 0.3f; z += pitch)
        box(b, {floor.lo.x + 0.1f, height - 0.22f, z - 0.05f}, {floor.hi.x - 0.1f, height - 0.002f, z + 0.05f});
    stage.putNew(std::move(b.mesh));
}

/// Three rooms in a row joined by doorways the shaft goes through, each framed by columns on both
/// sides, pilasters along the walls, two columns flanking the shaft in the middle room, a stair up to a door high in its back wall.
BenchScene enfilade(Stage& stage)
{
    Rng& rng = stage.rng;
    const float height = rng.range(3.4f, 4.2f), width = rng.range(6.5f, 8.5f);
    const float x1 = rng.range(4.5f, 7.0f), x2 = x1 + rng.range(5.5f, 8.0f), length = x2 + rng.range(4.5f, 7.0f);
    const vec2 from(rng.range(1.0f, 1.6f), 0.5f * width + rng.range(-1.0f, 1.0f));
    const vec2 to(length - rng.range(1.0f, 1.6f), 0.5f * width + rng.range(-1.0f, 1.0f));
    stage.setPatches(from, {rng.range(1.0f, 1.6f), rng.range(1.4f, 1.9f), rng.range(0.2f, 0.4f)}, to,
                     {rng.range(1.2f, 2.0f), rng.range(1.4f, 2.0f), rng.range(0.2f, 0.4f)}, 0.03f);

    std::vector<WallPlan> walls;
    std::vector<vec2> doorways;   // (x, z) of each doorway's two jambs, for the columns framing them
    for (float x : {x1, x2}) {
        // Doorways narrower than the shaft where it meets them, a little off its middle: they crop
        // its sides (and sometimes its top).
        const float t = (x - from.x) / (to.x - from.x);
        const float crossing = stage.along(t).y + rng.range(-0.35f, 0.35f);
        const float w = std::max(0.8f, 2.0f * stage.halfWidth(t) * rng.range(0.55f, 0.95f));
        const Opening d = door(crossing - 0.5f * w, crossing + 0.5f * w, rng.range(2.1f, std::min(2.6f, height - 0.4f)));
        std::vector<Opening> windows;
        if (d.s0 > 2.0f)
            windows.push_back(window(0.6f, d.s0 - 0.6f, 1.0f, 2.2f));
        if (d.s1 < width - 2.0f)
            windows.push_back(window(d.s1 + 0.6f, width - 0.6f, 1.0f, 2.2f));
        walls.push_back({{x, 0.05f}, {x, width - 0.05f}, {d}, windows, false});
        doorways.insert(doorways.end(), {{x, d.s0}, {x, d.s1}});
    }
    // The stair climbs along the back wall of the middle room to a landing and a door 2 m high.
    const int steps = std::clamp(int((height - 2.15f) / 0.18f), 5, 11);
    const float stairX = x1 + rng.range(0.6f, 1.2f), stairTop = float(steps) * 0.18f, landingX = stairX + float(steps) * 0.28f;
    const std::vector<vec2> roomEnds{{-1.0f, 0.9f}, {x1 - 0.8f, x1 + 0.8f}, {x2 - 0.8f, x2 + 0.8f}, {length - 0.9f, length + 1.0f}};
    std::vector<vec2> northClear = roomEnds;
    northClear.push_back({stairX, landingX + 1.0f});
    const float pitch = rng.range(2.2f, 2.8f);
    walls.push_back({{-0.1f, 0.0f}, {length + 0.1f, 0.0f}, {},
                     windowRow(0.3f, length - 0.3f, pitch, 1.2f, 0.9f, height - 0.9f, roomEnds), true});
    walls.push_back({{-0.1f, width}, {length + 0.1f, width}, {window(landingX + 0.05f, landingX + 0.95f, stairTop, stairTop + 2.0f)},
                     windowRow(0.3f, length - 0.3f, pitch, 1.2f, 0.9f, height - 0.9f, northClear), true});
    walls.push_back({{0.0f, 0.05f}, {0.0f, width - 0.05f}, {}, {window(0.5f * width - 0.8f, 0.5f * width + 0.8f)}, true});
    walls.push_back({{length, 0.05f}, {length, width - 0.05f}, {door(0.5f * width - 0.6f, 0.5f * width + 0.6f, 2.4f)}, {}, true});
    const Rect floor{{0.0f, 0.0f}, {length, width}};
    addShell(stage, walls, floor, height, 0.25f, 1.0f);
    for (auto [a, b] : {std::pair{0.0f, x1}, std::pair{x1, x2}, std::pair{x2, length}})
        coffers(stage, {{a + 0.1f, 0.1f}, {b - 0.1f, width - 0.1f}}, height, rng.range(0.8f, 1.1f));

    stage.put(stage.add(stair("stair", steps, 0.18f, 0.28f, 1.0f)), translate({stairX, 0.0f, width - 1.2f}));
    Builder landing("landing");
    box(landing, {landingX - 0.05f, stairTop - 0.2f, width - 1.25f}, {landingX + 1.05f, stairTop, width - 0.1f});
    for (float x : {landingX + 0.1f, landingX + 0.95f})
        box(landing, {x - 0.05f, 0.0f, width - 1.2f}, {x + 0.05f, stairTop - 0.19f, width - 1.1f});
    stage.putNew(std::move(landing.mesh));
    stage.put(stage.add(balustrade("landing_rail", 1.1f)), translate({landingX - 0.03f, stairTop, width - 1.2f}));
    stage.take({{stairX - 0.1f, width - 1.4f}, {landingX + 1.1f, width}});
    const std::uint32_t pillarMesh = stage.add(pillar());
    pierPilasters(stage, pillarMesh, walls[2].windows, 0.42f, 1.0f, height);
    pierPilasters(stage, pillarMesh, walls[3].windows, width - 0.42f, -1.0f, height);

    for (auto [a, b] : {std::pair{0.0f, x1}, std::pair{x1, x2}, std::pair{x2, length}})
        for (float x : {a + 0.5f, b - 0.5f})
            for (float z : {0.42f, width - 0.42f})
                column(stage, pillarMesh, {x, z}, height, {0.0f, z < 1.0f ? 1.0f : -1.0f});
    for (size_t k = 0; k < doorways.size(); ++k)
        for (float dx : {-0.55f, 0.55f})
            column(stage, pillarMesh, doorways[k] + vec2(dx, k % 2 ? 0.4f : -0.4f), height);
    for (float f : {0.38f, 0.62f}) {
        const float x = x1 + f * (x2 - x1), t = (x - from.x) / (to.x - from.x);
        for (float side : {-1.0f, 1.0f})
            column(stage, pillarMesh, stage.along(t, side * (stage.halfWidth(t) + rng.range(-0.3f, 0.4f))), height);
    }
    stage.reserveShaft(0.3f);
    smallObjects(stage, floor);
    return std::move(stage).finish("enfilade");
}

/// A double-height hall: a balcony on columns along one side (a stair up to it at the west end),
/// full-height columns along the other, two tiers of windows. The source stands under or on the
/// balcony, the receiver out in the nave, so the shaft passes between the columns.
BenchScene colonnade(Stage& stage)
{
    Rng& rng = stage.rng;
    const float height = rng.range(6.4f, 7.5f), width = rng.range(10.0f, 13.0f);
    const float xs = rng.range(1.8f, 2.6f), run = rng.range(12.0f, 20.0f), length = xs + run + rng.range(1.5f, 2.5f);
    const float level = rng.range(3.2f, 3.8f), rowA = rng.range(2.8f, 3.6f), rowB = width - rng.range(2.8f, 3.6f);
    // From the balcony the source stands near its edge and the receiver on the far side of the
    // nave, so the view down clears the balustrade for part of the rays rather than none.
    const bool onBalcony = rng.unit() < 0.5f;
    const float sourceWidth = rng.range(1.0f, 1.4f), nearWall = 0.35f + 0.5f * sourceWidth;
    const vec2 from(xs, onBalcony ? rng.range(rowA - 0.9f, rowA - 0.5f) : rng.range(std::max(1.0f, nearWall), rowA - 0.8f));
    const vec2 to(xs + run, rng.range(onBalcony ? std::max(rowA + 2.5f, rowB - 0.5f) : rowA + 1.5f, width - 1.5f));
    const PatchSize sourceSize = onBalcony ? PatchSize{sourceWidth, rng.range(1.2f, 1.6f), level + rng.range(0.4f, 0.8f)}
                                           : PatchSize{sourceWidth, rng.range(1.4f, 1.8f), rng.range(0.2f, 0.4f)};
    stage.setPatches(from, sourceSize, to, {rng.range(1.2f, 1.8f), rng.range(1.5f, 2.0f), rng.range(0.2f, 0.4f)}, 0.03f);

    const int steps = int(std::round(level / 0.18f));
    const float rise = level / float(steps), stairStart = rowA + 0.35f + float(steps) * 0.27f;
    const float pitch = rng.range(2.4f, 3.0f);
    auto tiers = [&](float s1, const std::vector<vec2>& clear) {
        std::vector<Opening> w = windowRow(1.0f, s1 - 1.0f, pitch, 1.2f, 0.9f, level - 0.6f, clear);
        const std::vector<Opening> upper = windowRow(1.0f, s1 - 1.0f, pitch, 1.2f, level + 0.9f, height - 0.8f, clear);
        w.insert(w.end(), upper.begin(), upper.end());
        return w;
    };
    const float mainDoor = rng.range(rowA + 1.0f, rowB - 3.0f);
    std::vector<WallPlan> walls{
        {{-0.1f, 0.0f}, {length + 0.1f, 0.0f}, {}, tiers(length, {}), true},
        {{-0.1f, width}, {length + 0.1f, width}, {}, tiers(length, {}), true},
        {{0.0f, 0.05f}, {0.0f, width - 0.05f}, {}, {window(rowA + 1.0f, rowB - 1.0f, level + 0.9f, height - 0.8f)}, true},
        {{length, 0.05f}, {length, width - 0.05f}, {door(mainDoor, mainDoor + 2.0f, 3.0f)},
         {window(rowA + 0.3f, mainDoor - 0.5f, level + 0.9f, height - 0.8f)}, true},
    };
    const Rect floor{{0.0f, 0.0f}, {length, width}};
    addShell(stage, walls, floor, height, 0.3f, 1.0f);

    stage.put(stage.add(stair("stair", steps, rise, 0.27f, 1.1f)), place({0.3f, 0.0f, stairStart}, 0.25f));
    stage.take({{0.2f, rowA + 0.3f}, {1.5f, stairStart + 0.2f}});
    Builder slab("balcony");
    box(slab, {0.1f, level - 0.25f, 0.1f}, {length - 0.1f, level, rowA + 0.35f});
    stage.putNew(std::move(slab.mesh));
    const float railFrom = 1.5f, railTo = length - 0.1f;
    const int sections = int(std::ceil((railTo - railFrom) / 2.5f));
    const float section = (railTo - railFrom) / float(sections);
    const std::uint32_t rail = stage.add(balustrade("balcony_rail", section - 0.01f));
    for (int k = 0; k < sections; ++k)
        stage.put(rail, translate({railFrom + section * float(k), level, rowA + 0.28f}));

    const std::uint32_t pillarMesh = stage.add(pillar());
    const float spacing = rng.range(2.6f, 3.4f);
    Builder beams("beams");
    for (float x = 2.2f + rng.range(0.0f, 0.6f); x < length - 1.2f; x += spacing) {
        column(stage, pillarMesh, {x, rowA}, level - 0.25f);
        column(stage, pillarMesh, {x, rowB}, height);
        box(beams, {x - 0.15f, height - 0.45f, rowA + 0.6f}, {x + 0.15f, height, width - 0.1f});
    }
    stage.putNew(std::move(beams.mesh));
    pierPilasters(stage, pillarMesh, walls[1].windows, width - 0.42f, -1.0f, height);
    stage.reserveShaft(0.3f);
    smallObjects(stage, floor);
    return std::move(stage).finish(onBalcony ? "colonnade (source on the balcony)" : "colonnade");
}

} // namespace

BenchScene architecturalInterior(std::uint64_t seed)
{
    Stage stage(seed, 0xA4C417EC7ull);
    return seed % 2 == 1 ? enfilade(stage) : colonnade(stage);
}

} // namespace sightline::demo::bench
