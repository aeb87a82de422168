#include "visibility/bsp/QuakeBsp.h"

#include <cmath>
#include <cstring>
#include <cstdint>
#include <unordered_map>

#include "base/Error.h"
#include "visibility/pvs/PvsFile.h"

namespace sightline::bsp {

namespace {

struct Layout {
    std::size_t node, leaf;
};
constexpr std::size_t kPlaneBytes = 20, kModelBytes = 64;
constexpr Layout kBsp29{24, 28}, kBsp2{44, 44};
constexpr std::uint32_t kBsp2Magic = 0x32505342;      // "BSP2"
constexpr std::uint32_t kBsp2RmqMagic = 0x42535032;   // "2PSB"
constexpr std::uint32_t kIbspMagic = 0x50534249;      // "IBSP" (Quake 2, Quake 3)

std::uint32_t u32(const std::string& b, std::size_t at)
{
    std::uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}
std::int32_t i32(const std::string& b, std::size_t at) { return std::int32_t(u32(b, at)); }
std::int16_t i16(const std::string& b, std::size_t at)
{
    std::int16_t v;
    std::memcpy(&v, b.data() + at, 2);
    return v;
}
float f32(const std::string& b, std::size_t at)
{
    float v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}
void put32(std::string& out, std::size_t at, std::uint32_t v) { std::memcpy(out.data() + at, &v, 4); }

std::string versionName(std::uint32_t version)
{
    if (version == kIbspMagic)
        return "a Quake 2 / Quake 3 BSP (IBSP)";
    if (version == kBsp2RmqMagic)
        return "a 2PSB BSP (the older BSP2 variant)";
    return "version " + std::to_string(version);
}

/// The records of lump `k`: their count, after checking the lump lies in the file and holds a whole
/// number of `size`-byte records.
std::size_t records(const QuakeBsp& bsp, int k, std::size_t size, const char* name, const std::string& what)
{
    const auto [offset, length] = bsp.lumps[std::size_t(k)];
    if (length % size != 0)
        throw Error(what + ": the " + name + " lump's " + std::to_string(length) + " bytes are not whole " +
                    std::to_string(size) + "-byte records");
    return length / size;
}

void readLumps(QuakeBsp& bsp, const std::string& what)
{
    const std::string& b = bsp.bytes;
    const std::size_t header = 4 + 8 * kLumpCount;
    if (b.size() < header)
        throw Error(what + ": truncated (" + std::to_string(b.size()) + " bytes; a BSP header takes " +
                    std::to_string(header) + ")");
    const std::uint32_t version = u32(b, 0);
    if (version == 29)
        bsp.format = BspFormat::Bsp29;
    else if (version == kBsp2Magic)
        bsp.format = BspFormat::Bsp2;
    else if (version == 30)
        bsp.format = BspFormat::HalfLife30;
    else
        throw Error(what + ": not a Quake 1 BSP (" + versionName(version) + "; BSP29, BSP2 and Half-Life's 30 are read)");
    for (int k = 0; k < kLumpCount; ++k) {
        const std::uint32_t offset = u32(b, 4 + 8 * std::size_t(k)), length = u32(b, 8 + 8 * std::size_t(k));
        if (std::int32_t(offset) < 0 || std::int32_t(length) < 0 || offset > b.size() || length > b.size() - offset)
            throw Error(what + ": lump " + std::to_string(k) + " (offset " + std::to_string(std::int32_t(offset)) +
                        ", " + std::to_string(std::int32_t(length)) + " bytes) lies outside the file's " +
                        std::to_string(b.size()) + " bytes");
        bsp.lumps[std::size_t(k)] = {offset, length};
    }
}

void readPlanes(QuakeBsp& bsp, const std::string& what)
{
    const std::size_t n = records(bsp, kPlaneLump, kPlaneBytes, "planes", what);
    const std::size_t base = bsp.lumps[kPlaneLump][0];
    bsp.planes.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t at = base + k * kPlaneBytes;
        BspPlane& p = bsp.planes[k];
        p.normal = {f32(bsp.bytes, at), f32(bsp.bytes, at + 4), f32(bsp.bytes, at + 8)};
        p.dist = f32(bsp.bytes, at + 12);
        const double length = std::sqrt(p.normal.x * p.normal.x + p.normal.y * p.normal.y + p.normal.z * p.normal.z);
        if (!std::isfinite(length) || !std::isfinite(p.dist) || length < 0.5 || length > 2.0)
            throw Error(what + ": plane " + std::to_string(k) + " is not finite or has no unit normal");
    }
}

void readNodes(QuakeBsp& bsp, const Layout& layout, const std::string& what)
{
    const std::size_t n = records(bsp, kNodeLump, layout.node, "nodes", what);
    const std::size_t base = bsp.lumps[kNodeLump][0];
    bsp.nodes.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t at = base + k * layout.node;
        BspNode& node = bsp.nodes[k];
        node.plane = i32(bsp.bytes, at);
        for (int s = 0; s < 2; ++s)
            node.children[std::size_t(s)] = !wideRecords(bsp.format) ? int(i16(bsp.bytes, at + 4 + 2 * std::size_t(s)))
                                                                            : i32(bsp.bytes, at + 4 + 4 * std::size_t(s));
        if (node.plane < 0 || std::size_t(node.plane) >= bsp.planes.size())
            throw Error(what + ": node " + std::to_string(k) + "'s plane " + std::to_string(node.plane) +
                        " is not one of the " + std::to_string(bsp.planes.size()) + " planes");
    }
}

void readLeaves(QuakeBsp& bsp, const Layout& layout, const std::string& what)
{
    const std::size_t n = records(bsp, kLeafLump, layout.leaf, "leaves", what);
    const std::size_t base = bsp.lumps[kLeafLump][0];
    const std::uint32_t visBytes = bsp.lumps[kVisibilityLump][1];
    bsp.leaves.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t at = base + k * layout.leaf;
        BspLeaf& leaf = bsp.leaves[k];
        leaf.contents = i32(bsp.bytes, at);
        leaf.visofs = i32(bsp.bytes, at + 4);
        if (leaf.visofs < -1 || (leaf.visofs >= 0 && std::uint32_t(leaf.visofs) >= visBytes))
            throw Error(what + ": leaf " + std::to_string(k) + "'s visofs " + std::to_string(leaf.visofs) +
                        " lies outside the " + std::to_string(visBytes) + "-byte visibility lump");
    }
    if (n == 0)
        throw Error(what + ": no leaves (a level has at least the shared solid leaf)");
}

void readWorldModel(QuakeBsp& bsp, const std::string& what)
{
    if (records(bsp, kModelLump, kModelBytes, "models", what) == 0)
        throw Error(what + ": no models (model 0 is the world)");
    const std::size_t at = bsp.lumps[kModelLump][0];
    for (int a = 0; a < 3; ++a) {
        bsp.mins[a] = f32(bsp.bytes, at + 4 * std::size_t(a));
        bsp.maxs[a] = f32(bsp.bytes, at + 12 + 4 * std::size_t(a));
        if (!std::isfinite(bsp.mins[a]) || !std::isfinite(bsp.maxs[a]) || bsp.mins[a] > bsp.maxs[a])
            throw Error(what + ": the world model's bounds are not finite and ordered");
        if (std::abs(bsp.mins[a]) > kMaxBspCoordinate || std::abs(bsp.maxs[a]) > kMaxBspCoordinate)
            throw Error(what + ": the world model's bounds reach beyond " + std::to_string(int(kMaxBspCoordinate)) +
                        " units (Quake levels fit in +-32768)");
    }
    bsp.headnode = i32(bsp.bytes, at + 36);
    bsp.visleafs = i32(bsp.bytes, at + 52);
    if (bsp.headnode < 0 || std::size_t(bsp.headnode) >= bsp.nodes.size())
        throw Error(what + ": the world model's head node " + std::to_string(bsp.headnode) + " is not one of the " +
                    std::to_string(bsp.nodes.size()) + " nodes");
    if (bsp.visleafs < 0 || std::size_t(bsp.visleafs) >= bsp.leaves.size())
        throw Error(what + ": the world model's visleafs " + std::to_string(bsp.visleafs) + " is beyond its " +
                    std::to_string(bsp.leaves.size()) + " leaves (leaf 0 is the solid leaf)");
}

/// Every node and leaf the world tree reaches, once: children in range and no node reached twice,
/// so every walk of the tree ends (a hostile file could otherwise loop forever).
void checkWorldTree(const QuakeBsp& bsp, const std::string& what)
{
    std::vector<char> seen(bsp.nodes.size(), 0);
    std::vector<int> todo{bsp.headnode};
    while (!todo.empty()) {
        const int n = todo.back();
        todo.pop_back();
        if (seen[std::size_t(n)])
            throw Error(what + ": node " + std::to_string(n) + " is reached twice from the world's head node (not a tree)");
        seen[std::size_t(n)] = 1;
        for (int child : bsp.nodes[std::size_t(n)].children) {
            if (child >= 0) {
                if (std::size_t(child) >= bsp.nodes.size())
                    throw Error(what + ": node " + std::to_string(n) + "'s child " + std::to_string(child) +
                                " is not one of the " + std::to_string(bsp.nodes.size()) + " nodes");
                todo.push_back(child);
            } else if (std::size_t(QuakeBsp::leafOfChild(child)) >= bsp.leaves.size()) {
                throw Error(what + ": node " + std::to_string(n) + "'s child leaf " +
                            std::to_string(QuakeBsp::leafOfChild(child)) + " is not one of the " +
                            std::to_string(bsp.leaves.size()) + " leaves");
            }
        }
    }
}

} // namespace

QuakeBsp readQuakeBsp(std::string bytes, const std::string& what)
{
    QuakeBsp bsp;
    bsp.bytes = std::move(bytes);
    readLumps(bsp, what);
    const Layout& layout = wideRecords(bsp.format) ? kBsp2 : kBsp29;
    readPlanes(bsp, what);
    readNodes(bsp, layout, what);
    readLeaves(bsp, layout, what);
    readWorldModel(bsp, what);
    checkWorldTree(bsp, what);
    return bsp;
}

pvs::VisibilityRows levelVisibility(const QuakeBsp& bsp, const std::string& what)
{
    const std::size_t n = std::size_t(bsp.visleafs);
    pvs::VisibilityRows rows(n, n);
    const std::string_view lump(bsp.bytes.data() + bsp.lumps[kVisibilityLump][0], bsp.lumps[kVisibilityLump][1]);
    for (std::size_t l = 0; l < n; ++l) {
        const int visofs = bsp.leaves[l + 1].visofs;
        if (visofs < 0 || lump.empty()) {
            for (std::size_t m = 0; m < n; ++m)
                rows.set(l, m, true);
            continue;
        }
        std::vector<std::uint8_t> row;
        try {
            row = pvs::decompressZeroRuns(lump, std::size_t(visofs), rows.rowBytes());
        } catch (const Error& e) {
            throw Error(what + ": leaf " + std::to_string(l + 1) + "'s visibility row: " + e.what());
        }
        std::copy(row.begin(), row.end(), rows.row(l));
        for (std::size_t bit = n; bit < rows.rowBytes() * 8; ++bit)
            rows.row(l)[bit / 8] &= std::uint8_t(~(1u << (bit % 8)));
    }
    return rows;
}

VisibilityLump encodeVisibilityLump(const pvs::VisibilityRows& rows)
{
    VisibilityLump out;
    std::unordered_map<std::string, std::int32_t> stored;
    for (std::size_t l = 0; l < rows.cellCount(); ++l) {
        const auto packed = pvs::compressZeroRuns(rows.row(l), rows.rowBytes());
        const auto [it, added] = stored.try_emplace(std::string(packed.begin(), packed.end()), std::int32_t(out.bytes.size()));
        if (added)
            out.bytes += it->first;
        out.rowOffsets.push_back(it->second);
    }
    return out;
}

std::string withVisibility(const QuakeBsp& bsp, const pvs::VisibilityRows& rows)
{
    if (rows.cellCount() != std::size_t(bsp.visleafs) || rows.objectCount() != std::size_t(bsp.visleafs))
        throw Error("visibility rows of " + std::to_string(rows.cellCount()) + " x " + std::to_string(rows.objectCount()) +
                    " leaves for a level of " + std::to_string(bsp.visleafs) + " visleafs");
    const VisibilityLump vis = encodeVisibilityLump(rows);
    const Layout& layout = wideRecords(bsp.format) ? kBsp2 : kBsp29;

    std::string leaves = bsp.bytes.substr(bsp.lumps[kLeafLump][0], bsp.lumps[kLeafLump][1]);
    for (std::size_t k = 0; k < bsp.leaves.size(); ++k) {
        const bool hasRow = k >= 1 && k <= std::size_t(bsp.visleafs);
        put32(leaves, k * layout.leaf + 4, std::uint32_t(hasRow ? vis.rowOffsets[k - 1] : -1));
    }

    const std::size_t header = 4 + 8 * kLumpCount;
    std::string out = bsp.bytes.substr(0, 4);
    out.resize(header, '\0');
    for (int k = 0; k < kLumpCount; ++k) {
        const std::string_view data = k == kVisibilityLump ? std::string_view(vis.bytes)
                                      : k == kLeafLump     ? std::string_view(leaves)
                                                           : std::string_view(bsp.bytes).substr(bsp.lumps[std::size_t(k)][0],
                                                                                                bsp.lumps[std::size_t(k)][1]);
        out.resize((out.size() + 3) & ~std::size_t(3), '\0');
        put32(out, 4 + 8 * std::size_t(k), std::uint32_t(out.size()));
        put32(out, 8 + 8 * std::size_t(k), std::uint32_t(data.size()));
        out.append(data);
    }
    return out;
}

namespace {

/// Texture names by texinfo: the texinfo's miptex index into the texture lump's directory.
std::vector<std::string> texinfoNames(const QuakeBsp& bsp, const std::string& what)
{
    constexpr std::size_t kTexinfoBytes = 40;
    const std::size_t count = records(bsp, kTexinfoLump, kTexinfoBytes, "texinfo", what);
    const auto [texOffset, texLength] = bsp.lumps[kTextureLump];
    std::size_t mipCount = 0;
    if (texLength >= 4) {
        const std::int32_t declared = i32(bsp.bytes, texOffset);
        if (declared < 0 || std::size_t(declared) > (texLength - 4) / 4)
            throw Error(what + ": the texture lump's " + std::to_string(declared) + " textures do not fit its " +
                        std::to_string(texLength) + " bytes");
        mipCount = std::size_t(declared);
    }
    std::vector<std::string> names(count);
    for (std::size_t k = 0; k < count; ++k) {
        const std::int32_t miptex = i32(bsp.bytes, bsp.lumps[kTexinfoLump][0] + k * kTexinfoBytes + 32);
        if (miptex < 0 || std::size_t(miptex) >= mipCount)
            continue;   // no texture data (compilers may strip it): a face without a name
        const std::int32_t at = i32(bsp.bytes, texOffset + 4 + 4 * std::size_t(miptex));
        if (at < 0 || std::size_t(at) + 16 > texLength)
            continue;   // -1 marks a texture missing from the file
        const char* name = bsp.bytes.data() + texOffset + std::size_t(at);
        names[k] = std::string(name, strnlen(name, 16));
    }
    return names;
}

} // namespace

std::vector<BspFace> worldFaces(const QuakeBsp& bsp, const std::string& what)
{
    const bool wide = wideRecords(bsp.format);
    const std::size_t faceBytes = wide ? 28 : 20, edgeBytes = wide ? 8 : 4;
    const std::size_t faces = records(bsp, kFaceLump, faceBytes, "faces", what);
    const std::size_t vertices = records(bsp, kVertexLump, 12, "vertices", what);
    const std::size_t edges = records(bsp, kEdgeLump, edgeBytes, "edges", what);
    const std::size_t surfedges = records(bsp, kSurfedgeLump, 4, "surfedges", what);
    const std::vector<std::string> names = texinfoNames(bsp, what);
    const std::size_t model = bsp.lumps[kModelLump][0];
    const std::int32_t first = i32(bsp.bytes, model + 56), count = i32(bsp.bytes, model + 60);
    if (first < 0 || count < 0 || std::size_t(first) > faces || std::size_t(count) > faces - std::size_t(first))
        throw Error(what + ": the world model's faces " + std::to_string(first) + "+" + std::to_string(count) +
                    " are not among the " + std::to_string(faces) + " faces");
    const std::string& b = bsp.bytes;
    auto vertex = [&](std::size_t v, std::size_t face) {
        if (v >= vertices)
            throw Error(what + ": face " + std::to_string(face) + " names vertex " + std::to_string(v) + " of " +
                        std::to_string(vertices));
        const std::size_t at = bsp.lumps[kVertexLump][0] + 12 * v;
        const glm::dvec3 p(f32(b, at), f32(b, at + 4), f32(b, at + 8));
        for (int a = 0; a < 3; ++a)
            if (!std::isfinite(p[a]) || std::abs(p[a]) > kMaxBspCoordinate)
                throw Error(what + ": vertex " + std::to_string(v) + " is not finite or lies beyond " +
                            std::to_string(int(kMaxBspCoordinate)) + " units");
        return p;
    };
    std::vector<BspFace> out;
    out.reserve(std::size_t(count));
    for (std::size_t f = std::size_t(first); f < std::size_t(first) + std::size_t(count); ++f) {
        const std::size_t at = bsp.lumps[kFaceLump][0] + f * faceBytes;
        const std::int64_t firstEdge = i32(b, at + (wide ? 8 : 4));
        const std::int64_t edgeCount = wide ? i32(b, at + 12) : i16(b, at + 8);
        const std::int64_t texinfo = wide ? i32(b, at + 16) : i16(b, at + 10);
        if (edgeCount < 3 || edgeCount > kMaxFaceEdges || firstEdge < 0 || std::uint64_t(firstEdge + edgeCount) > surfedges)
            throw Error(what + ": face " + std::to_string(f) + "'s " + std::to_string(edgeCount) + " edges from surfedge " +
                        std::to_string(firstEdge) + " are not 3 to " + std::to_string(kMaxFaceEdges) + " of the " +
                        std::to_string(surfedges) + " surfedges");
        BspFace face;
        if (texinfo >= 0 && std::size_t(texinfo) < names.size())
            face.texture = names[std::size_t(texinfo)];
        for (std::int64_t e = firstEdge; e < firstEdge + edgeCount; ++e) {
            const std::int32_t surfedge = i32(b, bsp.lumps[kSurfedgeLump][0] + 4 * std::size_t(e));
            const std::uint64_t edge = surfedge < 0 ? std::uint64_t(-std::int64_t(surfedge)) : std::uint64_t(surfedge);
            if (edge >= edges)
                throw Error(what + ": face " + std::to_string(f) + " names edge " + std::to_string(edge) + " of " +
                            std::to_string(edges));
            const std::size_t edgeAt = bsp.lumps[kEdgeLump][0] + edgeBytes * edge + (surfedge < 0 ? edgeBytes / 2 : 0);
            const std::size_t v = wide ? std::size_t(u32(b, edgeAt)) : std::size_t(std::uint16_t(i16(b, edgeAt)));
            face.polygon.push_back(vertex(v, f));
        }
        out.push_back(std::move(face));
    }
    return out;
}

int leafAt(const QuakeBsp& bsp, const glm::dvec3& p)
{
    int n = bsp.headnode;
    while (n >= 0) {
        const BspNode& node = bsp.nodes[std::size_t(n)];
        n = node.children[bsp.planes[std::size_t(node.plane)].side(p) > 0.0 ? 0 : 1];
    }
    return QuakeBsp::leafOfChild(n);
}

} // namespace sightline::bsp
