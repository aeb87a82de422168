#pragma once
// A compiled Quake 1 level (BSP29, BSP2 as modern compilers write it, and Half-Life's BSP30, which
// keeps Quake's layout): what leaf-to-leaf
// visibility needs from it (the world model's planes, nodes and leaves, and its visibility lump),
// and a copy of the file with a new visibility lump that engines and tools read unchanged.
//
// Quake's layout: a header (version, 15 lumps of offset and length), then the lumps. The world is
// model 0: its tree starts at headnode[0]; a child index >= 0 is a node, a negative one the leaf
// -(child + 1). Leaf 0 is the shared solid leaf; leaves 1..visleafs have visibility rows, each
// (visleafs + 7) / 8 bytes compressed by zero runs (pvs/PvsFile.h), bit m - 1 for leaf m, found at
// the leaf's visofs (-1: none, which engines read as "sees everything").

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/pvs/PvsData.h"

namespace sightline::bsp {

/// Quake 1's BSP29, BSP2 (Quake 1 with 32-bit indices and float boxes, as modern compilers write
/// it), and Half-Life's version 30 (Quake 1's records, its own textures and liquids named "!...").
enum class BspFormat { Bsp29, Bsp2, HalfLife30 };
inline bool wideRecords(BspFormat f) { return f == BspFormat::Bsp2; }
inline const char* formatName(BspFormat f)
{
    return f == BspFormat::Bsp29 ? "BSP29" : f == BspFormat::Bsp2 ? "BSP2" : "Half-Life BSP30";
}

/// Leaf contents as Quake writes them.
inline constexpr int kContentsEmpty = -1, kContentsSolid = -2, kContentsWater = -3,
                     kContentsSlime = -4, kContentsLava = -5, kContentsSky = -6;

inline constexpr int kLumpCount = 15;
/// The largest world coordinate read, in Quake units (BSP29 levels fit in +-32768; BSP2 ones a
/// little beyond): far enough for any level, near enough that double windings stay exact to 1e-6.
inline constexpr double kMaxBspCoordinate = 1e6;
inline constexpr int kPlaneLump = 1, kTextureLump = 2, kVertexLump = 3, kVisibilityLump = 4, kNodeLump = 5,
                     kTexinfoLump = 6, kFaceLump = 7, kLeafLump = 10, kEdgeLump = 12, kSurfedgeLump = 13,
                     kModelLump = 14;

struct BspPlane {
    glm::dvec3 normal{0.0};   ///< as stored (float), not renormalised: the level's own planes
    double dist = 0.0;
    double side(const glm::dvec3& p) const { return normal.x * p.x + normal.y * p.y + normal.z * p.z - dist; }
};

struct BspNode {
    int plane = 0;
    std::array<int, 2> children{};   ///< [0] in front of the plane, [1] behind; < 0: leaf -(c + 1)
};

struct BspLeaf {
    int contents = kContentsSolid;
    int visofs = -1;
};

struct QuakeBsp {
    BspFormat format = BspFormat::Bsp29;
    std::string bytes;                                 ///< the file as read, for the rewritten copy
    std::array<std::array<std::uint32_t, 2>, kLumpCount> lumps{};   ///< offset, length
    std::vector<BspPlane> planes;
    std::vector<BspNode> nodes;
    std::vector<BspLeaf> leaves;
    int headnode = 0;                                  ///< model 0's hull-0 root
    int visleafs = 0;                                  ///< model 0's: leaves 1..visleafs have rows
    glm::dvec3 mins{0.0}, maxs{0.0};                   ///< model 0's bounds

    bool hasVisibility() const { return lumps[kVisibilityLump][1] > 0; }
    static int leafOfChild(int child) { return -(child + 1); }
};

/// Parses a BSP's bytes; `what` names the file in errors. Throws sightline::Error for another
/// format (naming it: Quake 2's IBSP, the 2PSB variant), a lump outside the file or
/// of a length that is not a whole number of records, a plane that is not finite or has no normal,
/// world bounds beyond kMaxBspCoordinate, a node's plane or child out of range, a world tree that reaches a node twice (a cycle or a
/// shared subtree: not a tree), a visleafs count beyond the leaves, or a leaf's visofs outside the
/// visibility lump. Nothing is allocated beyond what the file's own bytes justify.
QuakeBsp readQuakeBsp(std::string bytes, const std::string& what);

/// The level's own visibility as rows over its visleafs: row l, bit m = leaf l + 1 sees leaf
/// m + 1. A leaf without a row (visofs -1, or no visibility lump) sees every leaf, as engines read
/// it. Throws sightline::Error when a row does not decode to its length.
pvs::VisibilityRows levelVisibility(const QuakeBsp& bsp, const std::string& what);

/// The visibility lump for `rows` (row l for leaf l + 1, bit m for leaf m + 1) and each leaf's
/// visofs into it: rows that compress to the same bytes are stored once. `rowOffsets[l]` is leaf
/// l + 1's visofs.
struct VisibilityLump {
    std::string bytes;
    std::vector<std::int32_t> rowOffsets;
};
VisibilityLump encodeVisibilityLump(const pvs::VisibilityRows& rows);

/// The file again with `rows` as its visibility lump: every other lump's bytes unchanged except
/// the leaves' visofs (leaves 1..visleafs point at their rows; the others keep -1), lumps laid out
/// in order on 4-byte boundaries. `rows` must be visleafs x visleafs.
std::string withVisibility(const QuakeBsp& bsp, const pvs::VisibilityRows& rows);

/// One face of the world model: a convex polygon in the level's units and axes (Quake's: Z up),
/// wound as Quake winds it (clockwise seen from the front), and its texture's name ("*..." for
/// water, slime and lava, "sky..." for sky; empty where the level has no texture data).
struct BspFace {
    std::vector<glm::dvec3> polygon;
    std::string texture;
};

/// The world model's faces (model 0's firstface..+numfaces). Throws sightline::Error for a face,
/// edge, surfedge, vertex or texture reference out of range, a face of fewer than 3 or more than
/// kMaxFaceEdges edges, or a vertex that is not finite or lies beyond kMaxBspCoordinate.
inline constexpr int kMaxFaceEdges = 1024;
std::vector<BspFace> worldFaces(const QuakeBsp& bsp, const std::string& what);

/// The leaf holding `p` (Quake's point-in-leaf: on a plane counts as behind it).
int leafAt(const QuakeBsp& bsp, const glm::dvec3& p);

} // namespace sightline::bsp
