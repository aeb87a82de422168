#pragma once
// Rooms for the bench scenes (internal): wall plans turned into closed wall slabs with casings,
// floor and ceiling tile grids, and a furnisher that fills rooms with the demo's furniture at
// random free spots until the level reaches a triangle budget, the bulk of a real level that
// lies outside the shaft.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "demo/bench/Stage.h"

namespace sightline::demo::bench {

struct WallPlan {
    vec2 a, b;                      ///< on the floor, a to b along +x or +z
    std::vector<Opening> doors;     ///< from the floor
    std::vector<Opening> windows;
    bool outer = false;             ///< outer windows get mullions and inside casings only
};

/// The walls (one closed mesh each), their casings (one mesh), a floor of `floorTile` m tiles and
/// a ceiling of `ceilingTile` m tiles at `height` over `floor`. The walls' lines and the floor in
/// front of each door are taken, so nothing is put inside a wall or in a doorway.
void addShell(Stage& stage, const std::vector<WallPlan>& walls, const Rect& floor, float height, float floorTile,
              float ceilingTile);

Opening door(float s0, float s1, float height = 2.1f);
Opening window(float s0, float s1, float y0 = 0.9f, float y1 = 2.3f);
/// Windows `width` wide every `pitch` m from s0 to s1 (world coordinates along the wall), leaving
/// out any that would come within 0.3 m of one of the `clear` ranges (doors, walls meeting it).
std::vector<Opening> windowRow(float s0, float s1, float pitch, float width, float y0, float y1,
                               const std::vector<vec2>& clear = {});

/// Places furniture (bookcases, round tables with bistro chairs, long tables with chairs, crate
/// stacks, sofas with low tables, vases on plinths) at free spots; each piece's floor is taken.
class Furnisher {
public:
    explicit Furnisher(Stage& stage) : stage_(stage) {}

    /// Places random pieces inside `room` (0.1 m off its edges) until the scene has
    /// `targetTriangles`, `maxPieces` are placed, or 80 tries in a row find no free spot. Returns
    /// the number placed.
    int fill(const Rect& room, std::size_t targetTriangles, int maxPieces);

private:
    enum Piece { Bookcase, RoundTableSet, LongTableSet, CrateStack, SofaSet, Vase, PieceCount };
    enum MeshId { BookcaseA, BookcaseB, RoundTable, BistroChair, LongTable, WoodChair, CrateLarge, CrateSmall,
                  Sofa, LowTable, VaseOnPlinth, MeshCount };
    bool tryPlace(Piece piece, const Rect& room);
    std::uint32_t mesh(MeshId which);

    Stage& stage_;
    std::vector<std::int64_t> meshes_;   ///< lazily added, -1 until first used
};

} // namespace sightline::demo::bench
