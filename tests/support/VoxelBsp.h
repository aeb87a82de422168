#pragma once
// Compiled Quake 1 BSP files (BSP29 and BSP2) built from a voxel grid, for the tests of the PVS
// writer: real maps need qbsp, and a voxel kd-tree gives a valid world tree whose leaves are known
// exactly (which voxels each holds), so a test can say what visibility is right without a compiler.
// Only what an engine's model loader needs for the world tree and its visibility is filled in: no
// faces, textures, lighting or clip hulls.

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace sightline::test {

// Quake's CONTENTS_* values, as a leaf's contents field holds them.
inline constexpr int kContentsEmpty = -1, kContentsSolid = -2, kContentsWater = -3, kContentsSlime = -4,
                     kContentsLava = -5, kContentsSky = -6;

struct VoxelLevel {
    int nx = 0, ny = 0, nz = 0;   // grid size, voxel (x, y, z) at index x + nx * (y + ny * z)
    double size = 64.0;           // edge of one voxel in Quake units; voxel (x, y, z) spans [x*size, (x+1)*size] etc. (Z up)
    std::vector<int> contents;    // one of the kContents* per voxel; everything outside the grid counts as solid

    std::size_t index(int x, int y, int z) const
    {
        if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz)
            throw std::out_of_range("VoxelLevel: voxel outside the grid");
        return static_cast<std::size_t>(x) +
               static_cast<std::size_t>(nx) * (static_cast<std::size_t>(y) + static_cast<std::size_t>(ny) * static_cast<std::size_t>(z));
    }
    int& at(int x, int y, int z) { return contents.at(index(x, y, z)); }
    int at(int x, int y, int z) const { return contents.at(index(x, y, z)); }
};

/// A grid of nx * ny * nz voxels all holding `fill` (solid by default, so tests carve rooms out of it).
inline VoxelLevel makeVoxelLevel(int nx, int ny, int nz, int fill = kContentsSolid, double size = 64.0)
{
    if (nx <= 0 || ny <= 0 || nz <= 0)
        throw std::invalid_argument("makeVoxelLevel: empty grid");
    VoxelLevel level;
    level.nx = nx;
    level.ny = ny;
    level.nz = nz;
    level.size = size;
    level.contents.assign(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) * static_cast<std::size_t>(nz), fill);
    return level;
}

enum class BspVersion { Bsp29, Bsp2 };

struct VoxelBsp {
    std::string bytes;              // the whole .bsp file
    int visleafs = 0;               // model 0's visleafs (leaves 1..visleafs)
    std::vector<int> leafOfVoxel;   // per voxel: the BSP leaf index that contains its centre (0 for solid voxels)
};

namespace voxel_bsp_detail {

// Every field is written byte by byte so the file is little-endian whatever the host is.
inline void putU32(std::string& out, std::uint32_t v)
{
    for (int i = 0; i < 4; ++i)
        out.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}
inline void putI32(std::string& out, std::int32_t v) { putU32(out, static_cast<std::uint32_t>(v)); }
inline void putU16(std::string& out, std::uint16_t v)
{
    out.push_back(static_cast<char>(v & 0xffu));
    out.push_back(static_cast<char>((v >> 8) & 0xffu));
}
inline void putI16(std::string& out, std::int16_t v) { putU16(out, static_cast<std::uint16_t>(v)); }
inline void putF32(std::string& out, float v) { putU32(out, std::bit_cast<std::uint32_t>(v)); }

inline std::int16_t toI16(double v, const char* what)
{
    if (v < std::numeric_limits<std::int16_t>::min() || v > std::numeric_limits<std::int16_t>::max())
        throw std::invalid_argument(std::string("voxelBsp: ") + what + " does not fit BSP29's 16-bit fields");
    return static_cast<std::int16_t>(v);
}

using Box = std::array<int, 3>;   // voxel coordinates, [lo, hi)

struct Tree {
    struct Plane {
        int axis;
        double dist;
    };
    struct Node {
        int plane;
        int children[2];
        Box lo, hi;
    };
    struct Leaf {
        int contents;
        Box lo, hi;
    };

    const VoxelLevel& level;
    std::vector<Plane> planes;
    std::map<std::pair<int, int>, int> planeOf;   // (axis, boundary) -> plane: nodes on one boundary share it, as in qbsp
    std::vector<Node> nodes;
    std::vector<Leaf> leaves;
    std::vector<int> leafOfVoxel;

    explicit Tree(const VoxelLevel& l) : level(l), leafOfVoxel(l.contents.size(), 0)
    {
        leaves.push_back({kContentsSolid, {0, 0, 0}, {0, 0, 0}});   // the shared solid leaf
    }

    bool uniform(const Box& lo, const Box& hi, int& contents) const
    {
        contents = level.at(lo[0], lo[1], lo[2]);
        for (int z = lo[2]; z < hi[2]; ++z)
            for (int y = lo[1]; y < hi[1]; ++y)
                for (int x = lo[0]; x < hi[0]; ++x)
                    if (level.at(x, y, z) != contents)
                        return false;
        return true;
    }

    int plane(int axis, int boundary)
    {
        const auto [it, added] = planeOf.try_emplace({axis, boundary}, static_cast<int>(planes.size()));
        if (added)
            planes.push_back({axis, boundary * level.size});
        return it->second;
    }

    // Returns the child value for the parent: a node index, or -(leaf + 1).
    int build(const Box& lo, const Box& hi)
    {
        int contents = 0;
        if (uniform(lo, hi, contents)) {
            if (contents == kContentsSolid)
                return -1;
            const int leaf = static_cast<int>(leaves.size());
            leaves.push_back({contents, lo, hi});
            for (int z = lo[2]; z < hi[2]; ++z)
                for (int y = lo[1]; y < hi[1]; ++y)
                    for (int x = lo[0]; x < hi[0]; ++x)
                        leafOfVoxel[level.index(x, y, z)] = leaf;
            return -(leaf + 1);
        }
        // Longest axis, the first of equals: a non-uniform box has at least two voxels along it.
        std::size_t axis = 0;
        for (std::size_t a = 1; a < 3; ++a)
            if (hi[a] - lo[a] > hi[axis] - lo[axis])
                axis = a;
        const int mid = lo[axis] + (hi[axis] - lo[axis]) / 2;
        const int node = static_cast<int>(nodes.size());
        nodes.push_back({plane(static_cast<int>(axis), mid), {0, 0}, lo, hi});
        Box frontLo = lo, backHi = hi;
        frontLo[axis] = mid;
        backHi[axis] = mid;
        const int front = build(frontLo, hi);
        const int back = build(lo, backHi);
        // Indexed again: the recursion may have reallocated `nodes`.
        nodes[static_cast<std::size_t>(node)].children[0] = front;
        nodes[static_cast<std::size_t>(node)].children[1] = back;
        return node;
    }
};

// Quake vis's CompressVis: zero bytes become (0, run length), runs at most 255 long.
inline void compressRow(const std::vector<std::uint8_t>& row, std::string& out)
{
    for (std::size_t j = 0; j < row.size(); ++j) {
        out.push_back(static_cast<char>(row[j]));
        if (row[j] != 0)
            continue;
        int run = 1;
        while (j + 1 < row.size() && row[j + 1] == 0 && run < 255) {
            ++j;
            ++run;
        }
        out.push_back(static_cast<char>(run));
    }
}

}   // namespace voxel_bsp_detail

/// Builds a BSP file whose world tree is a kd-tree over `level`'s voxels (see VoxelBsp). `visible`,
/// when given, decides the visibility lump: visible(a, b) for leaves a, b in 1..visleafs says
/// whether leaf a's row has leaf b's bit; without it there is no vis lump and every visofs is -1.
/// Throws std::invalid_argument for a malformed or homogeneous grid (a tree needs a node), or one
/// too large for BSP29's 16-bit fields.
inline VoxelBsp voxelBsp(const VoxelLevel& level, BspVersion version = BspVersion::Bsp29,
                         const std::function<bool(int leafA, int leafB)>& visible = {})
{
    using namespace voxel_bsp_detail;
    if (level.nx <= 0 || level.ny <= 0 || level.nz <= 0 || !(level.size > 0.0) ||
        level.contents.size() != static_cast<std::size_t>(level.nx) * static_cast<std::size_t>(level.ny) * static_cast<std::size_t>(level.nz))
        throw std::invalid_argument("voxelBsp: grid size and contents disagree");
    for (const int c : level.contents)
        if (c > kContentsEmpty || c < kContentsSky)
            throw std::invalid_argument("voxelBsp: voxel contents is not a kContents* value");

    Tree tree(level);
    if (tree.build({0, 0, 0}, {level.nx, level.ny, level.nz}) < 0)
        throw std::invalid_argument("voxelBsp: homogeneous grid, a BSP tree needs at least one node");

    const bool bsp2 = version == BspVersion::Bsp2;
    const int visleafs = static_cast<int>(tree.leaves.size()) - 1;
    if (!bsp2 && (tree.nodes.size() > 32767 || tree.leaves.size() > 32768))
        throw std::invalid_argument("voxelBsp: too many nodes or leaves for BSP29's 16-bit children");

    std::array<std::string, 15> lumps;
    lumps[0] = std::string("{\n\"classname\" \"worldspawn\"\n}\n") + '\0';

    for (const auto& p : tree.planes) {
        for (int a = 0; a < 3; ++a)
            putF32(lumps[1], a == p.axis ? 1.0f : 0.0f);
        putF32(lumps[1], static_cast<float>(p.dist));
        putI32(lumps[1], p.axis);   // PLANE_X, PLANE_Y, PLANE_Z
    }

    putI32(lumps[2], 0);   // no miptex

    std::vector<std::int32_t> visofs(tree.leaves.size(), -1);
    if (visible) {
        const std::size_t rowBytes = static_cast<std::size_t>(visleafs + 7) / 8;
        for (int a = 1; a <= visleafs; ++a) {
            std::vector<std::uint8_t> row(rowBytes, 0);
            for (int b = 1; b <= visleafs; ++b)
                if (visible(a, b))
                    row[static_cast<std::size_t>(b - 1) >> 3] |= static_cast<std::uint8_t>(1u << ((b - 1) & 7));
            visofs[static_cast<std::size_t>(a)] = static_cast<std::int32_t>(lumps[4].size());
            compressRow(row, lumps[4]);
        }
    }

    // Node and leaf boxes in world units; BSP29's shorts are rounded outward as qbsp does.
    const auto boxOut = [&](std::string& out, const Box& lo, const Box& hi) {
        for (std::size_t a = 0; a < 3; ++a) {
            const double v = lo[a] * level.size;
            if (bsp2)
                putF32(out, static_cast<float>(v));
            else
                putI16(out, toI16(std::floor(v), "box"));
        }
        for (std::size_t a = 0; a < 3; ++a) {
            const double v = hi[a] * level.size;
            if (bsp2)
                putF32(out, static_cast<float>(v));
            else
                putI16(out, toI16(std::ceil(v), "box"));
        }
    };

    for (const auto& n : tree.nodes) {
        putI32(lumps[5], n.plane);
        for (const int child : n.children) {
            if (bsp2)
                putI32(lumps[5], child);
            else
                putI16(lumps[5], static_cast<std::int16_t>(child));
        }
        boxOut(lumps[5], n.lo, n.hi);
        if (bsp2) {
            putU32(lumps[5], 0);   // firstface
            putU32(lumps[5], 0);   // numfaces
        } else {
            putU16(lumps[5], 0);
            putU16(lumps[5], 0);
        }
    }

    for (std::size_t i = 0; i < tree.leaves.size(); ++i) {
        const auto& l = tree.leaves[i];
        putI32(lumps[10], l.contents);
        putI32(lumps[10], visofs[i]);
        boxOut(lumps[10], l.lo, l.hi);
        if (bsp2) {
            putU32(lumps[10], 0);   // firstmarksurface
            putU32(lumps[10], 0);   // nummarksurfaces
        } else {
            putU16(lumps[10], 0);
            putU16(lumps[10], 0);
        }
        putU32(lumps[10], 0);   // ambient_level[4]
    }

    const std::array<int, 3> n = {level.nx, level.ny, level.nz};
    for (int a = 0; a < 3; ++a)
        putF32(lumps[14], 0.0f);
    for (const int cells : n)
        putF32(lumps[14], static_cast<float>(cells * level.size));
    for (int a = 0; a < 3; ++a)
        putF32(lumps[14], 0.0f);   // origin
    for (int h = 0; h < 4; ++h)
        putI32(lumps[14], 0);   // headnode[0] is the root; no clip hulls
    putI32(lumps[14], visleafs);
    putI32(lumps[14], 0);   // firstface
    putI32(lumps[14], 0);   // numfaces

    constexpr std::size_t headerBytes = 4 + 15 * 8;
    std::string file(headerBytes, '\0');
    if (bsp2)
        file.replace(0, 4, "BSP2");
    else
        file.replace(0, 4, std::string_view("\x1d\0\0\0", 4));
    for (std::size_t k = 0; k < lumps.size(); ++k) {
        file.resize((file.size() + 3) & ~std::size_t{3}, '\0');
        std::string entry;
        putI32(entry, static_cast<std::int32_t>(file.size()));
        putI32(entry, static_cast<std::int32_t>(lumps[k].size()));
        file.replace(4 + 8 * k, 8, entry);
        file += lumps[k];
    }

    VoxelBsp result;
    result.bytes = std::move(file);
    result.visleafs = visleafs;
    result.leafOfVoxel = std::move(tree.leafOfVoxel);
    return result;
}

}   // namespace sightline::test
