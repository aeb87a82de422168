// The generated demo level: size, determinism, instancing, closed meshes, and the demo view's shaft
// (enough fine clutter inside it for the benchmarks that use it).

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "HullClip.h"
#include "demo/DemoLevel.h"
#include "visibility/Patch.h"
#include "visibility/Scene.h"

using namespace sightline;
using test::corners;
using test::hullPlanes;
using test::intersects;
using test::slab;

namespace {

const Scene& level()
{
    static const Scene scene = demo::makeDemoLevel();
    return scene;
}

const WorldTriangles& world()
{
    static const WorldTriangles triangles = worldTriangles(level());
    return triangles;
}

bool isPlant(const Mesh& mesh) { return mesh.name.rfind(demo::kPlantMeshPrefix, 0) == 0; }

/// Indices of the world triangles that meet the convex hull of `points`.
std::vector<std::size_t> trianglesInHull(const std::vector<glm::dvec3>& points)
{
    return test::trianglesInHull(world(), points);
}

std::vector<glm::dvec3> shaftCorners(const demo::DemoView& view)
{
    std::vector<glm::dvec3> points = corners(view.source);
    const std::vector<glm::dvec3> r = corners(view.receiver);
    points.insert(points.end(), r.begin(), r.end());
    return points;
}

} // namespace

TEST(DemoLevel, HasAboutEightyThousandTriangles)
{
    const std::size_t count = level().triangleCount();
    EXPECT_GE(count, 70000u);
    EXPECT_LE(count, 90000u);
    EXPECT_EQ(world().size(), count);
}

TEST(DemoLevel, IsDeterministic)
{
    const Scene again = demo::makeDemoLevel();
    ASSERT_EQ(again.meshes.size(), level().meshes.size());
    ASSERT_EQ(again.instances.size(), level().instances.size());
    for (std::size_t i = 0; i < again.instances.size(); ++i) {
        EXPECT_EQ(again.instances[i].name, level().instances[i].name);
        EXPECT_EQ(again.instances[i].mesh, level().instances[i].mesh);
    }
    const WorldTriangles w = worldTriangles(again);
    ASSERT_EQ(w.vertices.size(), world().vertices.size());
    EXPECT_EQ(std::memcmp(w.vertices.data(), world().vertices.data(), w.vertices.size() * sizeof(glm::vec3)), 0);
    EXPECT_EQ(w.instanceOf, world().instanceOf);
}

TEST(DemoLevel, IsValidAndFloorSized)
{
    EXPECT_NO_THROW(validate(level(), "demo"));
    const Bounds box = level().bounds();
    const glm::vec3 size = box.max - box.min;
    EXPECT_GE(size.y, 2.5f);
    EXPECT_LE(size.y, 5.0f);
    EXPECT_NEAR(box.min.y, 0.0f, 0.05f);   // standing on the floor at y = 0
    for (float extent : {size.x, size.z}) {
        EXPECT_GE(extent, 10.0f);
        EXPECT_LE(extent, 100.0f);
    }
}

TEST(DemoLevel, EveryMeshHasUnitNormals)
{
    for (const Mesh& mesh : level().meshes) {
        ASSERT_EQ(mesh.normals.size(), mesh.positions.size()) << mesh.name;
        for (const glm::vec3& n : mesh.normals)
            ASSERT_NEAR(glm::length(n), 1.0f, 1e-3f) << mesh.name;
    }
}

TEST(DemoLevel, UsesInstancing)
{
    const Scene& scene = level();
    EXPECT_GT(scene.instances.size(), scene.meshes.size());
    EXPECT_LT(scene.uniqueTriangleCount() * 2, scene.triangleCount());

    std::map<std::string, int> storedAs, placements;
    for (const Mesh& mesh : scene.meshes)
        ++storedAs[mesh.name];
    int plantInstances = 0;
    for (const Instance& instance : scene.instances) {
        const Mesh& mesh = scene.meshes[instance.mesh];
        ++placements[mesh.name];
        if (isPlant(mesh))
            ++plantInstances;
    }
    int plantMeshes = 0;
    for (const Mesh& mesh : scene.meshes) {
        if (!isPlant(mesh))
            continue;
        ++plantMeshes;
        EXPECT_EQ(storedAs[mesh.name], 1) << mesh.name << " stored more than once";
        EXPECT_GE(placements[mesh.name], 3) << mesh.name;
        EXPECT_GE(mesh.triangleCount(), 700u) << mesh.name << ": a plant has about 1000 leaves";
    }
    EXPECT_GE(plantMeshes, 2);
    EXPECT_LE(plantMeshes, 6);
    EXPECT_GE(plantInstances, 30);
}

TEST(DemoLevel, LeavesAreSmall)
{
    for (const Mesh& mesh : level().meshes) {
        if (!isPlant(mesh))
            continue;
        int leaves = 0;
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                            c = mesh.positions[mesh.indices[3 * t + 2]];
            const float longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
            leaves += longest >= 0.025f && longest <= 0.09f;
        }
        EXPECT_GE(leaves, 700) << mesh.name;
    }
}

TEST(DemoLevel, WatertightMeshesAreClosedAndOutward)
{
    // The importers keep a glTF's watertight flag only where closedAndOutward holds, so a flagged
    // demo mesh failing it would lose its flag (and its culling) when demo_level.glb is loaded.
    int checked = 0;
    for (const Mesh& mesh : level().meshes) {
        if (!mesh.watertight)
            continue;
        ++checked;
        EXPECT_TRUE(closedAndOutward(mesh)) << mesh.name;
    }
    EXPECT_GE(checked, 10);
    for (const demo::BenchScene& bench : {demo::makeFewOccludersScene(), demo::makeDenseMeshScene()}) {
        for (const Mesh& mesh : bench.scene.meshes) {
            if (mesh.watertight) {
                EXPECT_TRUE(closedAndOutward(mesh)) << bench.name << ": " << mesh.name;
            }
        }
    }
    // The unflagged ones are open on purpose (plants: single-triangle leaves) or stand for an
    // imported mesh (the dense scene's statue); the plants must fail the check.
    for (const Mesh& mesh : level().meshes) {
        if (isPlant(mesh)) {
            EXPECT_FALSE(closedAndOutward(mesh)) << mesh.name;
        }
    }
}

TEST(DemoView, IsAValidPairOfPersonAndWallSizedPatches)
{
    const demo::DemoView view = demo::demoView();
    EXPECT_NO_THROW(validatePatchPair(view.source, view.receiver));
    EXPECT_EQ(view.source.na, 32);
    EXPECT_EQ(view.source.nb, 32);
    EXPECT_EQ(view.receiver.na, 32);
    EXPECT_EQ(view.receiver.nb, 32);
    const double sourceArea = glm::length(glm::cross(view.source.u, view.source.v));
    const double receiverArea = glm::length(glm::cross(view.receiver.u, view.receiver.v));
    EXPECT_NEAR(sourceArea, 1.6, 0.5);
    EXPECT_NEAR(receiverArea, 4.0, 1.0);
    // The source faces the receiver.
    EXPECT_GT(glm::dot(view.source.normal(), view.receiver.centre() - view.source.centre()), 0.0);
}

TEST(DemoView, PatchesTouchNoGeometry)
{
    const demo::DemoView view = demo::demoView();
    EXPECT_TRUE(trianglesInHull(slab(view.source, 0.02)).empty());
    EXPECT_TRUE(trianglesInHull(slab(view.receiver, 0.02)).empty());
}

TEST(DemoView, CentralRayPassesThroughTheWallsOpenings)
{
    // Source and receiver are in different rooms: a wall's plane lies between them, and the ray
    // between the patch centres crosses no wall triangle (it goes through a doorway).
    const demo::DemoView view = demo::demoView();
    const glm::dvec3 from = view.source.centre(), to = view.receiver.centre();
    const WorldTriangles& w = world();
    int wallsBetween = 0;
    for (std::size_t t = 0; t < w.size(); ++t) {
        const Instance& instance = level().instances[w.instanceOf[t]];
        if (level().meshes[instance.mesh].name.rfind("wall", 0) != 0)
            continue;
        const glm::dvec3 a(w.vertices[3 * t]), b(w.vertices[3 * t + 1]), c(w.vertices[3 * t + 2]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        const double sf = glm::dot(n, from - a), st = glm::dot(n, to - a);
        if ((sf > 0) == (st > 0))
            continue;
        const glm::dvec3 p = from + (to - from) * (sf / (sf - st));
        const bool inside = glm::dot(glm::cross(b - a, p - a), n) >= 0 && glm::dot(glm::cross(c - b, p - b), n) >= 0 &&
                            glm::dot(glm::cross(a - c, p - c), n) >= 0;
        EXPECT_FALSE(inside) << "the central ray hits " << instance.name;
        wallsBetween += std::abs(n.y) < 1e-6 * glm::length(n) ? 1 : 0;
    }
    EXPECT_GT(wallsBetween, 0) << "no wall plane between the patches: they are in one room";
}

TEST(DemoView, ShaftIsFullOfFineClutter)
{
    const demo::DemoView view = demo::demoView();
    const std::vector<std::size_t> hits = trianglesInHull(shaftCorners(view));
    std::size_t plants = 0;
    for (std::size_t t : hits)
        plants += isPlant(level().meshes[level().instances[world().instanceOf[t]].mesh]);
    EXPECT_GE(hits.size(), 12000u) << "the benchmark needs >= 12k triangles in the shaft";
    EXPECT_GE(plants, 3000u) << "plants in the shaft";
    EXPECT_LT(hits.size(), world().size() / 2) << "the shaft is not the whole level";
}

TEST(DemoView, HullTestIsExactOnSimpleCases)
{
    // Unit cube hull; triangles inside, crossing, touching a face, and outside near a corner.
    std::vector<glm::dvec3> cube;
    for (int i = 0; i < 8; ++i)
        cube.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
    const std::vector<test::HullPlane> planes = hullPlanes(cube);
    EXPECT_GE(planes.size(), 6u);
    EXPECT_TRUE(intersects(planes, {0.2, 0.2, 0.2}, {0.4, 0.2, 0.2}, {0.2, 0.4, 0.2}));
    EXPECT_TRUE(intersects(planes, {-1, 0.5, -1}, {3, 0.5, -1}, {-1, 0.5, 3}));   // big, cuts through
    EXPECT_FALSE(intersects(planes, {1.6, 1.0, 1.0}, {1.0, 1.6, 1.0}, {1.0, 1.0, 1.6}));   // off a corner
    EXPECT_FALSE(intersects(planes, {2, 2, 2}, {3, 2, 2}, {2, 3, 2}));
    EXPECT_TRUE(intersects(planes, {1.5, 0.5, -0.5}, {-0.5, 0.5, -0.5}, {0.5, 0.5, 1.5}));   // all corners outside
}
