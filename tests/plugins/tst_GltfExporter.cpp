// glTF exporter: .glb and .gltf round trips keep instancing, names, normals and world-space
// geometry; a failed save leaves nothing behind.

#include <fstream>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "TestFiles.h"
#include "plugins/SceneFormats.h"

using namespace sightline;
using sightline::test::expectOneLineError;
using sightline::test::TempDir;

namespace {

/// A unit tetrahedron instanced three times with different transforms, plus a single quad.
Scene sampleScene()
{
    Mesh tetra;
    tetra.name = "tetra";
    tetra.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tetra.normals = {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tetra.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    tetra.watertight = true;   // travels in the mesh's glTF extras
    Mesh quad;
    quad.name = "quad";
    quad.positions = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
    quad.indices = {0, 2, 1, 0, 3, 2};

    Scene scene;
    const std::uint32_t t = scene.addMesh(tetra);
    scene.instances.push_back({"a", t, glm::mat4(1.0f)});
    scene.instances.push_back({"b", t, glm::translate(glm::mat4(1.0f), {5.0f, 0.0f, -2.0f})});
    scene.instances.push_back({"c", t, glm::rotate(glm::scale(glm::mat4(1.0f), {2.0f, 0.5f, 3.0f}), 0.7f,
                                                   glm::normalize(glm::vec3(1.0f, 2.0f, 3.0f)))});
    scene.addMeshInstance(quad, glm::translate(glm::mat4(1.0f), {0.0f, -1.0f, 0.0f}));
    return scene;
}

void expectSameScene(const Scene& a, const Scene& b)
{
    ASSERT_EQ(a.meshes.size(), b.meshes.size());
    ASSERT_EQ(a.instances.size(), b.instances.size());
    EXPECT_EQ(a.triangleCount(), b.triangleCount());
    EXPECT_EQ(a.uniqueTriangleCount(), b.uniqueTriangleCount());
    for (std::size_t i = 0; i < a.meshes.size(); ++i) {
        EXPECT_EQ(a.meshes[i].name, b.meshes[i].name);
        EXPECT_EQ(a.meshes[i].positions, b.meshes[i].positions);
        EXPECT_EQ(a.meshes[i].normals, b.meshes[i].normals);
        EXPECT_EQ(a.meshes[i].indices, b.meshes[i].indices);
        EXPECT_EQ(a.meshes[i].watertight, b.meshes[i].watertight) << a.meshes[i].name;
    }
    for (std::size_t i = 0; i < a.instances.size(); ++i) {
        EXPECT_EQ(a.instances[i].name, b.instances[i].name);
        EXPECT_EQ(a.instances[i].mesh, b.instances[i].mesh);
    }
    const WorldTriangles wa = worldTriangles(a), wb = worldTriangles(b);
    ASSERT_EQ(wa.vertices.size(), wb.vertices.size());
    for (std::size_t i = 0; i < wa.vertices.size(); ++i)
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(wa.vertices[i][k], wb.vertices[i][k], 1e-6f) << "vertex " << i;
    EXPECT_EQ(wa.instanceOf, wb.instanceOf);
}

TEST(GltfExporter, GlbRoundTripKeepsInstancing)
{
    TempDir dir;
    const Scene scene = sampleScene();
    saveScene(scene, dir / "scene.glb");
    const Scene back = loadScene(dir / "scene.glb");
    EXPECT_EQ(back.meshes.size(), 2u);
    EXPECT_EQ(back.instances.size(), 4u);
    expectSameScene(scene, back);
    std::ifstream in(dir / "scene.glb", std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    EXPECT_EQ(std::string(magic, 4), "glTF");
}

TEST(GltfExporter, GltfRoundTripIsSelfContained)
{
    TempDir dir;
    const Scene scene = sampleScene();
    saveScene(scene, dir / "scene.gltf");
    // One file only: the buffer is a data URI, not a .bin beside it.
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()), 1);
    expectSameScene(scene, loadScene(dir / "scene.gltf"));
}

TEST(GltfExporter, WritesSpecRequiredFields)
{
    TempDir dir;
    saveScene(sampleScene(), dir / "scene.gltf");
    std::ifstream in(dir / "scene.gltf");
    const nlohmann::json doc = nlohmann::json::parse(in);
    EXPECT_EQ(doc["asset"]["version"], "2.0");
    ASSERT_EQ(doc["scenes"].size(), 1u);
    EXPECT_EQ(doc["scenes"][0]["nodes"].size(), 4u);
    EXPECT_EQ(doc["meshes"].size(), 2u);
    ASSERT_EQ(doc["buffers"].size(), 1u);
    EXPECT_EQ(doc["buffers"][0]["uri"].get<std::string>().rfind("data:", 0), 0u);
    for (const auto& node : doc["nodes"])
        EXPECT_EQ(node["matrix"].size(), 16u);
    const auto& prim = doc["meshes"][0]["primitives"][0];
    EXPECT_EQ(doc["accessors"][prim["indices"].get<int>()]["componentType"], 5125); // u32
    const auto& pos = doc["accessors"][prim["attributes"]["POSITION"].get<int>()];
    EXPECT_EQ(pos["min"], nlohmann::json({0.0, 0.0, 0.0}));
    EXPECT_EQ(pos["max"], nlohmann::json({1.0, 1.0, 1.0}));
    EXPECT_TRUE(prim["attributes"].contains("NORMAL"));
    EXPECT_FALSE(doc["meshes"][1]["primitives"][0]["attributes"].contains("NORMAL")); // quad has none
}

TEST(GltfExporter, EmptySceneRoundTrips)
{
    TempDir dir;
    saveScene(Scene{}, dir / "empty.glb");
    const Scene back = loadScene(dir / "empty.glb");
    EXPECT_TRUE(back.meshes.empty());
    EXPECT_TRUE(back.instances.empty());
}

TEST(GltfExporter, FailedSaveLeavesNothingBehind)
{
    TempDir dir;
    const auto target = dir / "missing-folder" / "scene.glb";
    expectOneLineError(target, [&] { saveScene(sampleScene(), target); });
    EXPECT_FALSE(std::filesystem::exists(dir / "missing-folder"));
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(GltfExporter, SaveReplacesAnExistingFile)
{
    TempDir dir;
    const auto target = dir / "scene.glb";
    test::writeFile(target, "old contents");
    saveScene(sampleScene(), target);
    EXPECT_EQ(loadScene(target).triangleCount(), sampleScene().triangleCount());
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()), 1);
}

TEST(GltfExporter, InvalidSceneOrFormatIsRefused)
{
    TempDir dir;
    Scene broken = sampleScene();
    broken.meshes[0].indices.push_back(99);
    broken.meshes[0].indices.push_back(0);
    broken.meshes[0].indices.push_back(1);
    const auto target = dir / "broken.glb";
    expectOneLineError(target, [&] { saveScene(broken, target); });
    EXPECT_FALSE(std::filesystem::exists(target));
    const auto obj = dir / "scene.obj";
    expectOneLineError(obj, [&] { saveScene(sampleScene(), obj); });
}

} // namespace
