#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "TestScenes.h"
#include "base/AtomicFile.h"
#include "base/Error.h"
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
    Mesh coloured = m;
    coloured.albedo = {glm::vec3(0.5f), glm::vec3(1.0f)};
    EXPECT_NO_THROW(validate(coloured, "x"));
    coloured.albedo.pop_back();   // one per triangle or none
    EXPECT_THROW(validate(coloured, "x"), Error);
    coloured.albedo = {glm::vec3(0.5f), glm::vec3(0.5f, 1.5f, 0.5f)};
    EXPECT_THROW(validate(coloured, "x"), Error);
    coloured.albedo[1].y = std::nanf("");
    EXPECT_THROW(validate(coloured, "x"), Error);
    coloured.albedo[1] = kUnknownAlbedo;   // the file does not say
    EXPECT_NO_THROW(validate(coloured, "x"));

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

namespace {

/// The closed box with every triangle given its own three vertices (as OBJ/STL/glTF files often
/// store them), shifted by `offset`.
Mesh unweldedBox(const glm::vec3& offset = glm::vec3(0.0f))
{
    const Mesh box = closedBox();
    Mesh m;
    for (std::uint32_t i : box.indices) {
        m.positions.push_back(box.positions[i] + offset);
        m.indices.push_back(std::uint32_t(m.indices.size()));
    }
    return m;
}

} // namespace

TEST(ClosedAndOutward, ClosedOutwardBoxesPassWeldedOrNotAndFarOut)
{
    EXPECT_TRUE(closedAndOutward(closedBox()));
    EXPECT_TRUE(closedAndOutward(unweldedBox()));
    EXPECT_TRUE(closedAndOutward(unweldedBox({1e5f, -3e4f, 2e5f})));   // volume from a local origin
    // Two disjoint boxes: each closed, volumes summed.
    Mesh two = unweldedBox();
    const Mesh other = unweldedBox({3.0f, 0.0f, 0.0f});
    for (std::uint32_t i : other.indices)
        two.indices.push_back(std::uint32_t(two.positions.size()) + i);
    two.positions.insert(two.positions.end(), other.positions.begin(), other.positions.end());
    EXPECT_TRUE(closedAndOutward(two));
}

TEST(ClosedAndOutward, OpenFlippedInvertedAndNonManifoldMeshesFail)
{
    Mesh open = closedBox();
    open.indices.resize(open.indices.size() - 6);   // one face (two triangles) missing
    EXPECT_FALSE(closedAndOutward(open));

    Mesh flipped = closedBox();
    std::swap(flipped.indices[1], flipped.indices[2]);   // one triangle wound the other way
    std::swap(flipped.indices[4], flipped.indices[5]);   // and its face's other triangle
    EXPECT_FALSE(closedAndOutward(flipped));

    Mesh inverted = closedBox();   // closed and consistent, but every face inward
    for (std::size_t t = 0; t < inverted.triangleCount(); ++t)
        std::swap(inverted.indices[3 * t + 1], inverted.indices[3 * t + 2]);
    EXPECT_FALSE(closedAndOutward(inverted));

    Mesh doubled = closedBox();   // a triangle stored twice: three faces on its edges
    doubled.indices.insert(doubled.indices.end(), {0, 2, 3});
    EXPECT_FALSE(closedAndOutward(doubled));

    // Two boxes sharing an edge (x = 0.5, z = 0.5 of the first): four faces on one edge.
    Mesh touching = unweldedBox();
    const Mesh other = unweldedBox({1.0f, 0.0f, 1.0f});
    for (std::uint32_t i : other.indices)
        touching.indices.push_back(std::uint32_t(touching.positions.size()) + i);
    touching.positions.insert(touching.positions.end(), other.positions.begin(), other.positions.end());
    EXPECT_FALSE(closedAndOutward(touching));

    EXPECT_FALSE(closedAndOutward(Mesh{}));
    Mesh outOfRange = closedBox();
    outOfRange.indices[7] = 8;
    EXPECT_FALSE(closedAndOutward(outOfRange));
}

TEST(ClosedAndOutward, DegenerateTrianglesAsDocumented)
{
    // A triangle with two corners at one position is skipped: the box stays closed.
    Mesh collapsed = closedBox();
    collapsed.positions.push_back(collapsed.positions[3]);   // a second vertex at corner 3's place
    collapsed.indices.insert(collapsed.indices.end(), {0, 3, 8});
    EXPECT_TRUE(closedAndOutward(collapsed));

    // A T-junction: the top face's edge 2-6 is split at its midpoint m in the -x face, and a
    // zero-area sliver (2, m, 6) joins the halves to the +y face's whole edge. Closed with the
    // sliver, open without it.
    Mesh split = closedBox();
    const std::uint32_t m = std::uint32_t(split.positions.size());
    split.positions.push_back(0.5f * (split.positions[2] + split.positions[6]));
    // The -x face (0, 4, 6, 2) is re-fanned through m: 0-4-6, 0-6 becomes 0-m and m-6 ...
    std::vector<std::uint32_t> indices;
    for (std::size_t t = 0; t < split.triangleCount(); ++t) {
        const std::uint32_t a = split.indices[3 * t], b = split.indices[3 * t + 1], c = split.indices[3 * t + 2];
        if (a == 0 && b == 4 && c == 6)
            indices.insert(indices.end(), {0, 4, 6, 0, 6, m});
        else if (a == 0 && b == 6 && c == 2)
            indices.insert(indices.end(), {0, m, 2});
        else
            indices.insert(indices.end(), {a, b, c});
    }
    split.indices = indices;
    EXPECT_FALSE(closedAndOutward(split));   // edges 6-m and m-2 have no partner
    split.indices.insert(split.indices.end(), {2, m, 6});
    EXPECT_TRUE(closedAndOutward(split));
}
