// The generated bench scenes (BenchScenes.h), seeds 1-3 of every kind: what each kind promises about
// its size, patches and shaft, since tuning the CPU sampler's strategy choice on them is only worth
// something if the scenes really are what their names say.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "HullClip.h"
#include "demo/BenchScenes.h"
#include "demo/DemoLevel.h"
#include "visibility/Patch.h"
#include "visibility/RayCastSampler.h"
#include "visibility/Scene.h"
#include "visibility/ShaftGeometry.h"

using namespace sightline;
using demo::BenchKind;

namespace {

constexpr int kSeeds = 3;

struct Case {
    BenchKind kind;
    int seed;
};

std::vector<Case> allCases()
{
    std::vector<Case> cases;
    for (BenchKind kind : demo::kBenchKinds)
        for (int seed = 1; seed <= kSeeds; ++seed)
            cases.push_back({kind, seed});
    return cases;
}

/// What a kind promises (BenchScenes.h).
struct Promise {
    std::size_t minTriangles, maxTriangles;
    double minBlocked, maxBlocked;
};

Promise promiseOf(BenchKind kind)
{
    switch (kind) {
    case BenchKind::ClutteredRooms: return {60000, 100000, 0.20, 0.90};
    case BenchKind::DenseMesh: return {40000, 120000, 0.40, 1.00};
    case BenchKind::ArchitecturalInterior: return {15000, 30000, 0.10, 0.90};
    case BenchKind::OpenHall: return {1, 1999, 0.05, 0.80};
    }
    return {};
}

bool startsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

class BenchScenes : public ::testing::TestWithParam<Case> {
protected:
    const demo::BenchScene bench = demo::makeBenchScene(GetParam().kind, std::uint64_t(GetParam().seed));
    const WorldTriangles world = worldTriangles(bench.scene);
    const Promise promise = promiseOf(GetParam().kind);

    const Mesh& meshOf(std::size_t triangle) const
    {
        return bench.scene.meshes[bench.scene.instances[world.instanceOf[triangle]].mesh];
    }
};

void PrintTo(const Case& c, std::ostream* os) { *os << demo::benchKindName(c.kind) << "-" << c.seed; }

std::string caseName(const ::testing::TestParamInfo<Case>& info)
{
    std::string name = demo::benchKindName(info.param.kind);
    std::replace(name.begin(), name.end(), '-', '_');
    return name + "_" + std::to_string(info.param.seed);
}

} // namespace

TEST_P(BenchScenes, IsNamedAfterItsKindAndSeed)
{
    EXPECT_EQ(bench.name, std::string(demo::benchKindName(GetParam().kind)) + "-" + std::to_string(GetParam().seed));
    EXPECT_FALSE(bench.layout.empty());
}

TEST_P(BenchScenes, IsDeterministic)
{
    const demo::BenchScene again = demo::makeBenchScene(GetParam().kind, std::uint64_t(GetParam().seed));
    EXPECT_EQ(again.layout, bench.layout);
    ASSERT_EQ(again.scene.meshes.size(), bench.scene.meshes.size());
    ASSERT_EQ(again.scene.instances.size(), bench.scene.instances.size());
    for (std::size_t i = 0; i < again.scene.meshes.size(); ++i) {
        EXPECT_EQ(again.scene.meshes[i].name, bench.scene.meshes[i].name);
        EXPECT_EQ(again.scene.meshes[i].indices, bench.scene.meshes[i].indices);
        EXPECT_EQ(again.scene.meshes[i].watertight, bench.scene.meshes[i].watertight);
    }
    const WorldTriangles w = worldTriangles(again.scene);
    ASSERT_EQ(w.vertices.size(), world.vertices.size());
    EXPECT_EQ(std::memcmp(w.vertices.data(), world.vertices.data(), w.vertices.size() * sizeof(glm::vec3)), 0);
    EXPECT_EQ(w.instanceOf, world.instanceOf);
    for (const auto& [a, b] : {std::pair{&again.source, &bench.source}, std::pair{&again.receiver, &bench.receiver}}) {
        EXPECT_EQ(std::memcmp(&a->corner, &b->corner, sizeof(glm::dvec3)), 0);
        EXPECT_EQ(std::memcmp(&a->u, &b->u, sizeof(glm::dvec3)), 0);
        EXPECT_EQ(std::memcmp(&a->v, &b->v, sizeof(glm::dvec3)), 0);
    }
}

TEST_P(BenchScenes, HasTheKindsTriangleCount)
{
    EXPECT_GE(world.size(), promise.minTriangles);
    EXPECT_LE(world.size(), promise.maxTriangles);
}

TEST_P(BenchScenes, IsValidWithFiniteCoordinates)
{
    EXPECT_NO_THROW(validate(bench.scene, bench.name));
    EXPECT_NO_THROW(validateCoordinates(world, bench.name));
    for (const glm::vec3& p : world.vertices)
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << bench.name;
}

TEST_P(BenchScenes, PatchesAreAValidPairOfStandingPatchesFacingEachOther)
{
    ASSERT_NO_THROW(validatePatchPair(bench.source, bench.receiver));
    const glm::dvec3 along = bench.receiver.centre() - bench.source.centre();
    EXPECT_GE(glm::length(along), 8.0);
    EXPECT_LE(glm::length(along), 25.0);
    for (const Patch* p : {&bench.source, &bench.receiver}) {
        EXPECT_EQ(p->na, 32);
        EXPECT_EQ(p->nb, 32);
        // Vertical: v straight up 1-2 m, u level.
        EXPECT_EQ(p->v.x, 0.0);
        EXPECT_EQ(p->v.z, 0.0);
        EXPECT_GE(p->v.y, 1.0);
        EXPECT_LE(p->v.y, 2.0);
        EXPECT_EQ(p->u.y, 0.0);
        EXPECT_GE(glm::length(p->u), 0.9);
        EXPECT_LE(glm::length(p->u), 2.0);
    }
    // Roughly facing: each normal within 30 degrees of the line to the other patch (cos 30 = sqrt 3 / 2).
    const glm::dvec3 d = glm::normalize(along);
    EXPECT_GT(glm::dot(bench.source.normal(), d), std::sqrt(3.0) / 2.0);
    EXPECT_GT(glm::dot(bench.receiver.normal(), -d), std::sqrt(3.0) / 2.0);
}

TEST_P(BenchScenes, PatchesTouchNoGeometry)
{
    // A designer's patch stands in the open: nothing within 2 cm of either (exact clipping, not the
    // conservative hull test).
    EXPECT_TRUE(test::trianglesInHull(world, test::slab(bench.source, 0.02)).empty()) << bench.name;
    EXPECT_TRUE(test::trianglesInHull(world, test::slab(bench.receiver, 0.02)).empty()) << bench.name;
}

TEST_P(BenchScenes, WatertightMeshesAreClosedAndOutward)
{
    // The importer drops a flag that fails this (with a warning), so a wrongly flagged mesh would
    // bench differently from its own file.
    int flagged = 0;
    for (const Mesh& mesh : bench.scene.meshes) {
        if (!mesh.watertight)
            continue;
        ++flagged;
        EXPECT_TRUE(closedAndOutward(mesh)) << bench.name << ": " << mesh.name;
    }
    EXPECT_GE(flagged, 1) << bench.name;
}

TEST_P(BenchScenes, ShaftIsOccupiedAsTheKindPromises)
{
    const ShaftHull hull(bench.source, bench.receiver);
    std::size_t inShaft = 0, plantsInShaft = 0, statueInShaft = 0;
    std::set<std::uint32_t> plantInstances;
    for (std::size_t t = 0; t < world.size(); ++t) {
        if (hull.excludes(world.vertices[3 * t], world.vertices[3 * t + 1], world.vertices[3 * t + 2]))
            continue;
        ++inShaft;
        const Mesh& mesh = meshOf(t);
        if (startsWith(mesh.name, demo::kPlantMeshPrefix)) {
            ++plantsInShaft;
            plantInstances.insert(world.instanceOf[t]);
        }
        statueInShaft += startsWith(mesh.name, "statue");
    }
    const HiddenSampleMap map = RayCastScene(bench.scene).sample(bench.source, bench.receiver);
    const double blocked = double(map.blockedCount()) / double(map.rayCount());
    std::cout << "[ bench    ] " << bench.name << " (" << bench.layout << "): " << world.size() << " triangles, "
              << inShaft << " meet the shaft hull, " << plantInstances.size() << " plant instances in it, "
              << 100.0 * blocked << "% of the rays blocked\n";
    EXPECT_GE(blocked, promise.minBlocked) << bench.name;
    EXPECT_LE(blocked, promise.maxBlocked) << bench.name;
    EXPECT_LT(inShaft, world.size()) << bench.name;

    int plantPlacements = 0;
    for (const Instance& instance : bench.scene.instances)
        plantPlacements += startsWith(bench.scene.meshes[instance.mesh].name, demo::kPlantMeshPrefix);
    switch (GetParam().kind) {
    case BenchKind::ClutteredRooms:
        EXPECT_GE(plantPlacements, 30) << bench.name;
        EXPECT_LE(plantPlacements, 45) << bench.name;
        EXPECT_GE(plantInstances.size(), 20u) << bench.name;
        EXPECT_GE(plantsInShaft, 3000u) << bench.name << ": leaves are most of what the shaft meets";
        break;
    case BenchKind::DenseMesh:
        // The statues are what the shaft meets: tens of thousands of small triangles.
        EXPECT_GE(statueInShaft, 20000u) << bench.name;
        EXPECT_GE(10 * statueInShaft, 9 * inShaft) << bench.name;
        break;
    case BenchKind::ArchitecturalInterior:
    case BenchKind::OpenHall:
        EXPECT_EQ(plantPlacements, 0) << bench.name;
        EXPECT_GE(inShaft, 1u) << bench.name;
        break;
    }
}

INSTANTIATE_TEST_SUITE_P(AllKinds, BenchScenes, ::testing::ValuesIn(allCases()), caseName);

TEST(BenchSceneKinds, DenseMeshStatuesAreMadeOfSmallTriangles)
{
    for (const demo::BenchScene& bench : demo::benchScenes(BenchKind::DenseMesh, kSeeds)) {
        int statues = 0;
        for (const Mesh& mesh : bench.scene.meshes) {
            if (!startsWith(mesh.name, "statue"))
                continue;
            ++statues;
            std::vector<float> longest;
            for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
                const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                                c = mesh.positions[mesh.indices[3 * t + 2]];
                longest.push_back(std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)}));
            }
            std::sort(longest.begin(), longest.end());
            // Scan-like: ray casting wins because the triangles are small (1-4 cm) and many, so
            // the typical one must be that size and hardly any much larger.
            EXPECT_GE(longest[longest.size() / 2], 0.01f) << mesh.name;
            EXPECT_LE(longest[longest.size() / 2], 0.04f) << mesh.name;
            EXPECT_LE(longest[longest.size() * 95 / 100], 0.06f) << mesh.name;
            // A statue of the group layout is a closed scan; the big one stands open on its plinth.
            EXPECT_EQ(mesh.watertight, bench.layout == "group") << mesh.name;
            EXPECT_EQ(closedAndOutward(mesh), mesh.watertight) << mesh.name;
        }
        EXPECT_GE(statues, 1) << bench.name;
        EXPECT_LE(statues, 3) << bench.name;
    }
}

TEST(BenchSceneKinds, SeedsOneToThreeCoverTwoLayoutsAndDiffer)
{
    for (BenchKind kind : demo::kBenchKinds) {
        const std::vector<demo::BenchScene> scenes = demo::benchScenes(kind, kSeeds);
        ASSERT_EQ(scenes.size(), std::size_t(kSeeds));
        std::set<std::string> layouts;
        for (const demo::BenchScene& s : scenes)
            layouts.insert(s.layout);
        EXPECT_GE(layouts.size(), 2u) << demo::benchKindName(kind);
        // Seeds 1 and 3 share a layout; they must still be different scenes.
        EXPECT_EQ(scenes[0].layout, scenes[2].layout);
        EXPECT_TRUE(scenes[0].scene.triangleCount() != scenes[2].scene.triangleCount() ||
                    scenes[0].source.corner != scenes[2].source.corner)
            << demo::benchKindName(kind);
    }
}

TEST(BenchSceneKinds, KindNamesAreDistinctFileStems)
{
    std::set<std::string> names;
    for (BenchKind kind : demo::kBenchKinds) {
        const std::string name = demo::benchKindName(kind);
        EXPECT_EQ(name.find_first_not_of("abcdefghijklmnopqrstuvwxyz-"), std::string::npos) << name;
        names.insert(name);
    }
    EXPECT_EQ(names.size(), std::size(demo::kBenchKinds));
}
