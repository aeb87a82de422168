// Amortised many-light updates (lighting/LightingCache.h): the view converges to the reference's
// irradiance, refreshes the brightest stale lights first within the budget, moving one light costs
// that light alone, and after an occluder moves only the lights within reach of it go stale and
// the view is exact again within the frames the budget allows.
#include <algorithm>
#include <cmath>
#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "TestLights.h"
#include "TestScenes.h"
#include "lighting/DirectLight.h"
#include "lighting/LightEmission.h"
#include "lighting/LightingCache.h"
#include "lighting/LowResolutionPass.h"
#include "lighting/SceneChange.h"
#include "base/Error.h"

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

/// A plan with no low-resolution pass (no light is dragged).
LowResolutionPlan noPlan(std::size_t points)
{
    LowResolutionPlan plan;
    plan.points = points;
    return plan;
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

TEST(LightingCache, AnOccluderMovingStalesThePointsItsShadowsCouldReachAndTheViewConvergesByPriority)
{
    Room before({3.0f, 0.5f, 3.0f});
    const LightingScene oldScene(before.scene);
    LightingCache cache(before.points, before.lights);
    while (!cache.update(oldScene, ~std::uint64_t(0)).exact) {
    }
    // The crate moves across the room: the regions are where it was and where it is.
    Room after({-3.0f, 0.5f, -2.0f});
    const LightingScene newScene(after.scene);
    const std::vector<Bounds> regions = changedRegions(worldTriangles(before.scene), worldTriangles(after.scene));
    ASSERT_EQ(regions.size(), 2u);
    EXPECT_NEAR(regions[0].min.x, 2.5f, 1e-6f);
    EXPECT_NEAR(regions[0].max.z, 3.5f, 1e-6f);
    EXPECT_NEAR(regions[1].min.x, -3.5f, 1e-6f);
    EXPECT_NEAR(regions[1].max.z, -1.5f, 1e-6f);
    EXPECT_NEAR(regions[1].max.y, 1.0f, 1e-6f);
    cache.sceneChanged(regions);
    const std::size_t stale = cache.staleCount();
    EXPECT_GE(stale, 2u);
    EXPECT_LT(stale, after.lights.size());   // lamps whose range no shadow segment through the region is in keep their light
    EXPECT_TRUE(cache.isStale(after.lights.size() - 1));   // the panel has no range
    // Stale where a shadow may have moved, not everywhere.
    const std::vector<float> share = cache.staleness();
    const auto staleShare = std::count(share.begin(), share.end(), 1.0f);
    EXPECT_GT(staleShare, 0);
    EXPECT_LT(staleShare, std::ptrdiff_t(after.points.size()));
    std::vector<double> brightness(after.lights.size());
    for (std::size_t l = 0; l < after.lights.size(); ++l)
        brightness[l] = cache.brightness(l);
    // Two stale lights' worth of whole refreshes a frame: the partial refreshes cost less, so the
    // view is exact again within ceil(stale / 2) frames, brightest first.
    const std::uint64_t budget = 2 * 9 * after.points.size();
    int frames = 0;
    std::uint64_t segments = 0;
    double dimmestRefreshed = INFINITY, brightestLeft = 0.0;
    LightingCache::Frame frame;
    do {
        frame = cache.update(newScene, budget);
        segments += frame.segments;
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
    // Less than refreshing every stale light whole.
    EXPECT_LT(segments, std::uint64_t(stale - 1 + 9) * after.points.size());
    expectExact(cache, newScene, after.lights, after.points);
    for (const float s : cache.staleness())
        EXPECT_EQ(s, 0.0f);
}

TEST(LightingCache, PointsThatCameWithTheSceneAreLitAndThoseThatStayedKeepTheirLight)
{
    // The crate's top carries points of its own (as an occluder carries texels): moving it takes
    // them away and brings new ones.
    const auto withTop = [](Room& room, const glm::dvec3& crate) {
        std::vector<ShadingPoint> points = room.points;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                points.push_back({crate + glm::dvec3(-0.375 + 0.25 * i, 0.51, -0.375 + 0.25 * j), {0.0, 1.0, 0.0}});
        return points;
    };
    Room before({3.0f, 0.5f, 3.0f});
    const std::vector<ShadingPoint> oldPoints = withTop(before, {3.0, 0.5, 3.0});
    const LightingScene oldScene(before.scene);
    LightingCache cache(oldPoints, before.lights);
    while (!cache.update(oldScene, ~std::uint64_t(0)).exact) {
    }
    Room after({-3.0f, 0.5f, -2.0f});
    const std::vector<ShadingPoint> newPoints = withTop(after, {-3.0, 0.5, -2.0});
    const LightingScene newScene(after.scene);
    const std::vector<std::size_t> previous = matchPoints(oldPoints, newPoints);
    std::size_t kept = 0;
    for (std::size_t j = 0; j < previous.size(); ++j) {
        EXPECT_EQ(previous[j] != SIZE_MAX, j < after.points.size()) << j;
        kept += previous[j] == j ? 1 : 0;
    }
    EXPECT_EQ(kept, after.points.size());
    cache.sceneChanged(changedRegions(worldTriangles(before.scene), worldTriangles(after.scene)), newPoints, previous,
                       noPlan(newPoints.size()));
    EXPECT_EQ(cache.points().size(), newPoints.size());
    EXPECT_EQ(cache.staleCount(), after.lights.size());   // every light has new points to light
    for (std::size_t j = after.points.size(); j < newPoints.size(); ++j)
        EXPECT_EQ(cache.irradiance()[j], glm::dvec3(0.0));   // nothing shown there yet
    while (!cache.update(newScene, ~std::uint64_t(0)).exact) {
    }
    expectExact(cache, newScene, after.lights, newPoints);
    // Mismatched indices are refused.
    std::vector<std::size_t> wrong(newPoints.size(), SIZE_MAX);
    wrong[0] = newPoints.size() + 5;
    EXPECT_THROW(cache.sceneChanged({}, newPoints, wrong, noPlan(newPoints.size())), Error);
    EXPECT_THROW(cache.sceneChanged({}, newPoints, std::vector<std::size_t>(3, SIZE_MAX),
                                    noPlan(newPoints.size())),
                 Error);
    EXPECT_THROW(cache.sceneChanged({}, newPoints, std::vector<std::size_t>(newPoints.size(), SIZE_MAX), noPlan(5)), Error);
    // Refused, the cache is as it was: still exact, and it goes on.
    expectExact(cache, newScene, after.lights, newPoints);
    Light moved = after.lights[0];
    moved.position.x += 0.5;
    cache.setLight(0, moved);
    after.lights[0] = moved;
    while (!cache.update(newScene, ~std::uint64_t(0)).exact) {
    }
    expectExact(cache, newScene, after.lights, newPoints);
}

TEST(SceneChange, TheRegionHoldsWhatEitherSideLacksAndPointsMatchBitForBit)
{
    Room a({3.0f, 0.5f, 3.0f}), b({3.0f, 0.5f, 3.0f});
    EXPECT_TRUE(changedRegions(worldTriangles(a.scene), worldTriangles(b.scene)).empty());
    // Instances listed in another order hold the same triangles.
    std::swap(b.scene.instances[0], b.scene.instances[2]);
    EXPECT_TRUE(changedRegions(worldTriangles(a.scene), worldTriangles(b.scene)).empty());
    // A removed instance: the region is its box.
    Scene fewer = a.scene;
    fewer.instances.pop_back();
    const std::vector<Bounds> regions = changedRegions(worldTriangles(a.scene), worldTriangles(fewer));
    ASSERT_EQ(regions.size(), 1u);
    const Bounds& gone = regions[0];
    EXPECT_NEAR(gone.min.x, 2.5f, 1e-6f);
    EXPECT_NEAR(gone.max.z, 3.5f, 1e-6f);
    EXPECT_NEAR(gone.min.y, 0.0f, 1e-6f);

    std::vector<ShadingPoint> p = {{{1, 2, 3}, {0, 1, 0}}, {{1, 2, 3}, {0, 1, 0}}, {{4, 5, 6}, {1, 0, 0}}};
    std::vector<ShadingPoint> q = {{{4, 5, 6}, {1, 0, 0}}, {{1, 2, 3}, {0, 1, 0}}, {{1, 2, 3}, {0, 1, 0}},
                                   {{1, 2, 3}, {0, 1, 0}}, {{4, 5, 6 + 1e-12}, {1, 0, 0}}, {{4, 5, 6}, {0, 1, 0}}};
    const std::vector<std::size_t> m = matchPoints(p, q);
    ASSERT_EQ(m.size(), q.size());
    EXPECT_EQ(m[0], 2u);
    EXPECT_TRUE((m[1] == 0 && m[2] == 1) || (m[1] == 1 && m[2] == 0));
    EXPECT_EQ(m[3], SIZE_MAX);   // each old point once
    EXPECT_EQ(m[4], SIZE_MAX);   // bit for bit
    EXPECT_EQ(m[5], SIZE_MAX);   // the normal too
}

namespace {

/// One tile of `width` x `height` texels whose texel (s, t) is point t * width + s, and the
/// texels' coordinates by point.
struct Tiles {
    AoTexelLayout layout;
    std::vector<std::size_t> pointOfTexel;
    std::vector<glm::vec2> texelOfPoint;

    void add(int width, int height, std::size_t missing = SIZE_MAX)
    {
        AoTexelTile tile;
        tile.width = width;
        tile.height = height;
        tile.firstPoint = pointOfTexel.size();
        layout.tiles.push_back(tile);
        for (int t = 0; t < height; ++t)
            for (int s = 0; s < width; ++s) {
                if (pointOfTexel.size() - tile.firstPoint == missing) {
                    pointOfTexel.push_back(SIZE_MAX);
                    continue;
                }
                pointOfTexel.push_back(texelOfPoint.size());
                texelOfPoint.push_back({float(s), float(t)});
            }
    }
};

} // namespace

TEST(LowResolutionPass, EveryTexelIsCoarseOrInterpolatedFromFourCoarseCornersOfItsTile)
{
    Tiles tiles;
    tiles.add(30, 30);
    tiles.add(1, 5);      // a line: all exact
    tiles.add(3, 3, 4);   // its centre texel missing
    tiles.add(7, 4);
    tiles.add(0, 0);      // degenerate
    for (const int stride : {2, 3, 5}) {
        const LowResolutionPlan plan = lowResolutionPlan(tiles.layout, tiles.pointOfTexel, stride);
        ASSERT_EQ(plan.points, tiles.texelOfPoint.size());
        std::vector<int> seen(plan.points, 0);
        std::vector<bool> coarse(plan.points, false);
        for (const std::uint32_t p : plan.coarse) {
            ++seen.at(p);
            coarse[p] = true;
        }
        for (const LowResolutionPlan::Block& block : plan.blocks) {
            ASSERT_GT(block.count, 0u);
            for (const std::uint32_t c : block.corners)
                EXPECT_TRUE(coarse.at(c));
            for (std::uint32_t k = block.first; k < block.first + block.count; ++k) {
                const LowResolutionPlan::Fine& fine = plan.fine.at(k);
                ++seen.at(fine.point);
                // Bilinear weights: they sum to one and give back the texel's own place.
                glm::vec2 at(0.0f);
                float sum = 0.0f;
                for (std::size_t c = 0; c < 4; ++c) {
                    EXPECT_GE(fine.weights[c], 0.0f);
                    sum += fine.weights[c];
                    at += fine.weights[c] * tiles.texelOfPoint[block.corners[c]];
                }
                EXPECT_NEAR(sum, 1.0f, 1e-6f);
                EXPECT_NEAR(at.x, tiles.texelOfPoint[fine.point].x, 1e-5f);
                EXPECT_NEAR(at.y, tiles.texelOfPoint[fine.point].y, 1e-5f);
            }
        }
        for (std::size_t p = 0; p < plan.points; ++p)
            EXPECT_EQ(seen[p], 1) << "point " << p << " at stride " << stride;
        EXPECT_LT(plan.coarse.size(), plan.points / 2) << stride;   // the big tile is mostly interpolated
    }
    EXPECT_THROW(lowResolutionPlan(tiles.layout, tiles.pointOfTexel, 1), Error);
}

TEST(LowResolutionPass, TexelsOfSmallTilesShareACoarsePointPerCubeAndFacing)
{
    // A big tile, then 400 one- and two-texel tiles (a plant's leaves) scattered over a 2 m cube
    // with random normals, and a line of 9 texels.
    Tiles tiles;
    tiles.add(12, 12);
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> size(1, 2);
    for (int k = 0; k < 400; ++k)
        tiles.add(size(rng), size(rng));
    tiles.add(9, 1);
    tiles.layout.density = 4.0;   // texels per metre: cubes of 2 / 4 = 0.5 m at stride 2
    std::uniform_real_distribution<double> u(0.0, 2.0), n(-1.0, 1.0);
    std::vector<ShadingPoint> points(tiles.texelOfPoint.size());
    for (std::size_t p = 0; p < points.size(); ++p) {
        points[p].position = {u(rng), u(rng), u(rng)};
        points[p].normal = glm::normalize(glm::dvec3(n(rng), n(rng), n(rng)) + glm::dvec3(1e-9));
    }
    const std::size_t big = 144;   // the big tile's points come first: laid out as a plane
    for (std::size_t p = 0; p < big; ++p)
        points[p] = {{0.25 * tiles.texelOfPoint[p].x, 0.0, 0.25 * tiles.texelOfPoint[p].y}, {0.0, 1.0, 0.0}};
    const LowResolutionPlan plain = lowResolutionPlan(tiles.layout, tiles.pointOfTexel, 2);
    const LowResolutionPlan plan = lowResolutionPlan(tiles.layout, tiles.pointOfTexel, 2, points);
    ASSERT_EQ(plan.points, points.size());
    std::vector<int> seen(plan.points, 0);
    for (const std::uint32_t p : plan.coarse)
        ++seen.at(p);
    const auto cube = [&](std::uint32_t p) {
        const glm::dvec3 a = glm::abs(points[p].normal);
        const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
        return std::array<int, 5>{int(std::floor(points[p].position.x / 0.5)), int(std::floor(points[p].position.y / 0.5)),
                                  int(std::floor(points[p].position.z / 0.5)), axis, points[p].normal[axis] < 0.0 ? 1 : 0};
    };
    std::size_t copies = 0;
    for (const LowResolutionPlan::Block& block : plan.blocks)
        for (std::uint32_t k = block.first; k < block.first + block.count; ++k) {
            const LowResolutionPlan::Fine& fine = plan.fine.at(k);
            ++seen.at(fine.point);
            if (fine.point < big)
                continue;   // the big tile's blocks are bilinear, as without the points
            // A copy of its group's first point: same cube, same facing.
            EXPECT_EQ(block.corners[0], block.corners[3]);
            EXPECT_EQ(fine.weights[0], 1.0f);
            EXPECT_EQ(cube(fine.point), cube(block.corners[0]));
            EXPECT_EQ(std::count(plan.coarse.begin(), plan.coarse.end(), block.corners[0]), 1);
            ++copies;
        }
    for (std::size_t p = 0; p < plan.points; ++p)
        EXPECT_EQ(seen[p], 1) << "point " << p;
    // The small tiles' texels: every one coarse without the points, one per group with them.
    EXPECT_GT(copies, 100u);
    EXPECT_EQ(plan.coarse.size() + copies, plain.coarse.size());
    EXPECT_THROW(lowResolutionPlan(tiles.layout, tiles.pointOfTexel, 2, std::span(points).first(10)), Error);
}

TEST(LightingCache, ADraggedLightTakesTheLowResolutionPassThenTheExactOne)
{
    Room room({3.0f, 0.5f, 3.0f});
    const LightingScene scene(room.scene);
    Tiles tiles;
    tiles.add(30, 30);   // the room's 30 x 30 floor points, row by row
    ASSERT_EQ(tiles.texelOfPoint.size(), room.points.size());
    LightingCache cache(room.points, room.lights, lowResolutionPlan(tiles.layout, tiles.pointOfTexel, 2));
    const LowResolutionPlan plan = lowResolutionPlan(tiles.layout, tiles.pointOfTexel, 2);
    while (!cache.update(scene, ~std::uint64_t(0)).exact) {
    }

    // The panel (3 x 3 samples) is dragged over the crate's shadow: its low-resolution pass
    // samples it 2 x 2, exactly at the coarse points and in the blocks whose corners disagree.
    const std::size_t panel = room.lights.size() - 1;
    Light moved = room.lights[panel];
    moved.area.corner += glm::dvec3(2.0, 0.0, 1.5);
    room.lights[panel] = moved;
    cache.setLight(panel, moved, /*rough=*/true);
    LightingCache::Frame frame = cache.update(scene, ~std::uint64_t(0));
    EXPECT_EQ(frame.rough, 1u);
    EXPECT_EQ(frame.refreshed, 1u);
    EXPECT_FALSE(frame.exact);
    EXPECT_TRUE(cache.isStale(panel));
    Light rough = moved;
    rough.colour = glm::dvec3(1.0);
    rough.area.na = rough.area.nb = 2;
    const std::vector<glm::dvec3> reference = directIrradiance(scene, {rough}, room.points, {.path = LightingPath::Reference});
    const std::vector<float>& field = cache.field(panel);
    const auto near = [&](std::uint32_t p) { EXPECT_NEAR(field[p], reference[p].x, 1e-5 * std::max(reference[p].x, 1e-9)) << p; };
    for (const std::uint32_t p : plan.coarse)
        near(p);
    std::size_t refined = 0, interpolated = 0;
    for (const LowResolutionPlan::Block& block : plan.blocks) {
        std::array<float, 4> corner{};
        for (std::size_t c = 0; c < 4; ++c)
            corner[c] = field[block.corners[c]];
        const bool edge = cornersDisagree(corner);
        for (std::uint32_t k = block.first; k < block.first + block.count; ++k) {
            const std::uint32_t p = plan.fine[k].point;
            if (edge) {
                near(p);
                ++refined;
            } else {   // between its corners
                EXPECT_GE(field[p], *std::min_element(corner.begin(), corner.end()) - 1e-6f);
                EXPECT_LE(field[p], *std::max_element(corner.begin(), corner.end()) + 1e-6f);
                ++interpolated;
            }
        }
    }
    EXPECT_GT(refined, 0u);        // the crate's shadow has edges
    EXPECT_GT(interpolated, 0u);   // and the open floor is smooth
    EXPECT_EQ(frame.segments, 4u * (plan.coarse.size() + refined));

    // Let go: the next frame refreshes it exactly, and the view is the reference's.
    frame = cache.update(scene, ~std::uint64_t(0));
    EXPECT_EQ(frame.rough, 0u);
    EXPECT_TRUE(frame.exact);
    expectExact(cache, scene, room.lights, room.points);
}

TEST(LightingCache, EachLightsCostCountsItsTermsAndRaysAndItsAge)
{
    Room room({3.0f, 0.5f, 3.0f});
    const LightingScene scene(room.scene);
    Tiles tiles;
    tiles.add(30, 30);
    LightingCache cache(room.points, room.lights, lowResolutionPlan(tiles.layout, tiles.pointOfTexel, 2));
    while (!cache.update(scene, ~std::uint64_t(0)).exact) {
    }
    // Terms: the (point, sample) pairs each light reaches before shadows, counted independently.
    const std::vector<Emitter> emitters = lightEmitters(room.lights);
    std::vector<std::uint64_t> terms(room.lights.size(), 0);
    for (const Emitter& e : emitters)
        for (const ShadingPoint& p : room.points)
            terms[e.light] += emitterTerm(room.lights[e.light], e.position, p.position, p.normal) > 0.0 ? 1 : 0;
    std::uint64_t rays = 0;
    for (std::size_t l = 0; l < room.lights.size(); ++l) {
        const LightingCache::LightCost cost = cache.cost(l);
        EXPECT_EQ(cost.samples, room.lights[l].sampleCount());
        EXPECT_EQ(cost.terms, terms[l]) << l;
        EXPECT_LE(cost.rays, cost.terms);
        EXPECT_FALSE(cost.stale);
        EXPECT_FALSE(cost.rough);
        EXPECT_EQ(cost.age, 0u);   // all refreshed in the one frame an unlimited budget allows
        EXPECT_GE(cost.ms, 0.0);
        rays += cost.rays;
    }
    EXPECT_GT(rays, 0u);   // the soup and the crate are in the way of some

    // Dragged, the panel shows the low-resolution pass; the others age a frame.
    const std::size_t panel = room.lights.size() - 1;
    cache.setLight(panel, room.lights[panel], /*rough=*/true);
    cache.update(scene, ~std::uint64_t(0));
    EXPECT_TRUE(cache.cost(panel).rough);
    EXPECT_TRUE(cache.cost(panel).stale);
    EXPECT_EQ(cache.cost(0).age, 1u);
    cache.update(scene, ~std::uint64_t(0));
    EXPECT_FALSE(cache.cost(panel).rough);
    EXPECT_EQ(cache.cost(panel).age, 0u);
    EXPECT_EQ(cache.cost(panel).terms, terms[panel]);
    EXPECT_EQ(cache.cost(0).age, 2u);
}
