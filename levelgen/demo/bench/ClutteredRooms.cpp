// cluttered-rooms: furnished rooms of 60-100k triangles with 30-45 plants, most of them lining or
// crossing the shaft (the demo's kind, in layouts the sampler was not tuned on).

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "demo/Props.h"
#include "demo/bench/Fittings.h"
#include "demo/bench/SceneKinds.h"
#include "demo/bench/Planting.h"
#include "demo/bench/Rooms.h"
#include "demo/bench/Stage.h"

namespace sightline::demo::bench {
namespace {

/// The rooms beside the main one (z from `z0` to `z1`), split by cross walls with doors, each with
/// a door into the main room in the wall at z0. Returns the rooms' floors.
std::vector<Rect> sideRooms(Rng& rng, std::vector<WallPlan>& walls, float length, float z0, float z1,
                            std::vector<Opening>& mainWallDoors)
{
    const int count = rng.between(2, 3);
    std::vector<Rect> rooms;
    for (int k = 0; k < count; ++k) {
        const float a = length * float(k) / float(count), b = length * float(k + 1) / float(count);
        rooms.push_back({{a, z0}, {b, z1}});
        const float c = rng.range(a + 1.2f, b - 1.2f);
        mainWallDoors.push_back(door(c - 0.5f, c + 0.5f));
        if (k > 0)
            walls.push_back({{a, z0 + 0.05f}, {a, z1 - 0.05f}, {door(z0 + 0.5f, z0 + 1.5f)}, {}, false});
    }
    return rooms;
}

std::vector<vec2> rangesOf(const std::vector<Opening>& openings)
{
    std::vector<vec2> out;
    for (const Opening& o : openings)
        out.push_back({o.s0, o.s1});
    return out;
}

/// Plants beyond those placed on purpose, at free spots anywhere on `floor`.
void scatterPlants(Stage& stage, Planting& planting, const Rect& floor, int total)
{
    for (int tries = 0; planting.count() < total && tries < 400; ++tries) {
        const vec2 at(stage.rng.range(floor.lo.x + 0.4f, floor.hi.x - 0.4f), stage.rng.range(floor.lo.y + 0.4f, floor.hi.y - 0.4f));
        if (stage.isFree(Rect::around(at, vec2(0.4f))))
            planting.potted(at, planting.anyKind());
    }
}

/// A glazed hall (plant rows along both sides of the aisle the shaft runs down, hanging baskets
/// from the roof beams), entered from a potting room through a wide doorway, store rooms beside.
BenchScene greenhouse(Stage& stage)
{
    Rng& rng = stage.rng;
    const float height = rng.range(3.6f, 4.4f), width = rng.range(6.5f, 9.0f), depth = rng.range(4.0f, 5.5f);
    const float xs = rng.range(1.2f, 2.0f), run = rng.range(13.0f, 21.0f), length = xs + run + rng.range(1.2f, 2.0f);
    const vec2 from(xs, 0.5f * width + rng.range(-0.8f, 0.8f)), to(xs + run, 0.5f * width + rng.range(-0.8f, 0.8f));
    stage.setPatches(from, {rng.range(1.0f, 1.6f), rng.range(1.2f, 1.8f), rng.range(0.2f, 0.5f)}, to,
                     {rng.range(1.2f, 2.0f), rng.range(1.4f, 2.0f), rng.range(0.2f, 0.4f)}, 0.03f);

    // The potting room's wall crosses the shaft near the source; its doorway is wider than the
    // shaft there, so it frames the view rather than cutting it.
    const float xp = xs + rng.range(1.6f, 2.6f);
    const float crossing = stage.along((xp - from.x) / (to.x - from.x)).y, doorWidth = rng.range(1.8f, 2.6f);
    const Opening potDoor = door(crossing - 0.5f * doorWidth, crossing + 0.5f * doorWidth, std::min(height - 0.5f, 2.6f));
    std::vector<Opening> partitionWindows;
    if (potDoor.s0 > 1.6f)
        partitionWindows.push_back(window(0.5f, potDoor.s0 - 0.5f, 1.0f, 2.2f));
    if (potDoor.s1 < width - 1.6f)
        partitionWindows.push_back(window(potDoor.s1 + 0.5f, width - 0.5f, 1.0f, 2.2f));

    std::vector<WallPlan> walls;
    std::vector<Opening> mainWallDoors;
    const std::vector<Rect> rooms = sideRooms(rng, walls, length, width, width + depth, mainWallDoors);
    const float glassPitch = rng.range(1.4f, 1.8f);
    walls.push_back({{-0.1f, 0.0f}, {length + 0.1f, 0.0f}, {},
                     windowRow(0.3f, length - 0.3f, glassPitch, glassPitch - 0.35f, 0.5f, height - 0.5f, {{xp, xp}}), true});
    walls.push_back({{0.05f, width}, {length - 0.05f, width}, mainWallDoors,
                     windowRow(0.3f, length - 0.3f, 2.4f, 1.2f, 1.0f, 2.2f, rangesOf(mainWallDoors)), false});
    walls.push_back({{-0.1f, width + depth}, {length + 0.1f, width + depth}, {},
                     windowRow(0.3f, length - 0.3f, 3.0f, 1.4f, 0.9f, 2.3f), true});
    const float westDoor = rng.range(0.8f, width - 1.8f);
    walls.push_back({{0.0f, 0.05f}, {0.0f, width + depth - 0.05f}, {door(westDoor, westDoor + 1.0f)},
                     {window(width + 0.8f, width + depth - 0.8f)}, true});
    const float eastDoor = rng.range(0.8f, width - 1.8f);
    walls.push_back({{length, 0.05f}, {length, width + depth - 0.05f}, {door(eastDoor, eastDoor + 1.0f)},
                     {window(width + 0.8f, width + depth - 0.8f)}, true});
    walls.push_back({{xp, 0.05f}, {xp, width - 0.05f}, {potDoor}, partitionWindows, false});
    const Rect floor{{0.0f, 0.0f}, {length, width + depth}};
    addShell(stage, walls, floor, height, 1.0f, 2.0f);

    // Roof beams over the hall; the baskets hang from them at 3.2 m like the demo's.
    Builder beams("beams");
    std::vector<float> beamAt;
    for (float x = xp + rng.range(0.8f, 1.4f); x < length - 0.5f; x += rng.range(2.0f, 2.6f)) {
        box(beams, {x - 0.08f, 3.2f, 0.1f}, {x + 0.08f, 3.36f, width - 0.1f});
        beamAt.push_back(x);
    }
    stage.putNew(std::move(beams.mesh));

    Planting planting(stage);
    const int total = rng.between(30, 45), hanging = rng.between(2, 5);
    const int inRows = std::min(total - hanging - 2, rng.between(22, 30));
    const float t0 = (xp + 0.9f - from.x) / (to.x - from.x), t1 = 0.93f;
    const float rowLength = (t1 - t0) * stage.length(), spacing = std::max(0.75f, 2.0f * rowLength / float(inRows));
    for (float s = rng.range(0.0f, 0.5f * spacing); s < rowLength && planting.count() < inRows; s += spacing)
        for (float side : {-1.0f, 1.0f}) {
            const float t = t0 + (s + rng.range(-0.1f, 0.1f) * spacing) / stage.length();
            if (planting.count() < inRows)
                planting.potted(stage.along(t, side * (stage.halfWidth(t) + rng.range(-0.15f, 0.35f))), planting.anyKind());
        }
    for (int k = 0; k < hanging && !beamAt.empty(); ++k) {
        const vec2 at = stage.along(rng.range(0.2f, 0.85f), stage.halfWidth(0.5f) * rng.range(-0.3f, 0.3f));
        const float x = *std::min_element(beamAt.begin(), beamAt.end(),
                                          [&](float a, float b) { return std::abs(a - at.x) < std::abs(b - at.x); });
        planting.hanging({x, 3.2f, at.y});
    }
    stage.reserveShaft(0.5f);
    scatterPlants(stage, planting, floor, total);

    Furnisher furnisher(stage);
    const auto target = std::size_t(rng.range(65000.0f, 90000.0f));
    for (const Rect& room : rooms)
        furnisher.fill(room, target, 14);
    furnisher.fill({{xp, 0.0f}, {length, width}}, target, 30);
    furnisher.fill({{0.0f, 0.0f}, {xp, width}}, target, 6);
    return std::move(stage).finish("greenhouse");
}

/// Four desks facing in pairs across a screen, with chairs and monitors, centred at `at`; meshes:
/// desk, screen, monitor, chair.
void deskPod(Stage& stage, const std::uint32_t meshes[4], vec2 at)
{
    stage.put(meshes[1], translate({at.x, 0.0f, at.y}));
    for (float row : {-1.0f, 1.0f})
        for (float x : {-0.82f, 0.82f}) {
            const mat4 frame = place({at.x + x, 0.0f, at.y + 0.42f * row}, row > 0 ? 0.0f : 0.5f);
            stage.put(meshes[0], frame);
            stage.put(meshes[2], frame * translate({0.0f, 0.0f, -0.2f}));
            stage.put(meshes[3], frame * place({stage.rng.range(-0.1f, 0.1f), 0.0f, stage.rng.range(0.55f, 0.75f)}, 0.5f + stage.rng.range(-0.05f, 0.05f)));
        }
    stage.take(Rect::around(at, {1.7f, 1.4f}));
}

/// An open-plan floor: the shaft runs down an aisle lined with planter cabinets (ferns on top)
/// and potted plants, desk pods beyond them, meeting rooms beside; half the floors end in a
/// glazed meeting room that the receiver stands in.
BenchScene office(Stage& stage)
{
    Rng& rng = stage.rng;
    const float height = rng.range(2.9f, 3.3f), width = rng.range(11.0f, 15.0f), depth = rng.range(3.5f, 4.5f);
    const float xs = rng.range(1.5f, 2.2f), run = rng.range(13.0f, 20.0f), length = xs + run + rng.range(1.5f, 2.2f);
    const float zs = width * rng.range(0.35f, 0.65f), zr = std::clamp(zs + rng.range(-1.2f, 1.2f), 2.5f, width - 2.5f);
    const vec2 from(xs, zs), to(xs + run, zr);
    stage.setPatches(from, {rng.range(1.0f, 1.6f), rng.range(1.3f, 1.8f), rng.range(0.3f, 0.5f)}, to,
                     {rng.range(1.2f, 2.0f), rng.range(1.4f, 1.9f), rng.range(0.25f, 0.4f)}, 0.03f);

    std::vector<WallPlan> walls;
    std::vector<Opening> mainWallDoors;
    const std::vector<Rect> rooms = sideRooms(rng, walls, length, width, width + depth, mainWallDoors);
    walls.push_back({{-0.1f, 0.0f}, {length + 0.1f, 0.0f}, {}, windowRow(0.3f, length - 0.3f, 1.8f, 1.3f, 0.8f, 2.5f), true});
    walls.push_back({{0.05f, width}, {length - 0.05f, width}, mainWallDoors,
                     windowRow(0.3f, length - 0.3f, 1.5f, 1.2f, 0.1f, 2.4f, rangesOf(mainWallDoors)), true});
    walls.push_back({{-0.1f, width + depth}, {length + 0.1f, width + depth}, {},
                     windowRow(0.3f, length - 0.3f, 1.8f, 1.3f, 0.8f, 2.5f), true});
    walls.push_back({{0.0f, 0.05f}, {0.0f, width + depth - 0.05f}, {}, windowRow(0.3f, width - 0.3f, 1.8f, 1.3f, 0.8f, 2.5f), true});
    walls.push_back({{length, 0.05f}, {length, width + depth - 0.05f}, {}, windowRow(0.3f, width - 0.3f, 1.8f, 1.3f, 0.8f, 2.5f), true});
    float rowEnd = 0.93f;
    if (rng.unit() < 0.5f) {
        // The glass wall of the end meeting room crosses the shaft: the view goes through its
        // panes and glazing bars.
        const float xm = to.x - rng.range(1.6f, 2.4f);
        const float crossing = stage.along((xm - from.x) / (to.x - from.x)).y;
        const float d0 = crossing > 0.5f * width ? 0.8f : width - 1.8f;
        const std::vector<Opening> doors{door(d0, d0 + 1.0f)};
        walls.push_back({{xm, 0.05f}, {xm, width - 0.05f}, doors,
                         windowRow(0.3f, width - 0.3f, rng.range(1.3f, 1.7f), 1.1f, 0.1f, 2.5f, rangesOf(doors)), true});
        rowEnd = (xm - 0.6f - from.x) / (to.x - from.x);
    }
    const Rect floor{{0.0f, 0.0f}, {length, width + depth}};
    addShell(stage, walls, floor, height, 0.6f, 0.6f);

    // The aisle's planters: cabinets with a fern on top and floor pots, alternating, on both sides.
    Planting planting(stage);
    const std::uint32_t cabinetMesh = stage.add(cabinet());
    const int total = rng.between(30, 45);
    const int inRows = std::min(total - 2, rng.between(22, 30));
    const float t0m = (0.5f * float(glm::length(stage.source().u)) + 0.9f) / stage.length();
    const float rowLength = (rowEnd - t0m) * stage.length(), spacing = std::max(0.75f, 2.0f * rowLength / float(inRows));
    int k = 0;
    for (float s = rng.range(0.0f, 0.3f * spacing); s < rowLength && planting.count() < inRows; s += spacing, ++k)
        for (float side : {-1.0f, 1.0f}) {
            const float t = t0m + s / stage.length();
            const vec2 at = stage.along(t, side * (stage.halfWidth(t) + rng.range(-0.1f, 0.3f)));
            if (planting.count() >= inRows)
                break;
            if ((k + (side > 0)) % 2 == 0) {
                stage.put(cabinetMesh, place({at.x, 0.0f, at.y}, rng.range(-0.01f, 0.01f)));
                stage.take(Rect::around(at, {0.42f, 0.25f}));
                planting.potted(at, PlantKind::Fern, 0.75f);
            } else {
                planting.potted(at, rng.unit() < 0.5f ? PlantKind::Ficus : PlantKind::Palm);
            }
        }
    stage.reserveShaft(0.4f);

    const std::uint32_t podMeshes[4] = {stage.add(desk()), stage.add(deskScreen(3.3f)), stage.add(monitor()), stage.add(chairWood())};
    for (float side : {-1.0f, 1.0f}) {
        const float lateral = rng.range(0.6f, 1.1f) + 1.4f;
        for (float s = rng.range(1.5f, 2.5f); s < stage.length() - 1.5f; s += rng.range(3.6f, 4.2f)) {
            const float t = s / stage.length();
            const vec2 at = stage.along(t, side * (stage.halfWidth(t) + lateral));
            const Rect pod = Rect::around(at, {1.7f, 1.4f});
            if (Rect{{0.3f, 0.3f}, {length - 0.3f, width - 0.3f}}.contains(pod) && stage.isFree(pod))
                deskPod(stage, podMeshes, at);
        }
    }
    scatterPlants(stage, planting, floor, total);

    Furnisher furnisher(stage);
    const auto target = std::size_t(rng.range(65000.0f, 90000.0f));
    for (const Rect& room : rooms)
        furnisher.fill(room, target, 10);
    furnisher.fill({{0.0f, 0.0f}, {length, width}}, target, 40);
    return std::move(stage).finish("office");
}

} // namespace

BenchScene clutteredRooms(std::uint64_t seed)
{
    Stage stage(seed, 0xC1077E4EDull);
    return seed % 2 == 1 ? greenhouse(stage) : office(stage);
}

} // namespace sightline::demo::bench
