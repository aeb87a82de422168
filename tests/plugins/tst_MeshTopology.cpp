// OpenMesh's half-edge view of a mesh (plugins/MeshTopology.h) against known answers on closed,
// open, flipped, inverted and non-manifold meshes, and against the core's edge-count check
// (visibility/Scene.h closedAndOutward) on every mesh file of the repository's test data.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "TestScenes.h"
#include "plugins/MeshTopology.h"
#include "plugins/SceneFormats.h"

using namespace sightline;
using namespace sightline::test;

namespace {

Mesh joined(Mesh a, const Mesh& b, glm::vec3 offset)
{
    const auto base = std::uint32_t(a.positions.size());
    for (const glm::vec3& p : b.positions)
        a.positions.push_back(p + offset);
    for (const std::uint32_t i : b.indices)
        a.indices.push_back(base + i);
    return a;
}

} // namespace

TEST(MeshTopology, ClosedBoxesAreClosedOutwardAndCounted)
{
    const MeshTopology box = meshTopology(closedBox());
    EXPECT_TRUE(box.closedAndOutward());
    EXPECT_EQ(box.faces, 12u);
    EXPECT_EQ(box.boundaryEdges, 0u);
    EXPECT_EQ(box.components, 1u);
    EXPECT_NEAR(box.volume, 1.0, 1e-9);
    const MeshTopology two = meshTopology(joined(closedBox(), closedBox(), {3.0f, 0.0f, 0.0f}));
    EXPECT_TRUE(two.closedAndOutward());
    EXPECT_EQ(two.components, 2u);
    EXPECT_NEAR(two.volume, 2.0, 1e-9);
}

TEST(MeshTopology, BrokenMeshesSayWhatIsWrong)
{
    Mesh open = closedBox();
    open.indices.resize(open.indices.size() - 6);   // one square face missing: a hole of four edges
    EXPECT_EQ(meshTopology(open).boundaryEdges, 4u);
    EXPECT_FALSE(meshTopology(open).closed());

    Mesh flipped = closedBox();
    std::swap(flipped.indices[1], flipped.indices[2]);
    std::swap(flipped.indices[4], flipped.indices[5]);
    EXPECT_GT(meshTopology(flipped).refused, 0u);
    EXPECT_FALSE(meshTopology(flipped).closed());

    Mesh inverted = closedBox();   // closed and consistent, every face inward
    for (std::size_t t = 0; t < inverted.triangleCount(); ++t)
        std::swap(inverted.indices[3 * t + 1], inverted.indices[3 * t + 2]);
    EXPECT_TRUE(meshTopology(inverted).closed());
    EXPECT_LT(meshTopology(inverted).volume, 0.0);
    EXPECT_FALSE(meshTopology(inverted).closedAndOutward());

    Mesh doubled = closedBox();   // a triangle stored twice
    doubled.indices.insert(doubled.indices.end(), {0, 2, 3});
    EXPECT_EQ(meshTopology(doubled).refused, 1u);

    // Two boxes sharing an edge: four faces on it, not a manifold.
    const Mesh touching = joined(closedBox(), closedBox(), {1.0f, 0.0f, 1.0f});
    EXPECT_FALSE(meshTopology(touching).closed());

    Mesh degenerate = closedBox();   // a triangle with two corners at one place covers nothing
    degenerate.indices.insert(degenerate.indices.end(), {0, 0, 3});
    EXPECT_EQ(meshTopology(degenerate).degenerate, 1u);
    EXPECT_TRUE(meshTopology(degenerate).closedAndOutward());

    EXPECT_FALSE(meshTopology(Mesh{}).closed());
    Mesh outOfRange = closedBox();
    outOfRange.indices[5] = 99;
    EXPECT_FALSE(meshTopology(outOfRange).closed());

    // Every broken case as the core's check answers it.
    for (const Mesh* m : std::initializer_list<const Mesh*>{&open, &flipped, &inverted, &doubled, &touching, &degenerate})
        EXPECT_EQ(meshTopology(*m).closedAndOutward(), closedAndOutward(*m));
}

TEST(MeshTopology, AgreesWithTheCoreCheckOnEveryTestMesh)
{
    int files = 0, closedFiles = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(std::string(SIGHTLINE_TEST_DATA) + "/meshes")) {
        const std::filesystem::path file = entry.path();
        if (!entry.is_regular_file() || !SceneFormatRegistry::builtin().importerFor(file))
            continue;
        Scene scene;
        try {
            scene = loadScene(file);
        } catch (const std::exception&) {
            continue;   // the negative files are the readers' tests
        }
        for (const Mesh& mesh : scene.meshes) {
            const MeshTopology topology = meshTopology(mesh);
            EXPECT_EQ(topology.closedAndOutward(), closedAndOutward(mesh)) << file;
            EXPECT_EQ(mesh.watertight, topology.closedAndOutward()) << file << ": the importer's flag";
            EXPECT_EQ(topology.faces + topology.degenerate + topology.refused, mesh.triangleCount()) << file;
            closedFiles += topology.closed();
        }
        ++files;
    }
    EXPECT_GE(files, 8);
    EXPECT_GE(closedFiles, 1);
    // The Stanford bunny of bun_zipper.ply has holes in its base.
    const MeshTopology bunny = meshTopology(loadScene(std::string(SIGHTLINE_TEST_DATA) + "/meshes/bun_zipper.ply").meshes.at(0));
    EXPECT_GT(bunny.boundaryEdges, 0u);
    EXPECT_FALSE(bunny.closed());
}
