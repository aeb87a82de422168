// glTF importer on small files the tests write: index types and primitive modes, strides, sparse
// accessors, data URIs, GLB containers, scene selection and instancing, and every refusal (buffer
// URIs escaping the folder, required extensions, overruns, bad indices, NaN, malformed input).

#include <algorithm>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "GltfTestDoc.h"
#include "TestImages.h"
#include "TextureMean.h"
#include "TestFiles.h"
#include "plugins/SceneFormats.h"

using namespace sightline;
using nlohmann::json;
using sightline::test::expectOneLineError;
using sightline::test::TempDir;
using sightline::test::writeFile;
using namespace sightline::test; // GltfDoc, triangleDoc, bytesOf, component types

namespace {

std::vector<glm::vec3> world(const Scene& scene) { return worldTriangles(scene).vertices; }

TEST(GltfImporter, EmbeddedExternalAndGlbAgree)
{
    TempDir dir;
    const std::vector<glm::vec3> expected = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    GltfDoc a = triangleDoc(), b = triangleDoc(), c = triangleDoc();
    EXPECT_EQ(world(loadScene(a.writeEmbedded(dir / "embedded.gltf"))), expected);
    EXPECT_EQ(world(loadScene(b.writeExternal(dir / "external.gltf", "external.bin"))), expected);
    EXPECT_EQ(world(loadScene(c.writeGlb(dir / "binary.glb"))), expected);
}

TEST(GltfImporter, DefaultNamesAndNoNormals)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    const Scene scene = loadScene(g.writeEmbedded(dir / "names.gltf"));
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.meshes[0].name, "mesh 0");
    EXPECT_EQ(scene.instances.at(0).name, "node 0");
    EXPECT_TRUE(scene.meshes[0].normals.empty());
}

TEST(GltfImporter, U8StripAndU32Fan)
{
    TempDir dir;
    GltfDoc g;
    // A unit quad as a strip (u8 indices) and, shifted by x+2, as a non-indexed fan.
    const int quad = g.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    const int strip = g.indices(std::vector<std::uint8_t>{0, 1, 2, 3}, kU8);
    const int fanPos = g.positions({2, 0, 0, 3, 0, 0, 3, 1, 0, 2, 1, 0});
    const int fanIdx = g.indices(std::vector<std::uint32_t>{0, 1, 2, 3}, kU32);
    g.mesh(json::array({{{"attributes", {{"POSITION", quad}}}, {"indices", strip}, {"mode", 5}},
                        {{"attributes", {{"POSITION", fanPos}}}, {"indices", fanIdx}, {"mode", 6}},
                        {{"attributes", {{"POSITION", quad}}}, {"mode", 1}}})); // lines: ignored
    g.scene(json::array({{{"mesh", 0}}}), {0});
    std::vector<std::string> warnings;
    const Scene scene = loadScene(g.writeEmbedded(dir / "modes.gltf"), &warnings);
    EXPECT_EQ(scene.triangleCount(), 4u);
    EXPECT_EQ(warnings.size(), 1u); // the LINES primitive
    // Strip: (0,1,2), (1,3,2) (odd triangles swap to keep the winding); fan: (1,2,0), (2,3,0).
    const std::vector<glm::vec3> expected = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                             {3, 0, 0}, {3, 1, 0}, {2, 0, 0}, {3, 1, 0}, {2, 1, 0}, {2, 0, 0}};
    EXPECT_EQ(world(scene), expected);
}

TEST(GltfImporter, MaterialsGiveEachTriangleItsBaseColourAsAlbedo)
{
    TempDir dir;
    GltfDoc g;
    const int quad = g.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    const int strip = g.indices(std::vector<std::uint8_t>{0, 1, 2, 3}, kU8);
    // Mesh 0: a red strip (two triangles), then a fan without a material (glTF's default: white).
    g.mesh(json::array({{{"attributes", {{"POSITION", quad}}}, {"indices", strip}, {"mode", 5}, {"material", 0}},
                        {{"attributes", {{"POSITION", quad}}}, {"mode", 6}}}));
    // Mesh 1: no material anywhere: no albedos (the run's own applies).
    g.mesh(json::array({{{"attributes", {{"POSITION", quad}}}, {"mode", 6}}}));
    // Mesh 2: a textured material: its colour is unknown (textures are not decoded).
    g.mesh(json::array({{{"attributes", {{"POSITION", quad}}}, {"mode", 6}, {"material", 1}}}));
    g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.1, 0.05, 0.5}}}}},
                                      {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    g.doc["textures"] = json::array({{{"source", 0}}});
    g.doc["images"] = json::array({{{"uri", "albedo.png"}}});
    g.scene(json::array({{{"mesh", 0}}, {{"mesh", 1}}, {{"mesh", 2}}}), {0, 1, 2});
    const Scene scene = loadScene(g.writeEmbedded(dir / "materials.gltf"));
    ASSERT_EQ(scene.meshes.size(), 3u);
    const std::vector<glm::vec3> expected = {{0.8f, 0.1f, 0.05f}, {0.8f, 0.1f, 0.05f}, {1.0f, 1.0f, 1.0f}, {1.0f, 1.0f, 1.0f}};
    EXPECT_EQ(scene.meshes[0].albedo, expected);
    EXPECT_TRUE(scene.meshes[1].albedo.empty());
    EXPECT_EQ(scene.meshes[2].albedo, std::vector<glm::vec3>(2, kUnknownAlbedo));

    // A base colour outside [0, 1] is refused in one line, naming the material.
    g.doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1.5, 0, 0, 1};
    const auto bad = g.writeEmbedded(dir / "bright.gltf");
    EXPECT_NE(expectOneLineError(bad, [&] { loadScene(bad); }).find("material 0's baseColorFactor"), std::string::npos);
}

float linear(int srgb) { return texture::srgbToLinear(float(srgb) / 255.0f); }

/// A 2 x 2 texture (top row red, green; bottom row blue, sRGB 188 grey) and one quad per call,
/// textured with the coordinates given; the document keeps the texture's PNG in its buffer.
struct TexturedQuads {
    GltfDoc g;
    int quad = 0, strip = 0;
    json primitives = json::array();

    TexturedQuads()
    {
        quad = g.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
        strip = g.indices(std::vector<std::uint8_t>{0, 1, 2, 3}, kU8);
        const std::string png = fourColourPng();
        g.doc["images"] = json::array({{{"bufferView", g.view(png)}, {"mimeType", "image/png"}}});
        g.doc["samplers"] = json::array({{{"wrapS", 33071}, {"wrapT", 33071}}, {{"wrapS", 33648}, {"wrapT", 33648}}, json::object()});
        // Texture k uses sampler k: clamp, mirror, repeat.
        g.doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}, {{"source", 0}, {"sampler", 1}}, {{"source", 0}, {"sampler", 2}}});
        g.doc["materials"] = json::array();
    }
    /// A strip quad whose four vertices take `uv`, in a material of texture `texture` x `factor`.
    void add(const std::vector<float>& uv, int texture, json factor = {1.0, 1.0, 1.0, 1.0})
    {
        const int coords = g.accessor({{"bufferView", g.view(bytesOf(uv))}, {"componentType", kF32}, {"count", 4}, {"type", "VEC2"}});
        g.doc["materials"].push_back({{"pbrMetallicRoughness", {{"baseColorFactor", factor}, {"baseColorTexture", {{"index", texture}}}}}});
        primitives.push_back({{"attributes", {{"POSITION", quad}, {"TEXCOORD_0", coords}}}, {"indices", strip}, {"mode", 5},
                              {"material", g.doc["materials"].size() - 1}});
    }
    Scene load(const std::filesystem::path& file, std::vector<std::string>* warnings = nullptr)
    {
        g.mesh(primitives);
        g.scene(json::array({{{"mesh", 0}}}), {0});
        return loadScene(g.writeGlb(file), warnings, {.textureAlbedos = true});
    }
};

/// The quad's four coordinates: a square of side `side` at (u, v).
std::vector<float> square(float u, float v, float side) { return {u, v, u + side, v, u, v + side, u + side, v + side}; }

TEST(GltfImporter, BaseColourTexturesGiveTheirMeanOverEachTriangle)
{
    TempDir dir;
    TexturedQuads t;
    // Clamped, inside each texel's outer quarter: that texel's colour alone, sRGB decoded, times the factor.
    t.add(square(0.0f, 0.0f, 0.25f), 0, {0.5, 1.0, 1.0, 1.0});   // top left: red
    t.add(square(0.75f, 0.0f, 0.25f), 0);                         // top right: green
    t.add(square(0.75f, 0.75f, 0.25f), 0);                        // bottom right: grey
    // Mirrored: [-0.25, 0] reflects onto [0, 0.25] (red); repeated: a speck at a texel's centre
    // three images over (blue).
    t.add(square(-0.25f, -0.25f, 0.25f), 1);
    t.add(square(3.25f, 5.75f, 1e-4f), 2);
    // The whole image, repeated twice: the quad's two halves average its mean (bilinear over whole
    // periods), within the sampling's error (a few samples a texel); repeated 64 times, each half
    // takes the mean itself (the chain's 1 x 1 level).
    t.add(square(0.0f, 0.0f, 2.0f), 2);
    t.add(square(0.5f, 0.25f, 64.0f), 2);
    // KHR_texture_transform: the unit square scaled to a quarter, turned a quarter turn (u' = v,
    // v' = -u) and moved onto the top-right texel's outer quarter (green; clamped). Turned the other
    // way it would straddle all four texels.
    t.add(square(0.0f, 0.0f, 1.0f), 0);
    t.g.doc["materials"].back()["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        {"KHR_texture_transform", {{"scale", {0.25, 0.25}}, {"rotation", std::acos(-1.0) / 2.0}, {"offset", {0.75, 0.25}}}}};
    const Scene scene = t.load(dir / "textured.glb");
    const std::vector<glm::vec3>& albedo = scene.meshes.at(0).albedo;
    ASSERT_EQ(albedo.size(), 16u);
    for (std::size_t k = 14; k < 16; ++k)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(albedo[k][c], c == 1 ? 1.0f : 0.0f, 1e-6) << "triangle " << k;
    const glm::vec3 expected[] = {{0.5f, 0, 0}, {0, 1, 0}, glm::vec3(linear(188)), {1, 0, 0}, {0, 0, 1}};
    for (std::size_t q = 0; q < 5; ++q)
        for (std::size_t k = 0; k < 2; ++k)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(albedo[2 * q + k][c], expected[q][c], q == 4 ? 1e-3 : 1e-6) << "quad " << q << " triangle " << k;
    EXPECT_NEAR(linear(188), 0.5f, 0.005f);   // sRGB 188 is linear one half
    const glm::vec3 mean = (glm::vec3(1, 0, 0) + glm::vec3(0, 1, 0) + glm::vec3(0, 0, 1) + glm::vec3(linear(188))) / 4.0f;
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(0.5f * (albedo[10][c] + albedo[11][c]), mean[c], 0.05);
        EXPECT_NEAR(albedo[12][c], mean[c], 1e-6);
        EXPECT_NEAR(albedo[13][c], mean[c], 1e-6);
    }
}

TEST(GltfImporter, TexturesAreReadOnlyWhereAskedFor)
{
    TempDir dir;
    TexturedQuads t;
    t.add(square(0.0f, 0.0f, 0.25f), 0);
    t.g.mesh(t.primitives);
    t.g.scene(json::array({{{"mesh", 0}}}), {0});
    const auto file = t.g.writeGlb(dir / "textured.glb");
    std::vector<std::string> warnings;
    EXPECT_EQ(loadScene(file, &warnings).meshes.at(0).albedo, std::vector<glm::vec3>(2, kUnknownAlbedo));
    EXPECT_TRUE(warnings.empty());
    EXPECT_EQ(loadScene(file, &warnings, {.textureAlbedos = true}).meshes.at(0).albedo, std::vector<glm::vec3>(2, glm::vec3(1, 0, 0)));
}

TEST(GltfImporter, TexturesThatCannotBeReadLeaveTheirAlbedoUnknownAndSaySo)
{
    TempDir dir;
    {   // A truncated image: a warning naming it; the file still loads.
        TexturedQuads t;
        const std::string png = pngBytes(2, 2, std::vector<unsigned char>(12, 200));
        t.g.doc["images"][0] = {{"bufferView", t.g.view(png.substr(0, png.size() - 20))}, {"mimeType", "image/png"}};
        t.add(square(0, 0, 1), 0);
        t.add(square(0, 0, 1), 0);
        std::vector<std::string> warnings;
        const Scene scene = t.load(dir / "truncated.glb", &warnings);
        EXPECT_EQ(scene.meshes.at(0).albedo, std::vector<glm::vec3>(4, kUnknownAlbedo));
        const auto image = std::count_if(warnings.begin(), warnings.end(), [](const std::string& w) { return w.find("image 0") != std::string::npos; });
        EXPECT_GE(image, 1);
        // One line a material, not one a primitive.
        const auto material0 = std::count_if(warnings.begin(), warnings.end(), [](const std::string& w) { return w.find("material 0's") != std::string::npos; });
        EXPECT_EQ(material0, 1);
    }
    {   // An image whose bufferView runs past its buffer: a warning naming it, never a read past the end.
        TexturedQuads t;
        t.add(square(0, 0, 1), 0);
        const int image = t.g.doc["images"][0]["bufferView"].get<int>();
        t.g.doc["bufferViews"][image]["byteLength"] = t.g.doc["bufferViews"][image]["byteLength"].get<int>() + 4096;
        std::vector<std::string> warnings;
        const Scene scene = t.load(dir / "overrun.glb", &warnings);
        EXPECT_EQ(scene.meshes.at(0).albedo, std::vector<glm::vec3>(2, kUnknownAlbedo));
        EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) { return w.find("overruns buffer") != std::string::npos; }));
    }
    {   // No TEXCOORD_0: a warning, unknown albedo; texture coordinates that are not finite, and a
        // texture transform that is not numbers, likewise.
        TexturedQuads t;
        t.add(square(0, 0, 1), 0);
        t.primitives[0]["attributes"].erase("TEXCOORD_0");
        t.add({0, 0, 1, 0, std::numeric_limits<float>::quiet_NaN(), 1, 1, 1}, 0);
        t.add(square(0, 0, 1), 0);
        t.g.doc["materials"].back()["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
            {"KHR_texture_transform", {{"scale", {1.0, "two"}}}}};
        std::vector<std::string> warnings;
        const Scene scene = t.load(dir / "nocoords.glb", &warnings);
        EXPECT_EQ(scene.meshes.at(0).albedo, std::vector<glm::vec3>(6, kUnknownAlbedo));
        EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) { return w.find("scale must be finite numbers") != std::string::npos; }));
        EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) { return w.find("no TEXCOORD_0") != std::string::npos; }));
        EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) { return w.find("not finite") != std::string::npos; }));
    }
    {   // A material naming a texture that is not there: refused in one line.
        TexturedQuads t;
        t.add(square(0, 0, 1), 7);
        const auto file = dir / "missing.glb";
        t.g.mesh(t.primitives);
        t.g.scene(json::array({{{"mesh", 0}}}), {0});
        t.g.writeGlb(file);
        EXPECT_NE(expectOneLineError(file, [&] { loadScene(file, nullptr, {.textureAlbedos = true}); }).find("names missing texture 7"), std::string::npos);
    }
}

TEST(GltfImporter, InterleavedStrideAndNormals)
{
    TempDir dir;
    GltfDoc g;
    // position xyz, normal xyz, one float of padding: stride 28.
    const std::vector<float> data = {0, 0, 0, 0, 0, 1, 9, 1, 0, 0, 0, 0, 1, 9, 0, 1, 0, 0, 0, 1, 9};
    const int v = g.view(bytesOf(data), 28);
    const int pos = g.accessor({{"bufferView", v}, {"componentType", kF32}, {"count", 3}, {"type", "VEC3"}});
    const int nrm = g.accessor({{"bufferView", v}, {"byteOffset", 12}, {"componentType", kF32}, {"count", 3}, {"type", "VEC3"}});
    g.mesh(json::array({{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}}}));
    g.scene(json::array({{{"mesh", 0}}}), {0});
    const Scene scene = loadScene(g.writeEmbedded(dir / "interleaved.gltf"));
    EXPECT_EQ(world(scene), (std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
    EXPECT_EQ(scene.meshes.at(0).normals, (std::vector<glm::vec3>(3, {0, 0, 1})));
}

TEST(GltfImporter, SparseAccessorWithoutBufferView)
{
    TempDir dir;
    GltfDoc g;
    // Zeros + sparse: vertices 1 and 2 set, vertex 0 stays at the origin.
    const int idxView = g.view(bytesOf(std::vector<std::uint8_t>{1, 2}));
    const int valView = g.view(bytesOf(std::vector<float>{4, 0, 0, 0, 5, 0}));
    const int pos = g.accessor({{"componentType", kF32}, {"count", 3}, {"type", "VEC3"},
                                {"sparse", {{"count", 2}, {"indices", {{"bufferView", idxView}, {"componentType", kU8}}},
                                            {"values", {{"bufferView", valView}}}}}});
    g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}}}));
    g.scene(json::array({{{"mesh", 0}}}), {0});
    EXPECT_EQ(world(loadScene(g.writeEmbedded(dir / "sparse.gltf"))),
              (std::vector<glm::vec3>{{0, 0, 0}, {4, 0, 0}, {0, 5, 0}}));
}

TEST(GltfImporter, InstancingAndTrs)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    // Parent translated by (10,0,0) with two children sharing mesh 0: one rotated 90° about Z, one scaled.
    const double s = std::sqrt(0.5);
    g.scene(json::array({{{"translation", {10, 0, 0}}, {"children", {1, 2}}},
                         {{"name", "turned"}, {"mesh", 0}, {"rotation", {0, 0, s, s}}},
                         {{"name", "big"}, {"mesh", 0}, {"scale", {2, 2, 2}}}}),
            {0});
    const Scene scene = loadScene(g.writeEmbedded(dir / "instances.gltf"));
    ASSERT_EQ(scene.meshes.size(), 1u);
    ASSERT_EQ(scene.instances.size(), 2u);
    EXPECT_EQ(scene.uniqueTriangleCount(), 1u);
    EXPECT_EQ(scene.triangleCount(), 2u);
    EXPECT_EQ(scene.instances[0].name, "turned");
    const std::vector<glm::vec3> expected = {{10, 0, 0}, {10, 1, 0}, {9, 0, 0}, {10, 0, 0}, {12, 0, 0}, {10, 2, 0}};
    const std::vector<glm::vec3> got = world(scene);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i)
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(got[i][k], expected[i][k], 1e-6f) << i;
}

TEST(GltfImporter, DefaultSceneIsChosen)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["nodes"] = json::array({{{"mesh", 0}}, {{"mesh", 0}, {"translation", {0, 0, 5}}}});
    g.doc["scenes"] = json::array({{{"nodes", {0}}}, {{"nodes", {1}}}});
    g.doc["scene"] = 1;
    const Scene scene = loadScene(g.writeEmbedded(dir / "second.gltf"));
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_FLOAT_EQ(scene.bounds().min.z, 5.0f);
}

TEST(GltfImporter, WithoutScenesAllRootNodesLoad)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc.erase("scenes");
    g.doc.erase("scene");
    // Node 1 is a child of node 0; node 2 is a second root.
    g.doc["nodes"] = json::array({{{"mesh", 0}, {"children", {1}}}, {{"mesh", 0}}, {{"mesh", 0}}});
    EXPECT_EQ(loadScene(g.writeEmbedded(dir / "noscene.gltf")).instances.size(), 3u);
}

TEST(GltfImporter, MissingImageOnlyWarns)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["images"] = json::array({{{"uri", "missing.png"}}});
    std::vector<std::string> warnings;
    EXPECT_EQ(loadScene(g.writeEmbedded(dir / "image.gltf"), &warnings).triangleCount(), 1u);
    EXPECT_FALSE(warnings.empty());
}

/// The unit cube [0, 1]^3, outward, as one indexed glTF mesh flagged (or not) watertight in its
/// extras; `dropLast` triangles left out.
GltfDoc cubeDoc(bool flagged, int dropLast = 0)
{
    GltfDoc g;
    const int pos = g.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1});
    std::vector<std::uint16_t> cube = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                       2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    cube.resize(cube.size() - 3 * std::size_t(dropLast));
    const int idx = g.indices(cube, kU16);
    g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}));
    if (flagged)
        g.doc["meshes"][0]["extras"] = {{"watertight", true}};
    g.doc["meshes"][0]["name"] = "cube";
    g.scene(json::array({{{"mesh", 0}}}), {0});
    return g;
}

TEST(GltfImporter, WatertightFlagIsHonouredOnlyOnAClosedOutwardMesh)
{
    TempDir dir;
    std::vector<std::string> warnings;
    const Scene closed = loadScene(cubeDoc(true).writeEmbedded(dir / "closed.gltf"), &warnings);
    EXPECT_TRUE(closed.meshes[0].watertight);
    EXPECT_TRUE(warnings.empty());

    // Flagged but open (the +x face's two triangles missing): no flag, one warning naming the mesh.
    const Scene open = loadScene(cubeDoc(true, 2).writeGlb(dir / "open.glb"), &warnings);
    ASSERT_EQ(open.triangleCount(), 10u);
    EXPECT_FALSE(open.meshes[0].watertight);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0].find('\n'), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("'cube'"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("watertight"), std::string::npos) << warnings[0];

    // glTF carries its own claim: an unflagged closed mesh stays unflagged.
    warnings.clear();
    EXPECT_FALSE(loadScene(cubeDoc(false).writeEmbedded(dir / "plain.gltf"), &warnings).meshes[0].watertight);
    EXPECT_TRUE(warnings.empty());
}

// ---- refusals ----------------------------------------------------------------------------------

TEST(GltfImporter, BufferUriEscapingTheFolderIsRefused)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    // The escaping buffer exists and is valid, so loading it would succeed: the refusal is the policy.
    writeFile(dir / "outside.bin", g.bin);
    g.doc["buffers"] = json::array({{{"byteLength", g.bin.size()}, {"uri", "../outside.bin"}}});
    const auto file = writeFile(dir / "inner" / "escape.gltf", g.doc.dump());
    EXPECT_NE(expectOneLineError(file, [&] { loadScene(file); }).find("../outside.bin"), std::string::npos);
}

TEST(GltfImporter, PercentEncodedEscapeIsRefused)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    writeFile(dir / "outside.bin", g.bin);
    g.doc["buffers"] = json::array({{{"byteLength", g.bin.size()}, {"uri", "%2E%2E/outside.bin"}}});
    const auto file = writeFile(dir / "inner" / "encoded.gltf", g.doc.dump());
    EXPECT_NE(expectOneLineError(file, [&] { loadScene(file); }).find("outside"), std::string::npos);
}

TEST(GltfImporter, AbsoluteBufferUriIsRefused)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    const auto bin = writeFile(dir / "abs.bin", g.bin); // same folder, still refused: absolute
    g.doc["buffers"] = json::array({{{"byteLength", g.bin.size()}, {"uri", bin.string()}}});
    const auto file = writeFile(dir / "absolute.gltf", g.doc.dump());
    EXPECT_NE(expectOneLineError(file, [&] { loadScene(file); }).find(bin.string()), std::string::npos);
}

TEST(GltfImporter, RequiredExtensionIsRefused)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    g.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    const auto file = g.writeEmbedded(dir / "required.gltf");
    EXPECT_NE(expectOneLineError(file, [&] { loadScene(file); }).find("KHR_mesh_quantization"), std::string::npos);
}

TEST(GltfImporter, MalformedJsonIsRefused)
{
    TempDir dir;
    const auto file = writeFile(dir / "broken.gltf", "{\"asset\": {\"version\": \"2.0\"},\n \"nodes\": [\n");
    expectOneLineError(file, [&] { loadScene(file); });
    const auto text = writeFile(dir / "text.glb", "this is not a glb file at all");
    expectOneLineError(text, [&] { loadScene(text); });
}

TEST(GltfImporter, GlbVersion1IsRefused)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    const auto file = g.writeGlb(dir / "old.glb", 1);
    EXPECT_NE(expectOneLineError(file, [&] { loadScene(file); }).find("version 1"), std::string::npos);
}

TEST(GltfImporter, IndexOutOfRangeIsRefused)
{
    TempDir dir;
    GltfDoc g;
    const int pos = g.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const int idx = g.indices(std::vector<std::uint16_t>{0, 1, 3}, kU16);
    g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}));
    g.scene(json::array({{{"mesh", 0}}}), {0});
    const auto file = g.writeEmbedded(dir / "badindex.gltf");
    EXPECT_NE(expectOneLineError(file, [&] { loadScene(file); }).find("out of range"), std::string::npos);
}

TEST(GltfImporter, AccessorOverrunningItsBufferIsRefused)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["accessors"][0]["count"] = 1000; // 3 vertices stored
    const auto file = g.writeEmbedded(dir / "overrun.gltf");
    expectOneLineError(file, [&] { loadScene(file); });

    GltfDoc h = triangleDoc();
    h.doc["bufferViews"][0]["byteLength"] = 4096; // the view itself overruns the buffer
    const auto view = h.writeEmbedded(dir / "viewoverrun.gltf");
    expectOneLineError(view, [&] { loadScene(view); });

    GltfDoc k = triangleDoc();
    k.doc["accessors"][0]["byteOffset"] = std::numeric_limits<std::uint64_t>::max() - 4; // wrap-around attempt
    const auto offset = k.writeEmbedded(dir / "offset.gltf");
    expectOneLineError(offset, [&] { loadScene(offset); });
}

TEST(GltfImporter, StrideSmallerThanElementIsRefused)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["bufferViews"][0]["byteStride"] = 4; // elements would overlap
    const auto file = g.writeEmbedded(dir / "stride.gltf");
    EXPECT_NE(expectOneLineError(file, [&] { loadScene(file); }).find("byteStride"), std::string::npos);
}

TEST(GltfImporter, SparseIndexOutOfRangeIsRefused)
{
    TempDir dir;
    GltfDoc g;
    const int idxView = g.view(bytesOf(std::vector<std::uint8_t>{7}));
    const int valView = g.view(bytesOf(std::vector<float>{4, 0, 0}));
    const int pos = g.accessor({{"componentType", kF32}, {"count", 3}, {"type", "VEC3"},
                                {"sparse", {{"count", 1}, {"indices", {{"bufferView", idxView}, {"componentType", kU8}}},
                                            {"values", {{"bufferView", valView}}}}}});
    g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}}}));
    g.scene(json::array({{{"mesh", 0}}}), {0});
    const auto file = g.writeEmbedded(dir / "sparse_bad.gltf");
    expectOneLineError(file, [&] { loadScene(file); });
}

TEST(GltfImporter, NonFloatPositionsAndNaNAreRefused)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.doc["accessors"][0]["type"] = "VEC2";
    const auto vec2 = g.writeEmbedded(dir / "vec2.gltf");
    expectOneLineError(vec2, [&] { loadScene(vec2); });

    GltfDoc n;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const int pos = n.positions({0, 0, 0, nan, 0, 0, 0, 1, 0});
    n.mesh(json::array({{{"attributes", {{"POSITION", pos}}}}}));
    n.scene(json::array({{{"mesh", 0}}}), {0});
    const auto file = n.writeEmbedded(dir / "nan.gltf");
    EXPECT_NE(expectOneLineError(file, [&] { loadScene(file); }).find("not finite"), std::string::npos);
}

TEST(GltfImporter, CyclicNodesAreRefused)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    g.scene(json::array({{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}}), {0});
    const auto file = g.writeEmbedded(dir / "cycle.gltf");
    expectOneLineError(file, [&] { loadScene(file); });
}

TEST(GltfImporter, TruncatedGlbIsRefused)
{
    TempDir dir;
    GltfDoc g = triangleDoc();
    const auto whole = g.writeGlb(dir / "whole.glb");
    std::ifstream in(whole, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (std::size_t cut : {std::size_t(10), std::size_t(30), bytes.size() - 8}) {
        const auto file = writeFile(dir / ("cut" + std::to_string(cut) + ".glb"), bytes.substr(0, cut));
        expectOneLineError(file, [&] { loadScene(file); });
    }
}

} // namespace
