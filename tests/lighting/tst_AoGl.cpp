// The paper-faithful GL mode (a depth map per direction, bits set by a compute shader) against the
// exact CPU mode, with an explicit tolerance: a bit may differ only where the depth map's
// resolution or its bias explains it (AoGlCaster.h): a GL-visible, CPU-blocked bit must become
// visible when the origin rises by the bias plus a texel towards the light; a GL-blocked,
// CPU-visible bit must become blocked when the origin moves by at most a texel in the map's plane.
#include <cmath>

#include <gtest/gtest.h>

#include "GlContextTest.h"
#include "TestScenes.h"
#include "lighting/ao/AoBinnedCaster.h"
#include "lighting/ao/AoEmbree.h"
#include "lighting/ao/AoGlCaster.h"
#include "lighting/ao/AoShading.h"

using namespace sightline;

namespace {

class AoGl : public test::GlContextTest {};

Scene clutter()
{
    Scene scene = test::sceneOf({test::quad({-3.0f, 0.0f, -3.0f}, {0.0f, 0.0f, 6.0f}, {6.0f, 0.0f, 0.0f}, "floor"),
                                 test::quad({1.5f, 0.0f, -3.0f}, {0.0f, 2.0f, 0.0f}, {0.0f, 0.0f, 6.0f}, "wall")});
    scene.addMeshInstance(test::closedBox(), glm::mat4(1.0f));
    return scene;
}

void basisOf(const glm::vec3& d, glm::vec3& u, glm::vec3& v)   // any basis: only the shifts' lengths matter
{
    const glm::vec3 helper = std::abs(d.x) < 0.6f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    u = glm::normalize(glm::cross(helper, d));
    v = glm::cross(d, u);
}

} // namespace

TEST_F(AoGl, AgreesWithTheExactCpuModeWithinDepthMapResolutionAndBias)
{
    const Scene scene = clutter();
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points = aoVertexPoints(scene);
    for (int x = 0; x < 20; ++x)   // and a grid on the floor
        for (int z = 0; z < 20; ++z) {
            points.positions.push_back({-2.8f + 0.29f * x, 0.0f, -2.7f + 0.28f * z});
            points.normals.push_back({0, 1, 0});
            points.status.push_back(AoPointStatus::Ok);
        }
    points.offsetOrigins(kAoOffsetRelative * occluders.diagonal());
    const int k = 258;
    const AoDirectionSet& set = aoDirections(k);
    AoGlCaster gl(context->functions(), occluders, {.resolution = 1024});
    AoBinnedCaster cpu(occluders);
    VisibilityMatrix a(points.size(), k), b(points.size(), k);
    ASSERT_TRUE(gl.fill(points, set, 0, k, a));
    ASSERT_TRUE(cpu.fill(points, set, 0, k, b));
    const AoEmbreeScene judge(occluders);
    std::size_t differ = 0, unexplained = 0;
    const double texel = gl.texelSize();
    for (std::size_t i = 0; i < points.size(); ++i)
        for (int j = 0; j < k; ++j) {
            if (a.visible(i, j) == b.visible(i, j))
                continue;
            ++differ;
            const glm::vec3 d = set.directions[std::size_t(j)];
            const glm::vec3 o = points.origins[i];
            // The GL answer must be the exact answer for the origin moved within the tolerance:
            // raised towards the light by up to the bias plus a texel, and/or moved in the map's
            // plane by up to one texel (8 directions).
            const float rise = float(gl.bias(glm::dot(points.normals[i], d)) + texel);
            glm::vec3 u, v;
            basisOf(d, u, v);
            bool explained = false;
            for (int s = 0; s <= 8 && !explained; ++s) {
                const float angle = float(s) * 0.785398f;
                const glm::vec3 shift = s == 8 ? glm::vec3(0.0f) : float(texel) * (std::cos(angle) * u + std::sin(angle) * v);
                for (float up : {0.0f, rise})
                    explained = explained || judge.unblocked(o + shift + up * d, d) == a.visible(i, j);
            }
            if (!explained)
                ADD_FAILURE() << "GL " << (a.visible(i, j) ? "visible" : "blocked") << ", CPU not: point " << i
                              << " direction " << j << " cos " << glm::dot(points.normals[i], d);
            unexplained += !explained;
        }
    EXPECT_EQ(unexplained, 0u) << differ << " bits differ";
    EXPECT_LT(double(differ), 0.02 * double(b.visibleCount(k)));
    // And the AO itself: mean difference well under 1%.
    const std::vector<float> aoGl = ambientOcclusion(a, points, k), aoCpu = ambientOcclusion(b, points, k);
    double sum = 0.0;
    for (std::size_t i = 0; i < aoGl.size(); ++i)
        sum += std::abs(aoGl[i] - aoCpu[i]);
    EXPECT_LT(sum / double(aoGl.size()), 0.01);
}

TEST_F(AoGl, ChunksGiveTheSameBitsAsOneCall)
{
    // d and -d share one render; a chunk boundary between them must not change either's bits.
    const Scene scene = clutter();
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points = aoVertexPoints(scene);
    points.offsetOrigins(kAoOffsetRelative * occluders.diagonal());
    const int k = 66;
    const AoDirectionSet& set = aoDirections(k);
    AoGlCaster gl(context->functions(), occluders, {.resolution = 256});
    VisibilityMatrix whole(points.size(), k), chunked(points.size(), k);
    ASSERT_TRUE(gl.fill(points, set, 0, k, whole));
    for (int first = 0; first < k; first += 7)
        ASSERT_TRUE(gl.fill(points, set, first, std::min(k, first + 7), chunked));
    ASSERT_GT(whole.visibleCount(k), 0u);
    for (std::size_t i = 0; i < points.size(); ++i)
        for (int j = 0; j < k; ++j)
            ASSERT_EQ(whole.visible(i, j), chunked.visible(i, j)) << "point " << i << " direction " << j;
}
