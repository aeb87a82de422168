// Amortised many-light updates (lighting/LightingCache.h): the view converges to the reference's
// irradiance, refreshes the brightest stale lights first within the budget, moving one light costs
// that light alone, and after an occluder moves only the lights within reach of it go stale and
// the view is exact again within the frames the budget allows.
#include <cmath>
#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "TestLights.h"
#include "TestScenes.h"
#include "lighting/DirectLight.h"
#include "lighting/LightingCache.h"

using namespace sightline;
using namespace sightline::test;

namespace {

struct Room {
    Scene scene;
    std::vector<ShadingPoint> points;
    std::vector<Light> lights;

    explicit Room(const glm::vec3& crate)
    {
        scene = sceneOf({quad({-6, 0, -6}, {12, 0, 0}, {0, 0, 12}, "floor"), randomSoup(5, 200, -4.0f, 4.0f, 0.3f, 2.0f, 0.3f)});
        // The soup lies in x, y in [-4, 4], z in [0.3, 2]: turned so that it hangs over the floor.
        scene.instances[1].transform = glm::rotate(glm::mat4(1.0f), -1.5707963f, glm::vec3(1, 0, 0));
        Mesh box = closedBox();
        box.watertight = false;
        scene.addMeshInstance(box, glm::translate(glm::mat4(1.0f), crate));
        for (int i = 0; i < 30; ++i)
            for (int j = 0; j < 30; ++j)
                points.push_back({{-5.8 + 0.4 * i, 0.01, -5.8 + 0.4 * j}, {0.0, 1.0, 0.0}});
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> x(-5.0, 5.0), y(2.5, 4.0), power(1.0, 20.0);
        for (int k = 0; k < 12; ++k) {
            Light lamp = pointLight({x(rng), y(rng), x(rng)}, power(rng), {1.0, 0.9, 0.7});
            lamp.range = 5.0;
            lights.push_back(lamp);
        }
        Patch panel;
        panel.corner = {-1.0, 4.5, -1.0};
        panel.u = {2.0, 0.0, 0.0};
        panel.v = {0.0, 0.0, 2.0};   // facing down
        panel.na = panel.nb = 3;
        lights.push_back(areaLight(panel, 8.0));
        validateLights(lights, "test");
    }
};

void expectExact(const LightingCache& cache, const LightingScene& scene, const std::vector<Light>& lights,
                 const std::vector<ShadingPoint>& points)
{
    const std::vector<glm::dvec3> reference = directIrradiance(scene, lights, points, {.path = LightingPath::Reference});
    for (std::size_t j = 0; j < points.size(); ++j)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(cache.irradiance()[j][c], reference[j][c], 1e-6 * std::max(reference[j][c], 1e-9)) << j;
}

} // namespace

TEST(LightingCache, ConvergesBrightestFirstAndMovesOneLightAtItsOwnCost)
{
    Room room({3.0f, 0.5f, 3.0f});
    const LightingScene scene(room.scene);
    LightingCache cache(room.points, room.lights);
    // A budget of about three point lights a frame: every light is new, so all are computed in
    // order until the budget is spent.
    const std::uint64_t budget = 3 * room.points.size();
    int frames = 0;
    LightingCache::Frame frame;
    do {
        frame = cache.update(scene, budget);
        ++frames;
        EXPECT_LE(frame.segments, std::max<std::uint64_t>(budget, 9 * room.points.size()));
        EXPECT_EQ(frame.exact, frame.stale == 0);
    } while (!frame.exact && frames < 20);
    EXPECT_TRUE(frame.exact);
    EXPECT_LE(frames, 8);   // 12 lamps x 900 + a 9-sample panel x 900 segments at 2,700 a frame
    expectExact(cache, scene, room.lights, room.points);
    for (const float share : cache.staleness())
        EXPECT_EQ(share, 0.0f);

    // Moving one lamp stales it alone; one frame brings the view back to the exact answer.
    Light moved = room.lights[4];
    moved.position += glm::dvec3(1.5, 0.0, -0.5);
    cache.setLight(4, moved);
    room.lights[4] = moved;
    EXPECT_EQ(cache.staleCount(), 1u);
    bool someStale = false;
    for (const float share : cache.staleness())
        someStale = someStale || share > 0.0f;
    EXPECT_TRUE(someStale);
    frame = cache.update(scene, 1);
    EXPECT_EQ(frame.refreshed, 1u);
    EXPECT_EQ(frame.segments, room.points.size());
    EXPECT_TRUE(frame.exact);
    expectExact(cache, scene, room.lights, room.points);
}

TEST(LightingCache, AnOccluderMovingStalesTheLightsWithinReachAndTheViewConvergesByPriority)
{
    Room before({3.0f, 0.5f, 3.0f});
    const LightingScene oldScene(before.scene);
    LightingCache cache(before.points, before.lights);
    while (!cache.update(oldScene, ~std::uint64_t(0)).exact) {
    }
    // The crate moves across the room: the lamps within 5 m of where it was or is, and the
    // panel (no range), go stale; the rest keep their light.
    Room after({-3.0f, 0.5f, -2.0f});
    const LightingScene newScene(after.scene);
    Bounds was, is;
    was.extend(glm::vec3(2.5f, 0.0f, 2.5f)), was.extend(glm::vec3(3.5f, 1.0f, 3.5f));
    is.extend(glm::vec3(-3.5f, 0.0f, -2.5f)), is.extend(glm::vec3(-2.5f, 1.0f, -1.5f));
    cache.sceneChanged(was);
    cache.sceneChanged(is);
    const std::size_t stale = cache.staleCount();
    EXPECT_GE(stale, 2u);
    EXPECT_LT(stale, after.lights.size());   // lamps out of reach of both places keep their light
    EXPECT_TRUE(cache.isStale(after.lights.size() - 1));   // the panel has no range
    // All went stale together, so the first frame takes the brightest of them.
    double dimmestRefreshed = INFINITY, brightestLeft = 0.0;
    std::vector<double> brightness(after.lights.size());
    for (std::size_t l = 0; l < after.lights.size(); ++l)
        brightness[l] = cache.brightness(l);
    // Two lights a frame: exact again within ceil(stale / 2) frames, brightest first.
    const std::uint64_t budget = 2 * 9 * after.points.size();
    int frames = 0;
    LightingCache::Frame frame;
    do {
        frame = cache.update(newScene, budget);
        if (frames == 0) {
            for (const std::size_t l : frame.lights)
                dimmestRefreshed = std::min(dimmestRefreshed, brightness[l]);
            for (std::size_t l = 0; l < after.lights.size(); ++l)
                if (cache.isStale(l))
                    brightestLeft = std::max(brightestLeft, brightness[l]);
        }
        ++frames;
    } while (!frame.exact && frames < 20);
    EXPECT_GE(dimmestRefreshed, brightestLeft);
    EXPECT_LE(std::size_t(frames), (stale + 1) / 2);
    expectExact(cache, newScene, after.lights, after.points);
}
