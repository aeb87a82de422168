// The light tree's cuts (lighting/LightTree.h): every point light counted once, clusters that
// carry their lights' total, an error that goes to zero with the threshold, and shadows still
// cast by each stand-in.

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "TestLights.h"
#include "TestScenes.h"
#include "lighting/DirectLight.h"
#include "lighting/LightTree.h"
#include "base/Error.h"

using namespace sightline;
using namespace sightline::test;

namespace {

/// `count` coloured lamps over a 20 m x 20 m floor, 1.5-3 m up, with a spot and a sun that stay exact.
std::vector<Light> lamps(int count, double range, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> x(-10.0, 10.0), y(1.5, 3.0), power(0.5, 5.0), tint(0.3, 1.0);
    std::vector<Light> lights;
    for (int k = 0; k < count; ++k) {
        Light lamp = pointLight({x(rng), y(rng), x(rng)}, power(rng), {tint(rng), tint(rng), tint(rng)});
        lamp.range = range;
        lights.push_back(lamp);
    }
    lights.push_back(spotLight({0.0, 4.0, 0.0}, {0.0, -1.0, 0.0}, 0.2, 0.6, 30.0));
    lights.push_back(directionalLight({0.3, -1.0, 0.2}, 1.5));
    validateLights(lights, "test");
    return lights;
}

std::vector<ShadingPoint> floorPoints(int side)
{
    std::vector<ShadingPoint> points;
    for (int i = 0; i < side; ++i)
        for (int j = 0; j < side; ++j)
            points.push_back({{-9.9 + 19.8 * (i + 0.5) / side, 0.01, -9.9 + 19.8 * (j + 0.5) / side}, {0.0, 1.0, 0.0}});
    return points;
}

double largestRelative(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b)
{
    double worst = 0.0;
    for (std::size_t j = 0; j < a.size(); ++j)
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(a[j][c] - b[j][c]) / std::max(b[j][c], 1e-12));
    return worst;
}

} // namespace

TEST(LightTree, ACutCountsEveryPointLightOnceAndItsClustersCarryTheirTotal)
{
    const std::vector<Light> lights = lamps(300, 0.0, 3);
    const LightTree tree(lights);
    EXPECT_EQ(tree.size(), 300u);
    EXPECT_TRUE(tree.clusters(0));
    EXPECT_FALSE(tree.clusters(300));   // the spot
    EXPECT_FALSE(tree.clusters(301));   // the sun
    std::vector<LightTree::Entry> cut;
    for (const double error : {1.0, 0.1, 0.01, 0.001}) {
        tree.cut({-1.0, 0.0, -1.0}, {1.0, 0.01, 1.0}, error, 100000, cut);
        std::uint32_t counted = 0;
        glm::dvec3 total(0.0);
        for (const LightTree::Entry& entry : cut) {
            counted += entry.count;
            total += entry.standIn.intensity * entry.standIn.colour;
            if (entry.count == 1) {   // a single light exactly as it is
                EXPECT_EQ(entry.standIn.position, lights[entry.representative].position);
                EXPECT_EQ(entry.standIn.colour, lights[entry.representative].colour);
            }
        }
        EXPECT_EQ(counted, 300u) << error;   // no range: none is dropped, none twice
        glm::dvec3 expected(0.0);
        for (std::size_t l = 0; l < 300; ++l)
            expected += lights[l].intensity * lights[l].colour;
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(total[c], expected[c], 1e-9 * expected[c]) << error;
    }
    // A smaller error never gives a coarser cut; a limit on the entries is kept.
    tree.cut({-1.0, 0.0, -1.0}, {1.0, 0.01, 1.0}, 0.1, 100000, cut);
    const std::size_t coarse = cut.size();
    tree.cut({-1.0, 0.0, -1.0}, {1.0, 0.01, 1.0}, 0.01, 100000, cut);
    EXPECT_GT(cut.size(), coarse);
    tree.cut({-1.0, 0.0, -1.0}, {1.0, 0.01, 1.0}, 1e-9, 40, cut);
    EXPECT_LE(cut.size(), 40u);
}

TEST(LightTree, LampsBeyondTheirRangeLeaveTheCut)
{
    std::vector<Light> lights = {pointLight({0.0, 2.0, 0.0}, 5.0), pointLight({30.0, 2.0, 0.0}, 5.0)};
    lights[0].range = lights[1].range = 4.0;
    validateLights(lights, "test");
    const LightTree tree(lights);
    std::vector<LightTree::Entry> cut;
    tree.cut({-1.0, 0.0, -1.0}, {1.0, 0.0, 1.0}, 1e-6, 100, cut);
    ASSERT_EQ(cut.size(), 1u);
    EXPECT_EQ(cut[0].representative, 0u);
    EXPECT_EQ(cut[0].count, 1u);
}

TEST(LightTree, ItsErrorGoesToZeroWithTheThresholdAndItCastsFewerSegments)
{
    const Scene scene = sceneOf({quad({-10, 0, -10}, {20, 0, 0}, {0, 0, 20}, "floor")});
    const LightingScene lighting(scene);
    const std::vector<Light> lights = lamps(600, 6.0, 5);
    const std::vector<ShadingPoint> points = floorPoints(48);
    DirectLightStats exactStats;
    const std::vector<glm::dvec3> exact = directIrradiance(lighting, lights, points, {}, &exactStats);
    // A threshold far below any cluster's share: every light alone, the exact sum up to its order.
    DirectLightStats fine;
    const std::vector<glm::dvec3> all = directIrradiance(lighting, lights, points, {.lightCutError = 1e-12}, &fine);
    EXPECT_EQ(fine.cutClusters, 0u);
    EXPECT_LT(largestRelative(all, exact), 1e-12);
    // Coarser cuts: a smaller error at a larger threshold, never zero work saved.
    double previous = 0.0;
    for (const double error : {0.003, 0.03, 0.3}) {
        DirectLightStats stats;
        const std::vector<glm::dvec3> cut = directIrradiance(lighting, lights, points, {.lightCutError = error}, &stats);
        EXPECT_GT(stats.cutClusters, 0u) << error;
        EXPECT_LT(stats.terms, exactStats.terms) << error;
        double mean = 0.0;
        for (std::size_t j = 0; j < points.size(); ++j)
            mean += std::abs(cut[j].y - exact[j].y) / exact[j].y;
        mean /= double(points.size());
        EXPECT_LT(mean, error) << error;   // open floor: no shadow to misjudge
        EXPECT_GE(mean, previous) << error;
        previous = mean;
    }
}

TEST(LightTree, EachStandInStillCastsItsShadow)
{
    // A lamp cluster over a sealed box: nothing of it reaches the floor inside.
    Scene scene = sceneOf({quad({-10, 0, -10}, {20, 0, 0}, {0, 0, 20}, "floor")});
    // The unit box [-0.5, 0.5]^3 made x, z in [-2.2, 2.2], y in [-0.5, 1].
    scene.addMeshInstance(closedBox(), glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.25f, 0.0f)), glm::vec3(4.4f, 1.5f, 4.4f)));
    const LightingScene lighting(scene);
    std::vector<Light> lights;
    for (int k = 0; k < 64; ++k)
        lights.push_back(pointLight({-8.0 + 0.25 * (k % 8), 3.0, -8.0 + 0.25 * (k / 8)}, 2.0));
    validateLights(lights, "test");
    std::vector<ShadingPoint> inside;
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j)
            inside.push_back({{-1.9 + 0.24 * i, 0.01, -1.9 + 0.24 * j}, {0.0, 1.0, 0.0}});
    DirectLightStats stats;
    for (const glm::dvec3& e : directIrradiance(lighting, lights, inside, {.lightCutError = 0.5}, &stats))
        EXPECT_EQ(e, glm::dvec3(0.0));
    EXPECT_GT(stats.cutClusters, 0u);
}

TEST(LightTree, ABadThresholdIsRefused)
{
    const Scene scene = sceneOf({quad({-1, 0, -1}, {2, 0, 0}, {0, 0, 2}, "floor")});
    const LightingScene lighting(scene);
    const std::vector<Light> lights = lamps(4, 0.0, 1);
    const std::vector<ShadingPoint> points = floorPoints(2);
    for (const double bad : {-0.1, std::nan(""), double(INFINITY)})
        EXPECT_THROW(directIrradiance(lighting, lights, points, {.lightCutError = bad}), Error) << bad;
}
