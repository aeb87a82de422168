#include "demo/bench/Rooms.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "demo/Props.h"

namespace sightline::demo::bench {

Opening door(float s0, float s1, float height) { return {s0, s1, 0.0f, height}; }
Opening window(float s0, float s1, float y0, float y1) { return {s0, s1, y0, y1}; }

std::vector<Opening> windowRow(float s0, float s1, float pitch, float width, float y0, float y1,
                               const std::vector<vec2>& clear)
{
    std::vector<Opening> out;
    const int count = std::max(0, int((s1 - s0) / pitch));
    const float margin = 0.5f * ((s1 - s0) - float(count) * pitch);
    for (int k = 0; k < count; ++k) {
        const float c = s0 + margin + pitch * (float(k) + 0.5f);
        const float a = c - 0.5f * width, b = c + 0.5f * width;
        if (std::none_of(clear.begin(), clear.end(), [&](vec2 r) { return a < r.y + 0.3f && r.x - 0.3f < b; }))
            out.push_back(window(a, b, y0, y1));
    }
    return out;
}

void addShell(Stage& stage, const std::vector<WallPlan>& walls, const Rect& floor, float height, float floorTile,
              float ceilingTile)
{
    const vec2 centre = 0.5f * (floor.lo + floor.hi);
    Builder trim("trim");
    int index = 0;
    for (const WallPlan& w : walls) {
        std::vector<Opening> openings = w.doors;
        openings.insert(openings.end(), w.windows.begin(), w.windows.end());
        stage.putNew(wall("wall_" + std::to_string(index++), w.a, w.b, openings, height));
        const vec2 d = glm::normalize(w.b - w.a);
        const float inside = glm::dot(vec2(-d.y, d.x), centre - w.a) > 0 ? 1.0f : -1.0f;
        for (const Opening& o : w.doors)
            casing(trim, w.a, w.b, o, false, 0.0f);
        for (const Opening& o : w.windows)
            casing(trim, w.a, w.b, o, w.outer, w.outer ? inside : 0.0f);
        stage.take({glm::min(w.a, w.b) - vec2(0.2f), glm::max(w.a, w.b) + vec2(0.2f)});
        // The floor a metre either side of a doorway stays open: a room must be walkable.
        const bool alongX = std::abs(d.x) > std::abs(d.y);
        for (const Opening& o : w.doors) {
            const vec2 lo = alongX ? vec2(o.s0, w.a.y - 1.0f) : vec2(w.a.x - 1.0f, o.s0);
            const vec2 hi = alongX ? vec2(o.s1, w.a.y + 1.0f) : vec2(w.a.x + 1.0f, o.s1);
            stage.take({lo, hi});
        }
    }
    if (!trim.mesh.indices.empty())
        stage.putNew(std::move(trim.mesh));
    stage.putNew(tiles("floor", floor.lo, floor.hi, 0.0f, 1.0f, floorTile));
    stage.putNew(tiles("ceiling", floor.lo, floor.hi, height, -1.0f, ceilingTile));
}

std::uint32_t Furnisher::mesh(MeshId which)
{
    if (meshes_.empty())
        meshes_.assign(MeshCount, -1);
    std::int64_t& id = meshes_[std::size_t(which)];
    if (id < 0) {
        Mesh m;
        switch (which) {
        case BookcaseA: m = bookcase("bookcase_a", 0xB00C5ull); break;
        case BookcaseB: m = bookcase("bookcase_b", 0xB00C6ull); break;
        case RoundTable: m = tableRound(); break;
        case BistroChair: m = chairBistro(); break;
        case LongTable: m = tableLong(); break;
        case WoodChair: m = chairWood(); break;
        case CrateLarge: m = crate("crate_large", 0.8f); break;
        case CrateSmall: m = crate("crate_small", 0.5f); break;
        case Sofa: m = sofa(); break;
        case LowTable: m = tableLow(); break;
        default: m = vaseOnPlinth(); break;
        }
        id = stage_.add(std::move(m));
    }
    return std::uint32_t(id);
}

bool Furnisher::tryPlace(Piece piece, const Rect& room)
{
    static constexpr vec2 kHalf[PieceCount] = {{0.62f, 0.2f}, {1.0f, 1.0f}, {1.3f, 0.95f},
                                               {0.45f, 0.45f}, {1.05f, 0.95f}, {0.25f, 0.25f}};
    Rng& rng = stage_.rng;
    const int quarter = rng.between(0, 3);
    const vec2 half = quarter % 2 ? vec2(kHalf[piece].y, kHalf[piece].x) : kHalf[piece];
    const vec2 lo = room.lo + half + vec2(0.1f), hi = room.hi - half - vec2(0.1f);
    if (lo.x > hi.x || lo.y > hi.y)
        return false;
    const vec2 c(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
    const Rect footprint = Rect::around(c, half);
    if (!stage_.isFree(footprint.grown(0.1f)))
        return false;
    stage_.take(footprint);
    const mat4 at = place({c.x, 0.0f, c.y}, 0.25f * float(quarter) + rng.range(-0.01f, 0.01f));
    switch (piece) {
    case Bookcase: stage_.put(mesh(rng.unit() < 0.5f ? BookcaseA : BookcaseB), at); break;
    case RoundTableSet: {
        stage_.put(mesh(RoundTable), at);
        const int chairs = rng.between(2, 4);
        const float phase = rng.unit();
        for (int i = 0; i < chairs; ++i) {
            const float a = phase + float(i) / float(chairs);
            stage_.put(mesh(BistroChair), at * place(onCircle(0.72f, a, 0.0f), -a - 0.25f));
        }
        break;
    }
    case LongTableSet:
        stage_.put(mesh(LongTable), at);
        for (float dx : {-0.75f, 0.0f, 0.75f})
            for (float side : {-1.0f, 1.0f})
                if (rng.unit() < 0.8f)
                    stage_.put(mesh(WoodChair), at * place({dx, 0.0f, 0.62f * side}, side < 0 ? 0.0f : 0.5f));
        break;
    case CrateStack:
        stage_.put(mesh(CrateLarge), at);
        if (rng.unit() < 0.6f)
            stage_.put(mesh(CrateSmall), at * place({rng.range(-0.1f, 0.1f), 0.8f, rng.range(-0.1f, 0.1f)}, rng.range(-0.1f, 0.1f)));
        break;
    case SofaSet:
        stage_.put(mesh(Sofa), at * translate({0.0f, 0.0f, -0.5f}));
        stage_.put(mesh(LowTable), at * translate({0.0f, 0.0f, 0.45f}));
        break;
    default: stage_.put(mesh(VaseOnPlinth), at); break;
    }
    return true;
}

int Furnisher::fill(const Rect& room, std::size_t targetTriangles, int maxPieces)
{
    int placed = 0;
    for (int misses = 0; placed < maxPieces && misses < 80 && stage_.scene.triangleCount() < targetTriangles;) {
        if (tryPlace(Piece(stage_.rng.between(0, PieceCount - 1)), room)) {
            ++placed;
            misses = 0;
        } else {
            ++misses;
        }
    }
    return placed;
}

} // namespace sightline::demo::bench
