#include "demo/DemoLevel.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "demo/LevelParts.h"
#include "demo/Props.h"

namespace sightline::demo {
namespace {

using namespace parts;

// ------------------------------------------------------------------------------ the level

class LevelBuilder {
public:
    Scene scene;

    std::uint32_t add(Mesh mesh) { return scene.addMesh(std::move(mesh)); }
    void put(std::uint32_t mesh, const mat4& transform)
    {
        scene.instances.push_back(Instance{scene.meshes[mesh].name, mesh, transform});
    }
};

struct WallSpec {
    const char* name;
    vec2 a, b;
    std::vector<Opening> doors;     // from the floor
    std::vector<Opening> windows;
    bool outer;                     // outer windows get mullions
};

Opening door(float s0, float s1, float height = 2.1f) { return {s0, s1, 0.0f, height}; }
Opening window(float s0, float s1, float y0 = 0.9f, float y1 = 2.3f) { return {s0, s1, y0, y1}; }

void addArchitecture(LevelBuilder& level)
{
    const std::vector<WallSpec> walls{
        {"wall_south", {-0.1f, 0}, {30.1f, 0}, {},
         {window(3, 4.6f), window(6.5f, 8.1f), window(12, 13.6f), window(15.5f, 17.1f), window(19, 20.6f),
          window(24, 25.6f), window(27, 28.6f)}, true},
        {"wall_north", {-0.1f, 20}, {30.1f, 20}, {},
         {window(2.5f, 4.1f), window(6, 7.6f), window(9.5f, 11.1f), window(16, 17.6f), window(20, 21.6f),
          window(24, 25.6f), window(27.5f, 29.1f)}, true},
        {"wall_west", {0, 0.05f}, {0, 19.95f}, {}, {window(6.5f, 8.1f), window(13, 14.6f), window(16.5f, 18.1f)}, true},
        {"wall_east", {30, 0.05f}, {30, 19.95f}, {}, {window(3, 4.6f), window(6.5f, 8.1f), window(12.5f, 14.1f),
                                                     window(16, 17.6f)}, true},
        {"wall_gallery_conservatory", {10, 0.05f}, {10, 9.95f}, {door(4.55f, 5.45f)},
         {window(1.4f, 2.9f, 1.0f, 2.2f), window(7.1f, 8.6f, 1.0f, 2.2f)}, false},
        {"wall_conservatory_archive", {22, 0.05f}, {22, 9.95f}, {door(7.2f, 8.4f)}, {window(1.5f, 3.0f, 1.0f, 2.2f)}, false},
        {"wall_middle", {0.05f, 10}, {29.95f, 10}, {door(4.2f, 5.2f), door(17, 18.6f, 2.2f), door(25.5f, 26.5f)},
         {window(11.2f, 12.8f, 1.0f, 2.2f)}, false},
        {"wall_dining_lounge", {14, 10.05f}, {14, 19.95f}, {door(14.2f, 15.8f, 2.2f)}, {window(17.4f, 18.8f, 1.0f, 2.2f)}, false},
    };
    Builder trim("trim");
    for (const WallSpec& w : walls) {
        std::vector<Opening> openings = w.doors;
        openings.insert(openings.end(), w.windows.begin(), w.windows.end());
        level.put(level.add(wall(w.name, w.a, w.b, openings)), mat4(1.0f));
        // Outer walls are trimmed on the inside only: the side of the building's centre.
        const vec2 d = glm::normalize(w.b - w.a);
        const float inside = glm::dot(vec2(-d.y, d.x), vec2(15, 10) - w.a) > 0 ? 1.0f : -1.0f;
        for (const Opening& o : w.doors)
            casing(trim, w.a, w.b, o, false, 0.0f);
        for (const Opening& o : w.windows)
            casing(trim, w.a, w.b, o, w.outer, w.outer ? inside : 0.0f);
    }
    level.put(level.add(std::move(trim.mesh)), mat4(1.0f));
    level.put(level.add(tiles("floor", {0, 0}, {30, 20}, 0.0f, 1.0f, 1.0f)), mat4(1.0f));
    level.put(level.add(tiles("ceiling", {0, 0}, {30, 20}, kCeiling, -1.0f, 2.0f)), mat4(1.0f));
}

void addFurniture(LevelBuilder& level)
{
    const float quarter = 0.25f, half = 0.5f;   // turns
    // --- pillars: two rows in the conservatory B (outside the demo shaft), four in the lounge E.
    const std::uint32_t pillarMesh = level.add(pillar());
    for (float x : {12.0f, 15.0f, 18.0f, 21.0f})
        for (float z : {2.6f, 7.4f})
            level.put(pillarMesh, place({x, 0, z}));
    for (float x : {18.0f, 26.0f})
        for (float z : {13.0f, 17.0f})
            level.put(pillarMesh, place({x, 0, z}));

    // --- the balustrade across the gallery A (x = 4.5, z in [2.5, 8.5]); sections run along +z.
    const std::uint32_t railMesh = level.add(railing()), postMesh = level.add(railingPost());
    for (int k = 0; k < 3; ++k)
        level.put(railMesh, place({4.5f, 0, 2.5f + 2.0f * float(k)}, -quarter));
    level.put(postMesh, place({4.5f, 0, 8.5f}, -quarter));

    // --- tables and chairs. A chair faces +z locally; turn it to face the table centre.
    const std::uint32_t roundMesh = level.add(tableRound()), bistroMesh = level.add(chairBistro());
    const std::uint32_t longMesh = level.add(tableLong()), woodMesh = level.add(chairWood());
    auto roundTable = [&](vec2 c, float phase, int chairs) {
        level.put(roundMesh, place({c.x, 0, c.y}, phase));
        for (int i = 0; i < chairs; ++i) {
            const float a = phase + float(i) / float(chairs);
            // At angle a around the table; a yaw of -a - 1/4 turns the chair's +z to the centre.
            level.put(bistroMesh, place(vec3(c.x, 0, c.y) + onCircle(0.72f, a, 0.0f), -a - quarter));
        }
    };
    roundTable({7.6f, 2.0f}, 0.3f, 3);     // gallery
    roundTable({14.2f, 4.35f}, 0.1f, 4);   // conservatory, in the shaft
    roundTable({17.4f, 8.4f}, 0.3f, 3);
    roundTable({12.6f, 1.4f}, 0.5f, 2);
    for (float x : {4.0f, 9.8f}) {         // dining hall: two long tables, eight chairs each
        level.put(longMesh, place({x, 0, 15.0f}));
        for (float dx : {-0.75f, 0.0f, 0.75f}) {
            level.put(woodMesh, place({x + dx, 0, 15.0f - 0.62f}, 0.0f));
            level.put(woodMesh, place({x + dx, 0, 15.0f + 0.62f}, half));
        }
        level.put(woodMesh, place({x - 1.5f, 0, 15.0f}, quarter));
        level.put(woodMesh, place({x + 1.5f, 0, 15.0f}, -quarter));
    }

    // --- lounge: sofas around low tables.
    const std::uint32_t sofaMesh = level.add(sofa()), lowMesh = level.add(tableLow());
    level.put(lowMesh, place({22, 0, 15}));
    level.put(sofaMesh, place({22, 0, 13.6f}, 0.0f));
    level.put(sofaMesh, place({22, 0, 16.4f}, half));
    level.put(lowMesh, place({28.2f, 0, 12.2f}, quarter));
    level.put(sofaMesh, place({29.3f, 0, 12.2f}, -quarter));
    level.put(sofaMesh, place({16.0f, 0, 18.9f}, half));

    // --- shelves and crates: archive C, plus a few in the dining hall and the lounge.
    const std::uint32_t caseA = level.add(bookcase("bookcase_a", 0xB00C5ull));
    const std::uint32_t caseB = level.add(bookcase("bookcase_b", 0xB00C6ull));
    for (int i = 0; i < 3; ++i) {          // a back-to-back row in the archive
        const float x = 23.4f + 1.22f * float(i);
        level.put(i % 2 ? caseA : caseB, place({x, 0, 4.6f}, half));
        level.put(i % 2 ? caseB : caseA, place({x, 0, 4.97f}, 0.0f));
    }
    level.put(caseA, place({1.4f, 0, 10.3f}));        // dining hall, against the middle wall
    level.put(caseB, place({18.8f, 0, 19.7f}, half));  // lounge, against the north wall
    const std::uint32_t crateL = level.add(crate("crate_large", 0.8f)), crateS = level.add(crate("crate_small", 0.5f));
    Rng rng(0xC4A7Eull);
    for (vec2 c : {vec2(23.0f, 0.7f), vec2(24.0f, 0.8f), vec2(28.9f, 1.0f), vec2(29.0f, 9.0f), vec2(27.9f, 9.1f)}) {
        level.put(crateL, place({c.x, 0, c.y}, rng.range(-0.03f, 0.03f)));
        level.put(crateS, place({c.x + rng.range(-0.1f, 0.1f), 0.8f, c.y + rng.range(-0.1f, 0.1f)}, rng.range(-0.1f, 0.1f)));
    }
    for (vec2 c : {vec2(25.3f, 8.9f), vec2(23.2f, 9.3f), vec2(26.4f, 0.6f)})
        level.put(crateS, place({c.x, 0, c.y}, rng.range(-0.1f, 0.1f)));

    // --- vases on plinths (gallery, dining), pendant lamps (origin at the ceiling).
    const std::uint32_t vaseMesh = level.add(vaseOnPlinth());
    for (vec2 c : {vec2(0.6f, 0.6f), vec2(0.6f, 9.4f), vec2(9.4f, 0.6f), vec2(13.4f, 19.4f)})
        level.put(vaseMesh, place({c.x, 0, c.y}));
    const std::uint32_t lampMesh = level.add(pendantLamp("lamp_pendant", 0.0f));
    const std::uint32_t lampLong = level.add(pendantLamp("lamp_pendant_long", 0.4f));
    for (vec2 c : {vec2(7.6f, 2.0f), vec2(2.9f, 15.0f), vec2(5.1f, 15.0f), vec2(8.7f, 15.0f), vec2(10.9f, 15.0f),
                   vec2(22.0f, 15.0f), vec2(26.0f, 5.0f), vec2(5.0f, 5.0f)})
        level.put(lampMesh, place({c.x, kCeiling, c.y}));
    for (vec2 c : {vec2(14.2f, 4.35f), vec2(17.4f, 8.4f), vec2(12.6f, 1.4f)})
        level.put(lampLong, place({c.x, kCeiling, c.y}));
}

void addPlants(LevelBuilder& level)
{
    const std::uint32_t potMesh = level.add(pot()), basketMesh = level.add(basket());
    const std::uint32_t variants[3] = {level.add(plant(kFicus)), level.add(plant(kFern)), level.add(plant(kPalm))};
    const std::uint32_t hanging = level.add(plant(kHanging));
    struct Spot {
        float x, z;
        int variant;   // 0 ficus, 1 fern, 2 palm
    };
    const Spot spots[] = {
        // In the demo shaft (z ~ 4-6): two in the gallery by the doorway, seven in the conservatory.
        {7.0f, 4.55f, 0}, {8.8f, 5.65f, 1}, {12.2f, 5.45f, 2}, {13.4f, 5.6f, 0}, {15.7f, 5.5f, 0}, {17.0f, 4.45f, 1},
        {18.7f, 5.5f, 0}, {20.2f, 4.5f, 2}, {21.1f, 5.6f, 1},
        // Elsewhere, mostly in corners and beside doors.
        {0.7f, 2.5f, 0}, {3.0f, 9.4f, 1}, {9.3f, 9.3f, 2}, {9.4f, 3.6f, 1},                        // gallery
        {10.7f, 0.6f, 0}, {10.7f, 9.4f, 2}, {21.4f, 0.6f, 1}, {21.4f, 9.4f, 0}, {15.3f, 9.4f, 1},  // conservatory
        {23.0f, 2.2f, 2}, {29.4f, 5.0f, 0}, {26.8f, 9.3f, 1},                                       // archive
        {0.6f, 10.7f, 2}, {13.4f, 10.7f, 0}, {0.6f, 19.4f, 1}, {7.0f, 19.4f, 0}, {4.8f, 19.4f, 2},  // dining hall
        {14.7f, 19.4f, 0}, {29.4f, 19.4f, 2}, {19.6f, 10.7f, 0}, {23.9f, 19.4f, 1}, {26.0f, 15.0f, 0}, // lounge
    };
    Rng rng(0x9A27ull);
    for (const Spot& s : spots) {
        const float turn = rng.unit(), size = rng.range(0.9f, 1.1f);
        level.put(potMesh, place({s.x, 0, s.z}, turn));
        level.put(variants[s.variant], place({s.x, 0, s.z}, turn, size));
    }
    for (vec2 c : {vec2(7.9f, 5.2f), vec2(11.4f, 4.7f), vec2(16.4f, 5.1f), vec2(19.5f, 5.3f), vec2(25.0f, 15.0f)}) {
        const float turn = rng.unit();
        level.put(basketMesh, place({c.x, kCeiling, c.y}, turn));
        level.put(hanging, place({c.x, kCeiling, c.y}, turn));
    }
}

} // namespace

Scene makeDemoLevel()
{
    LevelBuilder level;
    addArchitecture(level);
    addFurniture(level);
    addPlants(level);
    return std::move(level.scene);
}

namespace {

using namespace parts;

/// An empty benchmark scene with its patches: the demo view's shapes, 10 m apart along +x.
BenchScene benchScene(std::string name)
{
    BenchScene out;
    out.name = std::move(name);
    const DemoView view = demoView();
    out.source = view.source;
    out.receiver = view.receiver;
    out.source.corner = {0.0, 0.3, 5.5};
    out.receiver.corner = {10.0, 0.2, 4.0};
    return out;
}

} // namespace

BenchScene makeFewOccludersScene()
{
    BenchScene out = benchScene("few-occluders");
    // A wall with a 0.9 m doorway at x = 3, four square pillars, a wall with a window at x = 8.
    out.scene.addMeshInstance(wall("wall_door", {3.0f, 0.0f}, {3.0f, 10.0f}, {{4.55f, 5.45f, 0.0f, 2.1f}}));
    out.scene.addMeshInstance(wall("wall_window", {8.0f, 0.0f}, {8.0f, 10.0f}, {{4.2f, 5.8f, 0.9f, 1.9f}}));
    for (int k = 0; k < 4; ++k) {
        Builder b("pillar_square");
        const float x = 4.0f + 0.9f * float(k), z = k % 2 ? 4.6f : 5.3f;
        box(b, {x - 0.15f, 0.0f, z - 0.15f}, {x + 0.15f, kCeiling, z + 0.15f});
        out.scene.addMeshInstance(std::move(b.mesh));
    }
    return out;
}

BenchScene makeDenseMeshScene()
{
    BenchScene out = benchScene("dense-mesh");
    // A lumpy sphere (a scanned statue stand-in) of 2 x 130 x 266 = 69,160 triangles of about
    // 2 cm, in the middle of the shaft: r = 0.75 (1 + 0.12 sin(5 theta) sin(7 phi)).
    constexpr int kStacks = 131, kSlices = 266;
    const glm::dvec3 centre(5.0, 1.2, 5.0);
    auto point = [&](int i, int j) {
        const glm::dvec2 polar = cosSin(0.5 * i / kStacks), around = cosSin(double(j) / kSlices);
        const double lump = 1.0 + 0.12 * cosSin(2.5 * i / kStacks - 0.25).y * cosSin(7.0 * j / kSlices).y;
        const double r = 0.75 * lump;
        return vec3(centre + r * glm::dvec3(polar.y * around.x, polar.x, polar.y * around.y));
    };
    Builder b("statue", /*watertight=*/false);   // an imported mesh carries no watertight flag
    for (int i = 0; i < kStacks; ++i)
        for (int j = 0; j < kSlices; ++j) {
            const vec3 p00 = point(i, j), p01 = point(i, j + 1), p10 = point(i + 1, j), p11 = point(i + 1, j + 1);
            if (i > 0)
                b.triangle(p00, p01, p11);
            if (i + 1 < kStacks)
                b.triangle(p00, p11, p10);
        }
    out.scene.addMeshInstance(std::move(b.mesh));
    return out;
}

DemoView demoView()
{
    DemoView view;
    view.source.corner = {2.0, 0.3, 5.5};
    view.source.u = {0.0, 0.0, -1.0};
    view.source.v = {0.0, 1.6, 0.0};
    view.receiver.corner = {21.85, 0.2, 4.0};
    view.receiver.u = {0.0, 0.0, 2.0};
    view.receiver.v = {0.0, 2.0, 0.0};
    view.source.na = view.source.nb = 32;
    view.receiver.na = view.receiver.nb = 32;
    return view;
}

} // namespace sightline::demo
