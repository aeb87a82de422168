// Regression corpus for hostile or broken glTF/GLB files: each category of bad input is
// refused with one line naming the file and what is wrong, never a crash, a hang, runaway memory or
// geometry that silently vanishes; and the legal extremes next to each refusal still load.

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "GltfTestDoc.h"
#include "TestFiles.h"
#include "plugins/SceneFormats.h"
#include "base/InputFile.h"
#include "base/JsonDepth.h"
#include "visibility/SceneLimits.h"

using namespace sightline;
using namespace sightline::test;
using nlohmann::json;

namespace {

/// Expects loadScene(file) to fail with one line naming the file and containing every word.
void expectRefused(const std::filesystem::path& file, std::initializer_list<const char*> words)
{
    const std::string message = expectOneLineError(file, [&] { loadScene(file); });
    for (const char* word : words)
        EXPECT_NE(message.find(word), std::string::npos) << "'" << word << "' missing from: " << message;
}

/// A chain of `depth` nodes, each the only child of the one before, the last placing the triangle.
GltfDoc chain(std::size_t depth)
{
    GltfDoc g = triangleDoc();
    json nodes = json::array();
    for (std::size_t i = 0; i < depth; ++i) {
        json node = {{"translation", {0.001, 0, 0}}};
        if (i + 1 < depth)
            node["children"] = {i + 1};
        else
            node["mesh"] = 0;
        nodes.push_back(node);
    }
    g.scene(nodes, {0});
    return g;
}

std::string nested(std::size_t depth, char open, char close)
{
    return std::string(depth, open) + std::string(depth, close);
}

TEST(BadGltf, DeepNodeChainLoadsWithoutRecursion)
{
    // Far deeper than a recursive walk survives: the hierarchy is walked with an explicit stack.
    TempDir dir;
    GltfDoc g = chain(20'000);
    const auto file = g.writeEmbedded(dir / "chain.gltf");
    const Scene scene = loadScene(file);
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_NEAR(scene.instances[0].transform[3][0], 20'000 * 0.001, 1e-3); // every level's transform applied

    // The CLI's traversal of the same file (its `info` lists every instance).
    if (!std::filesystem::exists(SIGHTLINE_CLI))
        GTEST_SKIP() << "sightline-cli not built at " << SIGHTLINE_CLI;
    const std::string command = std::string(SIGHTLINE_CLI) + " info " + file.string() + " >/dev/null 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
}

TEST(BadGltf, NodeGraphMustBeDisjointStrictTrees)
{
    TempDir dir;
    auto write = [&](const char* name, json nodes, json roots) {
        GltfDoc g = triangleDoc();
        g.scene(std::move(nodes), std::move(roots));
        return g.writeEmbedded(dir / name);
    };
    // Each node lists the next twice: 2^40 paths to the last node, counted or expanded, never both.
    json doubling = json::array();
    for (int i = 0; i < 40; ++i)
        doubling.push_back({{"children", {i + 1, i + 1}}});
    doubling.push_back({{"mesh", 0}});
    expectRefused(write("doubling.gltf", doubling, {0}), {"node 0", "child 1 twice"});

    expectRefused(write("twoparents.gltf", {{{"children", {1, 2}}}, {{"children", {3}}}, {{"children", {3}}}, {{"mesh", 0}}}, {0}),
                  {"node 3", "child of both node 1 and node 2", "strict trees"});
    expectRefused(write("self.gltf", {{{"mesh", 0}, {"children", {0}}}}, {0}), {"node 0", "itself"});
    // A cycle no scene root reaches: the old walk never saw it and dropped its meshes in silence.
    expectRefused(write("cycle.gltf", {{{"mesh", 0}}, {{"mesh", 0}, {"children", {2}}}, {{"children", {1}}}}, {0}),
                  {"own ancestor", "cycle"});
    expectRefused(write("childroot.gltf", {{{"children", {1}}}, {{"mesh", 0}}}, {0, 1}),
                  {"scene 0", "node 1", "child of node 0", "root nodes"});
    expectRefused(write("tworoots.gltf", {{{"mesh", 0}}}, {0, 0}), {"scene 0", "root node 0 twice"});
}

TEST(BadGltf, SharedMeshWithinLimitsLoads)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    json nodes = json::array();
    json roots = json::array();
    for (int i = 0; i < 2'000; ++i) {
        nodes.push_back({{"mesh", 0}, {"translation", {i, 0, 0}}});
        roots.push_back(i);
    }
    g.scene(nodes, roots);
    const Scene scene = loadScene(g.writeEmbedded(dir / "shared.gltf"));
    EXPECT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.instances.size(), 2'000u);
    EXPECT_EQ(scene.triangleCount(), 2'000u);
}

TEST(BadGltf, InstancesPastTheLimitAreRefusedBeforeExpanding)
{
    // One root whose children are a million more nodes, every one placing the triangle. The node
    // list is written as text: a DOM of a million nodes would cost the test more than the importer.
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["nodes"] = json::array();
    g.writeEmbedded(dir / "unused.gltf"); // fills in the buffer
    std::string children, leaves;
    for (std::uint64_t i = 1; i <= kMaxSceneInstances; ++i) {
        if (i > 1)
            children += ',';
        children += std::to_string(i);
        leaves += ",{\"mesh\":0}";
    }
    std::string text = g.doc.dump();
    const std::string empty = "\"nodes\":[]";
    text.replace(text.find(empty), empty.size(), "\"nodes\":[{\"mesh\":0,\"children\":[" + children + "]}" + leaves + "]");
    expectRefused(writeFile(dir / "many.gltf", text), {"1000001 mesh instances", "limit of 1000000"});
}

TEST(BadGltf, TrianglesPastTheLimitAreRefusedBeforeExpanding)
{
    // One mesh of a million (degenerate) triangles, non-indexed, from a sparse POSITION accessor
    // without a bufferView (zeros but one), placed 51 times: 51M triangles from a few kilobytes.
    TempDir dir;
    GltfDoc g;
    const int index = g.view(bytesOf(std::vector<std::uint8_t>{1}));
    const int value = g.view(bytesOf(std::vector<float>{1, 0, 0}));
    const int pos = g.accessor({{"componentType", kF32}, {"count", 3'000'000}, {"type", "VEC3"},
                                {"sparse", {{"count", 1}, {"indices", {{"bufferView", index}, {"componentType", kU8}}},
                                            {"values", {{"bufferView", value}}}}}});
    g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}}}));
    json nodes = json::array();
    json roots = json::array();
    for (int i = 0; i < 51; ++i) {
        nodes.push_back({{"mesh", 0}});
        roots.push_back(i);
    }
    g.scene(nodes, roots);
    expectRefused(g.writeEmbedded(dir / "heavy.gltf"), {"51000000 triangles", "limit of 50000000"});
}

TEST(BadGltf, IndicesMustBeNonNegativeIntegersInRange)
{
    // tinygltf converts each of these to "absent" or to a wrapped int; the geometry vanished.
    struct Case {
        const char* name;
        json::json_pointer field;
        json value;
        std::initializer_list<const char*> words;
    };
    const std::vector<Case> cases = {
        {"mesh_fraction", json::json_pointer("/nodes/0/mesh"), 3.5, {"node 0 'mesh'", "3.5", "not a non-negative integer"}},
        {"mesh_huge", json::json_pointer("/nodes/0/mesh"), 1e308, {"node 0 'mesh'", "not a non-negative integer"}},
        {"mesh_u32", json::json_pointer("/nodes/0/mesh"), 4294967295u, {"node 0 'mesh'", "4294967295"}},
        {"mesh_negative", json::json_pointer("/nodes/0/mesh"), -1, {"node 0 'mesh'", "-1"}},
        {"mesh_string", json::json_pointer("/nodes/0/mesh"), "0", {"node 0 'mesh'", "not a non-negative integer"}},
        {"mesh_range", json::json_pointer("/nodes/0/mesh"), 7, {"node 0 'mesh'", "names mesh 7", "has 1 meshes"}},
        {"child_fraction", json::json_pointer("/nodes/0/children"), json::array({0.5}), {"node 0 'children' entry 0"}},
        {"root_fraction", json::json_pointer("/scenes/0/nodes"), json::array({0.5}), {"scene 0 'nodes' entry 0"}},
        {"root_range", json::json_pointer("/scenes/0/nodes"), json::array({3}), {"scene 0 'nodes' entry 0", "names node 3"}},
        {"scene_fraction", json::json_pointer("/scene"), 0.5, {"'scene'", "not a non-negative integer"}},
        {"position_fraction", json::json_pointer("/meshes/0/primitives/0/attributes/POSITION"), 0.5,
         {"mesh 0 primitive 0 attribute 'POSITION'"}},
        {"indices_range", json::json_pointer("/meshes/0/primitives/0/indices"), 9, {"'indices'", "names accessor 9"}},
        {"view_fraction", json::json_pointer("/accessors/0/bufferView"), 0.5, {"accessor 0 'bufferView'"}},
        {"view_range", json::json_pointer("/accessors/0/bufferView"), 5, {"accessor 0 'bufferView'", "names bufferView 5"}},
        {"count_negative", json::json_pointer("/accessors/0/count"), -3, {"accessor 0 'count'"}},
        {"buffer_fraction", json::json_pointer("/bufferViews/0/buffer"), 0.5, {"bufferView 0 'buffer'"}},
        {"buffer_range", json::json_pointer("/bufferViews/0/buffer"), 1, {"bufferView 0 'buffer'", "names buffer 1"}},
        {"offset_fraction", json::json_pointer("/bufferViews/0/byteOffset"), 0.5, {"bufferView 0 'byteOffset'"}},
        {"nodes_object", json::json_pointer("/nodes"), json::object(), {"'nodes'", "not an array"}},
    };
    TempDir dir;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        GltfDoc g = triangleDoc();
        g.doc["nodes"][0]["children"] = json::array();
        g.writeEmbedded(dir / "unused.gltf"); // fills in the buffer before the field is spoiled
        g.doc[c.field] = c.value;
        expectRefused(writeFile(dir / (std::string(c.name) + ".gltf"), g.doc.dump()), c.words);
    }
}

TEST(BadGltf, MisalignedAccessorsAreRefused)
{
    TempDir dir;
    const std::vector<float> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0};
    auto write = [&](const char* name, std::size_t padding, int viewOffset, int accessorOffset, int stride) {
        GltfDoc g;
        const int view = g.view(std::string(padding, '\0') + bytesOf(xyz), stride);
        g.doc["bufferViews"][view]["byteOffset"] = viewOffset;
        g.doc["bufferViews"][view]["byteLength"] = 12 * 3 + 2;
        const int pos = g.accessor({{"bufferView", view}, {"byteOffset", accessorOffset}, {"componentType", kF32},
                                    {"count", 3}, {"type", "VEC3"}});
        g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}}}));
        g.scene(json::array({{{"mesh", 0}}}), {0});
        return g.writeEmbedded(dir / name);
    };
    expectRefused(write("accessor_offset.gltf", 2, 0, 2, 0), {"accessor 0", "byteOffset 2", "component size (4 bytes)"});
    expectRefused(write("view_offset.gltf", 1, 1, 0, 0), {"accessor 0", "starts at byte 1", "bufferView 0 byteOffset 1"});
    expectRefused(write("stride.gltf", 0, 0, 0, 13), {"byteStride", "13"}); // tinygltf's own check
    // Ranges: an accessor past its view, a view past its buffer.
    expectRefused(write("overrun.gltf", 0, 0, 4, 0), {"accessor 0", "overruns bufferView 0"});
    GltfDoc g = triangleDoc();
    g.doc["bufferViews"][0]["byteLength"] = 4096;
    expectRefused(g.writeEmbedded(dir / "view_overrun.gltf"), {"bufferView 0", "overruns buffer 0"});
}

// An accessor with no bufferView is zeros the file does not hold: its count alone sized the
// allocation (2^28 positions: about 3 GB from a file of a few hundred bytes).
TEST(BadGltf, AccessorsWithoutDataInTheFileAreBounded)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["accessors"].push_back({{"componentType", kF32}, {"count", 1 << 28}, {"type", "VEC3"}});
    g.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = g.doc["accessors"].size() - 1;
    expectRefused(g.writeEmbedded(dir / "unbacked.gltf"), {"no bufferView", "268435456", "4194304"});
}

// Each primitive copies its whole POSITION accessor: 20 primitives sharing one 4M-vertex accessor
// (no bytes in the file) counted as 20 triangles and one instance, and took gigabytes.
TEST(BadGltf, VerticesCopiedPerPrimitiveAreCountedBeforeConverting)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["accessors"].push_back({{"componentType", kF32}, {"count", 1 << 22}, {"type", "VEC3"}});
    const auto positions = g.doc["accessors"].size() - 1;
    const json indices = g.doc["meshes"][0]["primitives"][0]["indices"];   // the triangle's 3
    json primitives = json::array();
    for (int k = 0; k < 20; ++k)
        primitives.push_back({{"attributes", {{"POSITION", positions}}}, {"indices", indices}});
    g.doc["meshes"][0]["primitives"] = primitives;
    expectRefused(g.writeEmbedded(dir / "shared_positions.gltf"), {"vertices in all", "limit of 50000000"});
}

TEST(BadGltf, DeepJsonIsRefusedBeforeParsing)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.writeEmbedded(dir / "plain.gltf"); // fills in the buffer
    std::string text = g.doc.dump();
    text.insert(text.rfind('}'), ",\"extras\":" + nested(20'000, '[', ']'));
    expectRefused(writeFile(dir / "extras.gltf", text), {"nested deeper than 512", "at byte"});
    expectRefused(writeFile(dir / "array.gltf", nested(1'000'000, '[', ']')), {"nested deeper than 512"});
    // Brackets in strings do not count, escaped quotes included; a legal depth still loads.
    GltfDoc ok = triangleDoc();
    ok.doc["extras"] = {{"text", std::string(5'000, '[') + "\\\"" + std::string(5'000, '{')}};
    json deep = 1;
    for (std::size_t i = 1; i < kMaxJsonDepth - 4; ++i)
        deep = json::array({deep});
    ok.doc["extras"]["deep"] = deep;
    EXPECT_EQ(loadScene(ok.writeEmbedded(dir / "strings.gltf")).instances.size(), 1u);

    // The GLB's JSON chunk is scanned too.
    GltfDoc b = triangleDoc();
    b.doc["extras"] = json::parse(nested(600, '[', ']'));
    // json::parse would itself recurse at 20k; 600 is past the limit and safe to build here.
    expectRefused(b.writeGlb(dir / "deep.glb"), {"nested deeper than 512"});
}

TEST(BadGltf, NumberOverflowNamesFileAndByte)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.writeEmbedded(dir / "plain.gltf"); // fills in the buffer
    std::string text = g.doc.dump();
    text.insert(text.rfind('}'), ",\"extras\":1e400");
    expectRefused(writeFile(dir / "overflow.gltf", text), {"invalid JSON", "1e400", "at byte"});
}

std::string u32(std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }

TEST(BadGltf, GlbContainerIsCheckedWhole)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    const std::string good = readInputFile(g.writeGlb(dir / "good.glb"), "test");
    // The header's total length must be the file's size, longer or shorter.
    std::string longer = good + std::string(8, '\0');
    expectRefused(writeFile(dir / "trailing.glb", longer), {"GLB header gives a length of", "the file has"});
    std::string shorter = good;
    shorter.replace(8, 4, u32(static_cast<std::uint32_t>(good.size() + 100)));
    expectRefused(writeFile(dir / "short.glb", shorter), {"GLB header gives a length of"});
    // A chunk that claims more bytes than the file holds.
    std::string chunk = good;
    chunk.replace(12, 4, u32(0x7fffffffu));
    expectRefused(writeFile(dir / "chunk.glb", chunk), {"GLB chunk 0", "past the end of the file"});
    std::string notJson = good;
    notJson.replace(16, 4, std::string("BIN\0", 4));
    expectRefused(writeFile(dir / "first.glb", notJson), {"first GLB chunk is not JSON"});
    expectRefused(writeFile(dir / "nomagic.glb", "{\"asset\":{\"version\":\"2.0\"}}"), {"not a GLB file"});
}

TEST(BadGltf, HugeSparseFilesAreRefusedBeforeReading)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    const auto glb = g.writeGlb(dir / "huge.glb");
    std::filesystem::resize_file(glb, std::uintmax_t(2) << 30); // sparse: no disk used
    expectRefused(glb, {"2048 MB", "more than the limit"});

    GltfDoc e = triangleDoc();
    const auto gltf = e.writeExternal(dir / "external.gltf", "huge.bin");
    std::filesystem::resize_file(dir / "huge.bin", std::uintmax_t(2) << 30);
    expectRefused(gltf, {"huge.bin", "more than the limit"});
}

TEST(BadGltf, CoordinatesPastTheRangeNameTheFile)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["nodes"][0]["scale"] = {1e11, 1, 1};
    expectRefused(g.writeEmbedded(dir / "scaled.gltf"), {"coordinates up to"});
}

// glTF requires node matrices decomposable to TRS; a projective last row was dropped without a
// word (another shape than the file's), so it is refused. The affine matrix next to it loads.
TEST(BadGltf, NodeMatricesMustBeAffine)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["nodes"][0]["matrix"] = {1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    expectRefused(g.writeEmbedded(dir / "projective.gltf"), {"matrix must be affine"});
    g.doc["nodes"][0]["matrix"] = {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 3, 0, 0, 1};
    EXPECT_NO_THROW(loadScene(g.writeEmbedded(dir / "affine.gltf")));
}

} // namespace
