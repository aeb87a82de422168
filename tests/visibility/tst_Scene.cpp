#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "TestScenes.h"
#include "visibility/AtomicFile.h"
#include "visibility/Error.h"
#include "visibility/Scene.h"

using namespace sightline;
using namespace sightline::test;

TEST(Scene, InstancesShareOneMesh)
{
    Scene scene;
    const std::uint32_t m = scene.addMesh(quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
    for (int i = 0; i < 200; ++i)
        scene.instances.push_back({"copy", m, glm::translate(glm::mat4(1.0f), glm::vec3(float(i), 0, 0))});
    EXPECT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.uniqueTriangleCount(), 2u);
    EXPECT_EQ(scene.triangleCount(), 400u);
    const Bounds box = scene.bounds();
    EXPECT_FLOAT_EQ(box.min.x, 0.0f);
    EXPECT_FLOAT_EQ(box.max.x, 200.0f);
    EXPECT_FLOAT_EQ(box.max.y, 1.0f);

    const WorldTriangles world = worldTriangles(scene);
    ASSERT_EQ(world.size(), 400u);
    EXPECT_EQ(world.instanceOf[399], 199u);
    EXPECT_FLOAT_EQ(world.vertices[3 * 399 + 1].x, 200.0f);   // second vertex of the last copy
}

TEST(Scene, AppendRemapsMeshIndices)
{
    Scene a = sceneOf({quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, "a")});
    Scene b = sceneOf({quad({0, 0, 5}, {1, 0, 0}, {0, 1, 0}, "b1"), quad({0, 0, 6}, {2, 0, 0}, {0, 2, 0}, "b2")});
    a.append(b);
    ASSERT_EQ(a.instances.size(), 3u);
    EXPECT_EQ(a.meshes[a.instances[2].mesh].name, "b2");
    EXPECT_EQ(a.bounds().max.z, 6.0f);
    EXPECT_TRUE(Scene{}.bounds().empty());
}

TEST(Scene, ValidateNamesTheProblem)
{
    Mesh m = quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    EXPECT_NO_THROW(validate(m, "ok"));

    Mesh nan = m;
    nan.positions[2].y = std::nanf("");
    try {
        validate(nan, "level.obj");
        FAIL() << "NaN vertex accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("level.obj"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos);
    }
    Mesh range = m;
    range.indices[4] = 17;
    EXPECT_THROW(validate(range, "x"), Error);
    Mesh partial = m;
    partial.indices.pop_back();
    EXPECT_THROW(validate(partial, "x"), Error);

    Scene scene = sceneOf({m});
    scene.instances.push_back({"ghost", 5, glm::mat4(1.0f)});
    EXPECT_THROW(validate(scene, "x"), Error);
    scene.instances.pop_back();
    scene.instances[0].transform[3][0] = INFINITY;
    EXPECT_THROW(validate(scene, "x"), Error);
}

TEST(AtomicFile, ReplacesWholeOrNotAtAll)
{
    namespace fs = std::filesystem;
    const fs::path folder = fs::temp_directory_path() / "sightline_atomic_test";
    fs::remove_all(folder);
    fs::create_directories(folder);
    const fs::path file = folder / "project.json";
    writeFileAtomically(file, "first");
    writeFileAtomically(file, "second, longer");
    std::stringstream content;
    content << std::ifstream(file).rdbuf();
    EXPECT_EQ(content.str(), "second, longer");
    // A failing save (its folder is missing) throws and leaves no temporary files behind.
    EXPECT_THROW(writeFileAtomically(folder / "nope" / "x.json", "data"), Error);
    // Target is a folder: the rename fails, the folder survives, no temporary file is left.
    fs::create_directories(folder / "dir");
    EXPECT_THROW(writeFileAtomically(folder / "dir", "data"), Error);
    EXPECT_TRUE(fs::is_directory(folder / "dir"));
    int entries = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(folder))
        ++entries;
    EXPECT_EQ(entries, 2);   // project.json and dir
    fs::remove_all(folder);
}

TEST(Scene, MirroredInstancesKeepOutwardWinding)
{
    Scene scene;
    Mesh tri;
    tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};   // counter-clockwise seen from +Z: normal +Z
    tri.indices = {0, 1, 2};
    const std::uint32_t m = scene.addMesh(tri);
    scene.instances.push_back({"plain", m, glm::mat4(1.0f)});
    scene.instances.push_back({"mirrored", m, glm::scale(glm::mat4(1.0f), glm::vec3(1, 1, -1))});
    const WorldTriangles world = worldTriangles(scene);
    auto normal = [&](std::size_t t) {
        return glm::cross(world.vertices[3 * t + 1] - world.vertices[3 * t], world.vertices[3 * t + 2] - world.vertices[3 * t]);
    };
    EXPECT_GT(normal(0).z, 0.0f);
    // Mirroring z maps the +Z face normal to -Z: the outward side moved, and the winding follows.
    EXPECT_LT(normal(1).z, 0.0f);
}
