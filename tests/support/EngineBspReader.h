#pragma once
// A Quake engine's reading of a compiled BSP's world tree and visibility (model.c's
// Mod_LoadBrushModel: Mod_LoadPlanes, Mod_LoadVisibility, Mod_LoadLeafs, Mod_LoadNodes,
// Mod_LoadSubmodels, then Mod_DecompressVis, Mod_LeafPVS and Mod_PointInLeaf), written apart from
// Sightline's own BSP reader so that a file Sightline writes is judged by what an engine would do
// with it. Where the engine trusts the file and would read past a buffer, this reader throws
// std::runtime_error instead, so a test fails on anything an engine could misread.

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace sightline::test {

// bspfile.h's BSP2VERSION: the magic "BSP2" read as a little-endian int.
inline constexpr int kBsp2Version = 'B' | ('S' << 8) | ('P' << 16) | ('2' << 24);

struct EngineBsp {
    int version = 0;                    // 29, or kBsp2Version
    int visleafs = 0;                   // model 0's
    std::vector<int> leafContents;      // per leaf
    std::vector<int> leafVisofs;        // per leaf
    std::vector<std::array<float, 4>> planes;   // normal xyz, dist
    struct Node {
        int plane;
        int children[2];   // as in the file: >= 0 node, < 0 is -(leaf + 1)
    };
    std::vector<Node> nodes;
    std::vector<std::pair<int, int>> lumps;   // (offset, length) per lump
    std::string file;                         // the whole file, for lumpBytes and the vis rows

    /// Raw bytes of lump k.
    std::string lumpBytes(int lump) const
    {
        if (lump < 0 || static_cast<std::size_t>(lump) >= lumps.size())
            throw std::out_of_range("EngineBsp::lumpBytes: no such lump");
        const auto [ofs, len] = lumps[static_cast<std::size_t>(lump)];
        return file.substr(static_cast<std::size_t>(ofs), static_cast<std::size_t>(len));
    }
};

namespace engine_bsp_detail {

inline constexpr int kLumpEntities = 0, kLumpPlanes = 1, kLumpTextures = 2, kLumpVertexes = 3,
                     kLumpVisibility = 4, kLumpNodes = 5, kLumpTexinfo = 6, kLumpFaces = 7,
                     kLumpLighting = 8, kLumpClipnodes = 9, kLumpLeafs = 10, kLumpMarksurfaces = 11,
                     kLumpEdges = 12, kLumpSurfedges = 13, kLumpModels = 14, kNumLumps = 15;

[[noreturn]] inline void fail(const std::string& what) { throw std::runtime_error("engine BSP: " + what); }

// Little-endian fields, assembled byte by byte (LittleLong and friends); callers check bounds.
inline std::uint32_t u32(const std::string& s, std::size_t at)
{
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i)
        v = (v << 8) | static_cast<std::uint8_t>(s[at + static_cast<std::size_t>(i)]);
    return v;
}
inline std::int32_t i32(const std::string& s, std::size_t at) { return static_cast<std::int32_t>(u32(s, at)); }
inline std::int16_t i16(const std::string& s, std::size_t at)
{
    return static_cast<std::int16_t>(static_cast<std::uint16_t>(static_cast<std::uint8_t>(s[at]) |
                                                                (static_cast<std::uint8_t>(s[at + 1]) << 8)));
}
inline float f32(const std::string& s, std::size_t at) { return std::bit_cast<float>(u32(s, at)); }

}   // namespace engine_bsp_detail

/// Mod_DecompressVis for leaf `leaf` as Mod_LeafPVS calls it: the (visleafs + 7) / 8 bytes of the
/// leaf's row; leaf 0 and visofs -1 give all 0xff (mod_novis). Throws std::out_of_range for a leaf
/// outside 0..visleafs, std::runtime_error when the row runs past the vis lump or past its length,
/// or holds a zero run of length 0 (which no vis tool writes).
inline std::vector<std::uint8_t> engineDecompressVis(const EngineBsp& bsp, int leaf)
{
    using namespace engine_bsp_detail;
    if (leaf < 0 || leaf > bsp.visleafs || static_cast<std::size_t>(leaf) >= bsp.leafVisofs.size())
        throw std::out_of_range("engineDecompressVis: leaf outside 0..visleafs");
    const std::size_t row = static_cast<std::size_t>(bsp.visleafs + 7) >> 3;
    const int visofs = bsp.leafVisofs[static_cast<std::size_t>(leaf)];
    if (leaf == 0 || visofs == -1)
        return std::vector<std::uint8_t>(row, 0xff);

    const auto [lumpOfs, lumpLen] = bsp.lumps[kLumpVisibility];
    const std::size_t end = static_cast<std::size_t>(lumpOfs) + static_cast<std::size_t>(lumpLen);
    std::size_t in = static_cast<std::size_t>(lumpOfs) + static_cast<std::size_t>(visofs);
    std::vector<std::uint8_t> out;
    out.reserve(row);
    while (out.size() < row) {
        if (in >= end)
            fail("vis row of leaf " + std::to_string(leaf) + " runs past the vis lump");
        const auto b = static_cast<std::uint8_t>(bsp.file[in++]);
        if (b != 0) {
            out.push_back(b);
            continue;
        }
        if (in >= end)
            fail("vis row of leaf " + std::to_string(leaf) + " runs past the vis lump (zero run's count)");
        const auto count = static_cast<std::uint8_t>(bsp.file[in++]);
        if (count == 0)
            fail("vis row of leaf " + std::to_string(leaf) + " has a zero run of length 0");
        if (out.size() + count > row)
            fail("vis row of leaf " + std::to_string(leaf) + " runs past the row length");
        out.insert(out.end(), count, std::uint8_t{0});
    }
    return out;
}

/// Reads `bytes` as an engine's model loader does, with every check strict (see above).
inline EngineBsp readEngineBsp(const std::string& bytes)
{
    using namespace engine_bsp_detail;
    EngineBsp bsp;
    bsp.file = bytes;
    constexpr std::size_t headerBytes = 4 + kNumLumps * 8;
    if (bytes.size() < headerBytes)
        fail("file of " + std::to_string(bytes.size()) + " bytes is shorter than the header");

    bsp.version = i32(bytes, 0);
    const bool bsp2 = bsp.version == kBsp2Version;
    if (!bsp2 && bsp.version != 29)
        fail("unknown version " + std::to_string(bsp.version));

    for (int k = 0; k < kNumLumps; ++k) {
        const std::int64_t ofs = i32(bytes, 4 + 8 * static_cast<std::size_t>(k));
        const std::int64_t len = i32(bytes, 8 + 8 * static_cast<std::size_t>(k));
        if (ofs < 0 || len < 0 || ofs + len > static_cast<std::int64_t>(bytes.size()))
            fail("lump " + std::to_string(k) + " (offset " + std::to_string(ofs) + ", length " + std::to_string(len) +
                 ") lies outside the file of " + std::to_string(bytes.size()) + " bytes");
        bsp.lumps.emplace_back(static_cast<int>(ofs), static_cast<int>(len));
    }

    // The record sizes Mod_Load* divide by (the BSP2 ones from the engines that read BSP2).
    const auto records = [&](int k, std::size_t size) {
        const auto len = static_cast<std::size_t>(bsp.lumps[static_cast<std::size_t>(k)].second);
        if (len % size != 0)
            fail("lump " + std::to_string(k) + "'s length " + std::to_string(len) + " is not a multiple of " +
                 std::to_string(size));
        return len / size;
    };
    const auto at = [&](int k) { return static_cast<std::size_t>(bsp.lumps[static_cast<std::size_t>(k)].first); };
    records(kLumpVertexes, 12);
    records(kLumpTexinfo, 40);
    records(kLumpFaces, bsp2 ? 28 : 20);
    records(kLumpClipnodes, bsp2 ? 12 : 8);
    records(kLumpMarksurfaces, bsp2 ? 4 : 2);
    records(kLumpEdges, bsp2 ? 8 : 4);
    records(kLumpSurfedges, 4);

    // Mod_LoadTextures reads nummiptex and the offsets after it from a non-empty lump.
    if (const auto texLen = static_cast<std::size_t>(bsp.lumps[kLumpTextures].second); texLen != 0) {
        if (texLen < 4)
            fail("texture lump shorter than its count");
        const std::int32_t count = i32(bytes, at(kLumpTextures));
        if (count < 0 || 4 + 4 * static_cast<std::size_t>(count) > texLen)
            fail("texture lump's miptex count " + std::to_string(count) + " runs past the lump");
    }

    const std::size_t numPlanes = records(kLumpPlanes, 20);
    for (std::size_t i = 0; i < numPlanes; ++i) {
        const std::size_t p = at(kLumpPlanes) + 20 * i;
        bsp.planes.push_back({f32(bytes, p), f32(bytes, p + 4), f32(bytes, p + 8), f32(bytes, p + 12)});
    }

    // Mod_LoadVisibility keeps the lump; Mod_LoadLeafs points each leaf's compressed_vis into it.
    const auto visLen = bsp.lumps[kLumpVisibility].second;
    const std::size_t leafSize = bsp2 ? 44 : 28;
    const std::size_t numLeafs = records(kLumpLeafs, leafSize);
    if (numLeafs == 0)
        fail("no leafs");
    for (std::size_t i = 0; i < numLeafs; ++i) {
        const std::size_t p = at(kLumpLeafs) + leafSize * i;
        const std::int32_t contents = i32(bytes, p);
        const std::int32_t visofs = i32(bytes, p + 4);
        if (visofs != -1 && (visofs < 0 || visofs >= visLen))
            fail("leaf " + std::to_string(i) + "'s visofs " + std::to_string(visofs) +
                 " lies outside the vis lump of " + std::to_string(visLen) + " bytes");
        bsp.leafContents.push_back(contents);
        bsp.leafVisofs.push_back(visofs);
    }

    // Mod_LoadNodes: BSP29's children are signed shorts, as in the original engine.
    const std::size_t nodeSize = bsp2 ? 44 : 24;
    const std::size_t numNodes = records(kLumpNodes, nodeSize);
    if (numNodes == 0)
        fail("no nodes");
    for (std::size_t i = 0; i < numNodes; ++i) {
        const std::size_t p = at(kLumpNodes) + nodeSize * i;
        EngineBsp::Node node{};
        node.plane = i32(bytes, p);
        if (node.plane < 0 || static_cast<std::size_t>(node.plane) >= numPlanes)
            fail("node " + std::to_string(i) + "'s plane " + std::to_string(node.plane) + " is out of range");
        for (std::size_t j = 0; j < 2; ++j) {
            const int child = bsp2 ? i32(bytes, p + 4 + 4 * j) : i16(bytes, p + 4 + 2 * j);
            const bool ok = child >= 0 ? static_cast<std::size_t>(child) < numNodes
                                       : static_cast<std::size_t>(-1 - static_cast<std::int64_t>(child)) < numLeafs;
            if (!ok)
                fail("node " + std::to_string(i) + "'s child " + std::to_string(child) + " is out of range");
            node.children[j] = child;
        }
        bsp.nodes.push_back(node);
    }

    // Mod_LoadSubmodels: the world is model 0, and its visleafs sizes every vis row.
    if (records(kLumpModels, 64) == 0)
        fail("no models");
    const std::int32_t headnode = i32(bytes, at(kLumpModels) + 36);
    if (headnode < 0 || static_cast<std::size_t>(headnode) >= numNodes)
        fail("model 0's headnode " + std::to_string(headnode) + " is out of range");
    bsp.visleafs = i32(bytes, at(kLumpModels) + 52);
    if (bsp.visleafs < 0 || static_cast<std::size_t>(bsp.visleafs) >= numLeafs)
        fail("model 0's visleafs " + std::to_string(bsp.visleafs) + " does not fit " + std::to_string(numLeafs) + " leafs");

    // The engine decodes a row when the player enters the leaf; decoding them all here fails the
    // read on a row it would trip on later.
    for (int leaf = 1; leaf <= bsp.visleafs; ++leaf)
        engineDecompressVis(bsp, leaf);
    return bsp;
}

/// Quake's Mod_LeafPVS for leaf `leaf` (0..visleafs): entry m - 1 says whether leaf m is visible;
/// leaf 0 and visofs -1 give all true (mod_novis).
inline std::vector<bool> engineLeafPvs(const EngineBsp& bsp, int leaf)
{
    const std::vector<std::uint8_t> row = engineDecompressVis(bsp, leaf);
    std::vector<bool> pvs(static_cast<std::size_t>(bsp.visleafs));
    for (std::size_t m = 0; m < pvs.size(); ++m)
        pvs[m] = (row[m >> 3] >> (m & 7)) & 1u;
    return pvs;
}

/// Quake's Mod_PointInLeaf from node 0: d = dot(normal, p) - dist in single precision as the
/// engine's vec_t, front (children[0]) when d > 0, else back. Returns the leaf index.
inline int enginePointInLeaf(const EngineBsp& bsp, double x, double y, double z)
{
    if (bsp.nodes.empty())
        throw std::runtime_error("engine BSP: no nodes");
    const float p[3] = {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)};
    int node = 0;
    // Children were range-checked on reading, but a cycle would loop forever.
    for (std::size_t steps = 0; steps <= bsp.nodes.size(); ++steps) {
        const auto& n = bsp.nodes[static_cast<std::size_t>(node)];
        const auto& plane = bsp.planes[static_cast<std::size_t>(n.plane)];
        const float d = p[0] * plane[0] + p[1] * plane[1] + p[2] * plane[2] - plane[3];
        const int child = d > 0 ? n.children[0] : n.children[1];
        if (child < 0)
            return -1 - child;
        node = child;
    }
    throw std::runtime_error("engine BSP: the node tree has a cycle");
}

}   // namespace sightline::test
