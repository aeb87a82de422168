// Coarse occluders by OpenMesh's decimater (plugins/MeshSimplification.h): fewer triangles, the
// same shape within a few per cent, no folds, holes kept where they are.
#include <gtest/gtest.h>

#include "TestScenes.h"
#include "plugins/MeshSimplification.h"
#include "plugins/MeshTopology.h"
#include "plugins/SceneFormats.h"

using namespace sightline;
using namespace sightline::test;

namespace {

Bounds boundsOf(const Mesh& mesh)
{
    Bounds b;
    for (const glm::vec3& p : mesh.positions)
        b.extend(p);
    return b;
}

} // namespace

TEST(MeshSimplification, AClosedTorusKeepsItsShapeAndVolume)
{
    const Mesh torus = closedTorus({1.0, 2.0, 3.0}, 1.0, 0.3, 96, 48, 0.1);
    const MeshTopology before = meshTopology(torus);
    ASSERT_TRUE(before.closedAndOutward());
    for (const std::size_t target : {std::size_t(2000), std::size_t(400)}) {
        const Mesh coarse = simplifiedMesh(torus, target);
        EXPECT_LE(coarse.triangleCount(), target + 2) << target;
        const MeshTopology after = meshTopology(coarse);
        EXPECT_TRUE(after.closedAndOutward()) << target;
        EXPECT_TRUE(coarse.watertight) << target;
        EXPECT_NEAR(after.volume, before.volume, 0.06 * before.volume) << target;
        const Bounds a = boundsOf(torus), b = boundsOf(coarse);
        EXPECT_LT(glm::length(a.min - b.min) + glm::length(a.max - b.max), 0.1) << target;
    }
}

TEST(MeshSimplification, AnOpenScanKeepsItsHoleAndItsSize)
{
    const Mesh bunny = loadScene(std::string(SIGHTLINE_TEST_DATA) + "/meshes/bun_zipper.ply").meshes.at(0);
    const Mesh coarse = simplifiedMesh(bunny, 1500);
    EXPECT_LE(coarse.triangleCount(), 1502u);
    EXPECT_GT(meshTopology(coarse).boundaryEdges, 0u);
    const Bounds a = boundsOf(bunny), b = boundsOf(coarse);
    EXPECT_LT(glm::length(a.min - b.min) + glm::length(a.max - b.max), 0.01);   // of a 15 cm bunny
}

// A halfedge collapse keeps one of its vertices, so on a convex part each coarse face is a chord
// inside the original; the fit onto the original surface takes that bias out: the volume stays
// within a per cent where chords alone lose several.
TEST(MeshSimplification, TheFitKeepsTheVolumeThatChordsWouldLose)
{
    const Mesh torus = closedTorus({0.0, 0.0, 0.0}, 1.0, 0.3, 128, 64, 0.0);
    const double volume = meshTopology(torus).volume;
    for (const std::size_t target : {std::size_t(1000), std::size_t(300)}) {
        const Mesh coarse = simplifiedMesh(torus, target);
        const MeshTopology after = meshTopology(coarse);
        ASSERT_TRUE(after.closedAndOutward()) << target;
        EXPECT_NEAR(after.volume / volume, 1.0, 0.01) << target;
    }
}
