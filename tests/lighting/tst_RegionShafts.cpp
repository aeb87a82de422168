// Which points' shadows a change inside some boxes can move (lights/RegionShafts.h): every point
// with a segment to an emitter that meets a box is named (checked segment by segment against the
// boxes, for every kind of light), and points whose segments pass far from the boxes are not.
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "TestLights.h"
#include "lighting/LightEmission.h"
#include "lights/PointTiles.h"
#include "lights/RegionShafts.h"

using namespace sightline;
using namespace sightline::test;

namespace {

/// Whether segment a-b meets the closed box (dense sampling is not exact: this is the slab test
/// written again independently, clipping the parameter range axis by axis).
bool meets(const glm::dvec3& a, const glm::dvec3& b, const Bounds& box)
{
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        const double lo = box.min[k], hi = box.max[k], d = b[k] - a[k];
        if (std::abs(d) < 1e-300) {
            if (a[k] < lo || a[k] > hi)
                return false;
            continue;
        }
        const double ta = (lo - a[k]) / d, tb = (hi - a[k]) / d;
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    return t0 <= t1;
}

} // namespace

TEST(RegionShafts, EveryPointWithASegmentThroughAChangedBoxIsNamedForEveryKindOfLight)
{
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-6.0, 6.0), h(0.0, 3.0);
    std::vector<ShadingPoint> points;
    for (int k = 0; k < 3000; ++k)
        points.push_back({{u(rng), h(rng) * (k % 3 == 0 ? 0.0 : 1.0), u(rng)}, {0.0, 1.0, 0.0}});
    const std::vector<lights::PointTile> tiles = lights::makePointTiles(points);
    Bounds scene;
    scene.extend(glm::vec3(-6.0f, 0.0f, -6.0f)), scene.extend(glm::vec3(6.0f, 4.0f, 6.0f));
    const DirectionalReach reach(scene);   // where the brute force ends a sun's segments

    Patch panel;
    panel.corner = {-1.0, 3.5, -0.5};
    panel.u = {2.0, 0.0, 0.0};
    panel.v = {0.0, 0.0, 1.0};
    panel.na = 4, panel.nb = 3;
    Light ranged = pointLight({2.0, 2.5, -1.0}, 5.0);
    ranged.range = 4.0;
    const std::vector<Light> lights = {pointLight({0.0, 3.0, 0.0}, 5.0), ranged, areaLight(panel, 3.0),
                                       directionalLight({0.3, -1.0, 0.2}, 2.0),
                                       spotLight({-3.0, 3.0, 2.0}, {0.2, -1.0, 0.0}, 0.3, 0.6, 4.0)};
    for (int trial = 0; trial < 6; ++trial) {
        std::vector<Bounds> regions(1 + trial % 2);
        for (Bounds& box : regions) {
            const glm::vec3 c(float(u(rng)) * 0.6f, float(h(rng)), float(u(rng)) * 0.6f);
            box.extend(c - glm::vec3(0.3f, 0.2f, 0.4f)), box.extend(c + glm::vec3(0.5f, 0.3f, 0.2f));
        }
        for (const Light& light : lights) {
            const std::vector<std::uint32_t> named = lights::pointsShadowedThrough(light, regions, tiles, points);
            ASSERT_TRUE(std::is_sorted(named.begin(), named.end()));
            std::vector<Emitter> emitters = lightEmitters({light});
            std::size_t through = 0;
            for (std::size_t j = 0; j < points.size(); ++j) {
                const glm::dvec3& x = points[j].position;
                if (light.range > 0.0 && glm::length(light.position - x) >= light.range)
                    continue;   // no light there either way
                bool any = false;
                for (const Emitter& e : emitters) {
                    const glm::dvec3 end = light.type == LightType::Directional ? reach.end(light, x) : e.position;
                    for (const Bounds& box : regions)
                        any = any || meets(x, end, box);
                }
                if (!any)
                    continue;
                ++through;
                EXPECT_TRUE(std::binary_search(named.begin(), named.end(), std::uint32_t(j)))
                    << "trial " << trial << ", light type " << int(light.type) << ", point " << j;
            }
            // Conservative by a margin, not by naming everything.
            EXPECT_LE(named.size(), through + through / 10 + 10) << "trial " << trial << ", light type " << int(light.type);
        }
    }
}

TEST(RegionShafts, ASunsPointsAreNamedUnderAChangeBeyondTheScenesBounds)
{
    // An occluder taken away 20 m over a 10 m floor: the scene's bounds shrink to the floor, and
    // the sun's segments now end below where it was; the floor under it still goes stale.
    std::vector<ShadingPoint> points;
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 20; ++j)
            points.push_back({{-4.75 + 0.5 * i, 0.01, -4.75 + 0.5 * j}, {0.0, 1.0, 0.0}});
    const std::vector<lights::PointTile> tiles = lights::makePointTiles(points);
    Bounds slab;
    slab.extend(glm::vec3(-1.0f, 20.0f, -1.0f)), slab.extend(glm::vec3(1.0f, 20.5f, 1.0f));
    const Light sun = directionalLight({0.0, -1.0, 0.0}, 2.0);
    const std::vector<std::uint32_t> named = lights::pointsShadowedThrough(sun, std::vector<Bounds>{slab}, tiles, points);
    std::size_t under = 0;
    for (std::size_t j = 0; j < points.size(); ++j) {
        const bool below = std::abs(points[j].position.x) <= 1.0 && std::abs(points[j].position.z) <= 1.0;
        under += below ? 1 : 0;
        if (below) {
            EXPECT_TRUE(std::binary_search(named.begin(), named.end(), std::uint32_t(j))) << j;
        }
    }
    EXPECT_EQ(under, 16u);
    EXPECT_LT(named.size(), points.size() / 4);
}
