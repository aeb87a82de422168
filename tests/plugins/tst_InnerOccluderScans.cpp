// The conservative coarse occluder (visibility/InnerOccluder.h) on every shared scan, as the
// rays between two patches see it: for each closed scan, in three placements across the shaft,
// no ray of 32x32 x 32x32 is blocked by the inner occluder and left free by the scan itself
// (the exact sampler answers both); the open scans get no inner occluder, with the reason.
#include <algorithm>
#include <cstdint>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "TestFiles.h"
#include "TestScenes.h"
#include "plugins/SceneFormats.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"
#include "visibility/InnerOccluder.h"
#include "visibility/Scene.h"

using namespace sightline;
using sightline::test::testData;

namespace {

/// `mesh` scaled to fit a `size` box, centred at `centre`.
Mesh placed(const Mesh& mesh, glm::vec3 centre, float size)
{
    Bounds box;
    for (const glm::vec3& p : mesh.positions)
        box.extend(p);
    const float scale = size / std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z});
    const glm::vec3 middle = 0.5f * (box.min + box.max);
    Mesh out = mesh;
    for (glm::vec3& p : out.positions)
        p = centre + scale * (p - middle);
    return out;
}

Patch squareAt(double z)
{
    Patch p;
    p.corner = {-1.0, -1.0, z};
    p.u = {2.0, 0.0, 0.0};
    p.v = {0.0, 2.0, 0.0};
    return p;   // 32 x 32 samples
}

} // namespace

TEST(InnerOccluderScans, NoClosedScanBlocksARayItsInnerOccluderDoesNot)
{
    const Patch source = squareAt(0.0), receiver = squareAt(4.0);
    for (const std::string file : {"meshes/armadillo.obj", "meshes/dragon.obj"}) {
        const Mesh scan = loadScene(testData() / file).meshes.at(0);
        ASSERT_TRUE(scan.watertight) << file;
        // Across the middle of the shaft, off to a side (its silhouette across the rays' edge), and
        // near the receiver, large.
        for (const auto& [centre, size] : {std::pair{glm::vec3(0.0f, 0.0f, 2.0f), 1.2f}, std::pair{glm::vec3(0.8f, -0.3f, 1.5f), 1.0f},
                                           std::pair{glm::vec3(-0.2f, 0.4f, 3.2f), 1.6f}}) {
            const Mesh original = placed(scan, centre, size);
            for (const int resolution : {16, 32}) {
                const Mesh inner = innerOccluderMesh(original, resolution);
                ASSERT_GT(inner.triangleCount(), 0u) << file;
                const HiddenSampleMap exact = CpuBitmaskSampler(test::sceneOf({original})).sample(source, receiver);
                const HiddenSampleMap coarse = CpuBitmaskSampler(test::sceneOf({inner})).sample(source, receiver);
                ASSERT_GT(exact.blockedCount(), 1000u) << file;
                std::uint64_t falseBlocked = 0;
                for (int j = 0; j < exact.receiverCount(); ++j)
                    for (int i = 0; i < exact.sourceCount(); ++i)
                        falseBlocked += coarse.blocked(j, i) && !exact.blocked(j, i);
                EXPECT_EQ(falseBlocked, 0u) << file << " at " << centre.x << ", " << centre.y << ", " << centre.z
                                            << ", resolution " << resolution;
                EXPECT_GT(coarse.blockedCount(), 0u) << file;   // and it blocks something
            }
        }
    }
}

TEST(InnerOccluderScans, OpenScansGetNoInnerOccluder)
{
    for (const std::string file : {"meshes/bun_zipper.ply", "meshes/teapot.obj"}) {
        const Mesh scan = loadScene(testData() / file).meshes.at(0);
        ASSERT_FALSE(scan.watertight) << file;
        try {
            (void)innerOccluderMesh(scan, 32);
            ADD_FAILURE() << file << ": an inner occluder of an open mesh";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("closed"), std::string::npos) << e.what();
        }
    }
}
