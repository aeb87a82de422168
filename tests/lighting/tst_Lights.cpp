// Many lights, direct and shadowed (docs/lights.md): closed forms (the inverse-square law, a disc's
// shadow edge, a rectangle's form factor, a sealed room, a wall), and both paths, the reference
// and the fast one, judged point by point by an independent brute force (LightsJudge.h) on random
// and adversarial scenes, near the origin and 10 km from it.
#include <cmath>
#include <numbers>
#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "LightsJudge.h"
#include "TestLights.h"
#include "TestScenes.h"
#include "lighting/DirectLight.h"
#include "lighting/Light.h"
#include "base/Error.h"

using namespace sightline;
using namespace sightline::test;

namespace {

std::vector<glm::dvec3> irradiance(const LightingScene& scene, std::vector<Light> lights, std::vector<ShadingPoint> points,
                                   LightingPath path, const Patch* grid = nullptr, DirectLightStats* stats = nullptr)
{
    validateLights(lights, "test");
    validateShadingPoints(points, "test");
    DirectLightOptions options;
    options.path = path;
    options.receiverGrid = grid;
    options.bitmaskAreaLights = grid != nullptr;
    return directIrradiance(scene, lights, points, options, stats);
}

/// A closed box room of six quads (both faces of each block).
Mesh room(const glm::vec3& lo, const glm::vec3& hi)
{
    Mesh m;
    m.name = "room";
    for (int i = 0; i < 8; ++i)
        m.positions.emplace_back((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    m.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    return m;
}

/// Judges every path at every point: the reference, the fast path's tiles, and with a receiver
/// grid the fast path with area lights by the bitmask. Returns the number of points where some
/// path lies outside the exact interval; `fastStats` gets the tiles' counts, `bitmaskStats` the
/// bitmask run's.
int disagreements(const Scene& scene, std::vector<Light> lights, std::vector<ShadingPoint> points, const Patch* grid,
                  DirectLightStats* bitmaskStats = nullptr, DirectLightStats* fastStats = nullptr)
{
    validateLights(lights, "test");
    validateShadingPoints(points, "test");
    const LightingScene lighting(scene);
    const test::LightsJudge judge(scene);
    const auto tiles = irradiance(lighting, lights, points, LightingPath::Fast, nullptr, fastStats);
    const auto bitmask = irradiance(lighting, lights, points, LightingPath::Fast, grid, bitmaskStats);
    const auto reference = irradiance(lighting, lights, points, LightingPath::Reference);
    int wrong = 0;
    for (std::size_t j = 0; j < points.size(); ++j) {
        const test::LitInterval exact = judge.at(lights, points[j]);
        if (!test::LightsJudge::agrees(exact, tiles[j]) || !test::LightsJudge::agrees(exact, bitmask[j]) ||
            !test::LightsJudge::agrees(exact, reference[j])) {
            ++wrong;
            ADD_FAILURE() << "point " << j << ": exact [" << exact.lit.x << ", " << exact.lit.x + exact.ties.x << "], tiles "
                          << tiles[j].x << ", bitmask " << bitmask[j].x << ", reference " << reference[j].x;
        }
    }
    return wrong;
}

} // namespace

TEST(Lights, PointLightFollowsTheInverseSquareLaw)
{
    const Scene empty;
    const LightingScene scene(empty);
    const glm::dvec3 light(0.3, 2.0, -0.1);
    std::vector<ShadingPoint> points;
    for (int k = 0; k < 50; ++k)
        points.push_back({{-2.0 + 0.08 * k, 0.0, 0.05 * k}, {0.0, 1.0, 0.0}});
    for (const LightingPath path : {LightingPath::Fast, LightingPath::Reference}) {
        const auto e = irradiance(scene, {pointLight(light, 10.0, {1.0, 0.5, 0.25})}, points, path);
        for (std::size_t j = 0; j < points.size(); ++j) {
            const glm::dvec3 to = light - points[j].position;
            const double d2 = glm::dot(to, to), expected = 10.0 * to.y / std::sqrt(d2) / d2;
            EXPECT_NEAR(e[j].x, expected, 1e-12 * expected);
            EXPECT_NEAR(e[j].y, 0.5 * expected, 1e-12 * expected);
            EXPECT_NEAR(e[j].z, 0.25 * expected, 1e-12 * expected);
        }
    }
}

TEST(Lights, RangeAndSpotConeFollowTheirWindows)
{
    const Scene empty;
    const LightingScene scene(empty);
    Light ranged = pointLight({0.0, 1.0, 0.0}, 4.0);
    ranged.range = 3.0;
    const Light spot = spotLight({0.0, 2.0, 0.0}, {0.0, -1.0, 0.0}, 0.2, 0.6, 5.0);
    for (double x : {0.0, 0.5, 1.0, 2.0, 2.9, 3.5}) {
        const ShadingPoint p{{x, 0.0, 0.0}, {0.0, 1.0, 0.0}};
        const double d = std::hypot(x, 1.0);
        const double window = std::pow(std::clamp(1.0 - std::pow(d / 3.0, 4.0), 0.0, 1.0), 2.0);
        EXPECT_NEAR(irradiance(scene, {ranged}, {p}, LightingPath::Fast)[0].x, 4.0 / (d * d) / d * window, 1e-12);
        const double ds = std::hypot(x, 2.0), cosT = 2.0 / ds;
        const double cone = std::pow(std::clamp((cosT - std::cos(0.6)) / (std::cos(0.2) - std::cos(0.6)), 0.0, 1.0), 2.0);
        EXPECT_NEAR(irradiance(scene, {spot}, {p}, LightingPath::Fast)[0].x, 5.0 * (2.0 / ds) / (ds * ds) * cone, 1e-12);
    }
}

// A point light 4 m above the floor and a disc (a 64-gon) of radius 0.5 at 2 m: a floor point at
// radius rho sends its segment through the disc's plane at rho * (4 - 2) / (4 - y), so the shadow
// is the disc scaled by about two. Points clearly inside get nothing, clearly outside the full
// inverse-square light.
TEST(Lights, DiscOccluderCastsItsShadowEdge)
{
    Mesh disc;
    disc.name = "disc";
    const int sides = 64;
    disc.positions.emplace_back(0.0f, 2.0f, 0.0f);
    for (int k = 0; k < sides; ++k) {
        const double a = 2.0 * std::numbers::pi * k / sides;
        disc.positions.emplace_back(float(0.5 * std::cos(a)), 2.0f, float(0.5 * std::sin(a)));
        disc.indices.insert(disc.indices.end(), {0u, std::uint32_t(1 + k), std::uint32_t(1 + (k + 1) % sides)});
    }
    const Scene scene = test::sceneOf({disc, test::quad({-5, 0, -5}, {10, 0, 0}, {0, 0, 10}, "floor")});
    const LightingScene lighting(scene);
    const glm::dvec3 light(0.0, 4.0, 0.0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
    std::vector<ShadingPoint> points;
    std::vector<int> expectShadow;
    const double y = 1e-3, inner = 0.5 * std::cos(std::numbers::pi / sides);
    for (int k = 0; k < 400; ++k) {
        const double rho = 0.005 * k, a = angle(rng), atDisc = rho * 2.0 / (4.0 - y);
        if (std::abs(atDisc - inner) < 1e-3 || (atDisc > inner && atDisc < 0.5 + 1e-3))
            continue;   // between the 64-gon's inscribed and circumscribed circles
        points.push_back({{rho * std::cos(a), y, rho * std::sin(a)}, {0.0, 1.0, 0.0}});
        expectShadow.push_back(atDisc < inner);
    }
    int shadowed = 0;
    for (const LightingPath path : {LightingPath::Fast, LightingPath::Reference}) {
        const auto e = irradiance(lighting, {pointLight(light, 8.0)}, points, path);
        for (std::size_t j = 0; j < points.size(); ++j) {
            const glm::dvec3 to = light - points[j].position;
            const double d2 = glm::dot(to, to), lit = 8.0 * to.y / std::sqrt(d2) / d2;
            EXPECT_NEAR(e[j].x, expectShadow[j] ? 0.0 : lit, 1e-12) << "rho " << glm::length(points[j].position);
            shadowed += expectShadow[j];
        }
    }
    EXPECT_GT(shadowed, 100);
}

// The unoccluded irradiance of a rectangle of radiance L at a point below one of its corners on
// a parallel plane is L pi F, F the differential form factor
//     F = 1/(2 pi) [A/sqrt(1+A²) atan(B/sqrt(1+A²)) + B/sqrt(1+B²) atan(A/sqrt(1+B²))],
// A, B the sides over the height. The sampled sum is a midpoint rule: its error falls as 1/n².
TEST(Lights, AreaLightConvergesToTheRectanglesFormFactor)
{
    const double w = 1.0, l = 2.0, h = 1.5, radiance = 3.0;
    const double A = w / h, B = l / h;
    const double F = (A / std::sqrt(1 + A * A) * std::atan(B / std::sqrt(1 + A * A)) +
                      B / std::sqrt(1 + B * B) * std::atan(A / std::sqrt(1 + B * B))) / (2.0 * std::numbers::pi);
    const double exact = radiance * std::numbers::pi * F;
    const Scene empty;
    const LightingScene scene(empty);
    const ShadingPoint below{{0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}};
    double previous = 1.0;
    for (int n : {8, 32, 128}) {
        Patch rect;   // facing down: u x v = (0, -1, 0)
        rect.corner = {0.0, h, 0.0};
        rect.u = {w, 0.0, 0.0};
        rect.v = {0.0, 0.0, l};
        rect.na = n;
        rect.nb = n;
        const double e = irradiance(scene, {areaLight(rect, radiance)}, {below}, LightingPath::Fast)[0].x;
        const double error = std::abs(e - exact) / exact;
        EXPECT_LT(error, previous / 10.0) << n << " samples";
        previous = error;
    }
    EXPECT_LT(previous, 1e-4);
}

// Lights outside a closed room light nothing inside it, lights inside nothing outside, whatever
// their kind, at the origin and 10 km from it.
TEST(Lights, SealedRoomLeaksNothing)
{
    for (const double offset : {0.0, 10000.0}) {
        const glm::dvec3 o(offset, 0.0, -offset);
        const Scene scene = test::sceneOf({room(glm::vec3(o + glm::dvec3(-2, 0, -2)), glm::vec3(o + glm::dvec3(2, 3, 2)))});
        const LightingScene lighting(scene);
        Patch panel;
        panel.corner = o + glm::dvec3(-1.0, 3.5, -1.0);
        panel.u = {2.0, 0.0, 0.0};
        panel.v = {0.0, 0.0, 2.0};   // facing down onto the roof
        const std::vector<Light> outside = {pointLight(o + glm::dvec3(5, 1, 0), 100.0),
                                            spotLight(o + glm::dvec3(0, 6, 0), {0, -1, 0}, 0.1, 1.2, 100.0),
                                            directionalLight({0.3, -1.0, 0.2}, 5.0), areaLight(panel, 20.0)};
        std::vector<ShadingPoint> inside;
        for (int k = 0; k < 25; ++k)
            inside.push_back({o + glm::dvec3(-1.8 + 0.15 * k, 0.01, 0.3), {0.0, 1.0, 0.0}});
        inside.push_back({o + glm::dvec3(1.99, 1.5, 0.0), {-1.0, 0.0, 0.0}});
        for (const LightingPath path : {LightingPath::Fast, LightingPath::Reference})
            for (const glm::dvec3& e : irradiance(lighting, outside, inside, path))
                EXPECT_EQ(e, glm::dvec3(0.0)) << "offset " << offset;

        const std::vector<Light> within = {pointLight(o + glm::dvec3(0, 2, 0), 100.0),
                                           spotLight(o + glm::dvec3(1, 2.5, 0), {0.3, -1, 0}, 0.1, 1.4, 50.0)};
        std::vector<ShadingPoint> around;
        for (int k = 0; k < 10; ++k)
            around.push_back({o + glm::dvec3(2.5 + 0.2 * k, 0.01, 0.0), {0.0, 1.0, 0.0}});
        around.push_back({o + glm::dvec3(0.0, 3.01, 0.0), {0.0, 1.0, 0.0}});
        for (const LightingPath path : {LightingPath::Fast, LightingPath::Reference})
            for (const glm::dvec3& e : irradiance(lighting, within, around, path))
                EXPECT_EQ(e, glm::dvec3(0.0)) << "offset " << offset;
    }
}

TEST(Lights, LightBehindAWallLightsNothingThroughIt)
{
    // A wall in the plane z = 0 over x in [-1, 1], y in [0, 3]; the light at z = -2.
    const Scene scene = test::sceneOf({test::quad({-1, 0, 0}, {2, 0, 0}, {0, 3, 0}, "wall")});
    const LightingScene lighting(scene);
    const glm::dvec3 light(0.0, 1.0, -2.0);
    std::vector<ShadingPoint> points;
    for (int k = 0; k < 128; ++k)   // behind the wall's middle (two tiles), and past its end
        points.push_back({{-0.5 + 0.0625 * (k % 16), 0.01, 0.5 + 0.125 * (k / 16)}, {0.0, 1.0, 0.0}});
    points.push_back({{4.0, 0.01, 1.0}, {0.0, 1.0, 0.0}});
    for (const LightingPath path : {LightingPath::Fast, LightingPath::Reference}) {
        DirectLightStats stats;
        const auto e = irradiance(lighting, {pointLight(light, 10.0)}, points, path, nullptr, &stats);
        for (int k = 0; k < 128; ++k)
            EXPECT_EQ(e[std::size_t(k)].x, 0.0) << k;
        EXPECT_GT(e.back().x, 0.0);
        if (path == LightingPath::Fast) {   // the wall's two triangles, fused, shadow tiles whole
            EXPECT_GE(stats.tilesProvenShadowed, 1u);
        }
    }
}

// A wall face split around a doorway (coplanar triangles sharing edges whose union is not convex):
// fusing neighbours must not close the doorway. Lights behind it, points on the floor beyond.
TEST(Lights, AWallWithADoorwayIsNotProvedShut)
{
    // The wall z = 0, x in [-3, 3], y in [0, 3], with a doorway x in [-0.5, 0.5], y in [0, 2.2]:
    // left, right and lintel rectangles, each two triangles, sharing edges at the lintel's ends.
    Mesh wall;
    wall.name = "wall";
    const float xs[4] = {-3.0f, -0.5f, 0.5f, 3.0f};
    for (int i = 0; i < 4; ++i)
        for (const float y : {0.0f, 2.2f, 3.0f})
            wall.positions.emplace_back(xs[i], y, 0.0f);
    const auto at = [](int i, int j) { return std::uint32_t(3 * i + j); };   // column i, row j
    const auto rect = [&](int i0, int i1, int j0, int j1) {
        wall.indices.insert(wall.indices.end(), {at(i0, j0), at(i1, j0), at(i1, j1), at(i0, j0), at(i1, j1), at(i0, j1)});
    };
    rect(0, 1, 0, 1), rect(0, 1, 1, 2), rect(1, 2, 1, 2), rect(2, 3, 0, 1), rect(2, 3, 1, 2);
    const Scene scene = test::sceneOf({wall});
    std::vector<ShadingPoint> points;
    for (int i = 0; i < 24; ++i)
        for (int j = 0; j < 16; ++j)
            points.push_back({{-3.0 + 0.25 * i, 0.01, 0.2 + 0.25 * j}, {0.0, 1.0, 0.0}});
    Patch panel;
    panel.corner = {-0.5, 2.6, -2.0};
    panel.u = {1.0, 0.0, 0.0};
    panel.v = {0.0, 0.0, 1.0};   // facing down
    panel.na = 4, panel.nb = 4;
    DirectLightStats stats;
    EXPECT_EQ(disagreements(scene, {pointLight({0.2, 1.5, -1.5}, 20.0), areaLight(panel, 10.0), directionalLight({0.1, -0.6, 1.0}, 2.0)},
                            points, nullptr, nullptr, &stats),
              0);
    EXPECT_GE(stats.tilesCast, 1u);
}

// An area light's segments go in packets towards the smaller end: from each sample where a
// quarter of the tile is smaller than the light (the dense grid's 0.4 m tiles under a 1.4 m
// panel), from each point where it is larger (the sparse grid's 4 m tiles). Both ways, both paths
// give the judge's answer, a crate's shadow and penumbra included.
TEST(Lights, AreaLightPacketsFromEitherEndAgreeWithTheContract)
{
    Scene scene = test::sceneOf({test::quad({-3.0f, 0.0f, -3.0f}, {0.0f, 0.0f, 6.0f}, {6.0f, 0.0f, 0.0f}, "floor")});
    scene.addMeshInstance(test::closedBox(), glm::translate(glm::mat4(1.0f), glm::vec3(0.2f, 0.8f, -0.1f)) *
                                                 glm::scale(glm::mat4(1.0f), glm::vec3(0.6f, 0.3f, 0.8f)));
    Patch panel;
    panel.corner = {-0.5, 2.5, -0.5};
    panel.u = {1.0, 0.0, 0.0};
    panel.v = {0.0, 0.0, 1.0};   // facing down
    panel.na = 4, panel.nb = 4;
    for (const double spacing : {0.05, 0.5}) {
        std::vector<ShadingPoint> points;
        for (int i = 0; i < 12; ++i)
            for (int j = 0; j < 12; ++j)
                points.push_back({{-0.3 + spacing * (i - 6), 0.01, 0.1 + spacing * (j - 6)}, {0.0, 1.0, 0.0}});
        DirectLightStats stats;
        EXPECT_EQ(disagreements(scene, {areaLight(panel, 10.0)}, points, nullptr, nullptr, &stats), 0) << "spacing " << spacing;
        EXPECT_GE(stats.tilesCast, 1u) << "spacing " << spacing;
    }
}

// The reference takes a tile's emitters a thousand-odd at a time: an area light of 1,600 samples
// between two point lights spans two chunks, and the sums still come out as the judge's.
TEST(Lights, TheReferenceTakesThousandsOfEmittersInChunks)
{
    Scene scene = test::sceneOf({test::quad({-3.0f, 0.0f, -3.0f}, {0.0f, 0.0f, 6.0f}, {6.0f, 0.0f, 0.0f}, "floor")});
    scene.addMeshInstance(test::closedBox(), glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 0.0f)) *
                                                 glm::scale(glm::mat4(1.0f), glm::vec3(0.5f, 0.2f, 0.5f)));
    Patch panel;
    panel.corner = {-0.6, 2.5, -0.6};
    panel.u = {1.2, 0.0, 0.0};
    panel.v = {0.0, 0.0, 1.2};
    panel.na = 40, panel.nb = 40;
    std::vector<ShadingPoint> points;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
            points.push_back({{-1.0 + 0.45 * i, 0.01, -1.0 + 0.45 * j}, {0.0, 1.0, 0.0}});
    EXPECT_EQ(disagreements(scene, {pointLight({1.0, 2.0, 0.5}, 5.0), areaLight(panel, 10.0), pointLight({-1.0, 2.0, -0.5}, 5.0)},
                            points, nullptr),
              0);
}

// The yardstick (a user's float Embree brute force) answers the same sums where no segment comes
// near an edge or an end: a lamp and a panel over a floor with a block well inside its shadow.
TEST(Lights, TheEmbreeFloatYardstickAgreesAwayFromEdges)
{
    const Scene scene = sceneOf({quad({-4, 0, -4}, {8, 0, 0}, {0, 0, 8}, "floor"), quad({-1, 1, -1}, {2, 0, 0}, {0, 0, 2}, "slab")});
    const LightingScene lighting(scene);
    Patch panel;
    panel.corner = {-0.25, 3.0, -0.25};
    panel.u = {0.5, 0.0, 0.0};
    panel.v = {0.0, 0.0, 0.5};   // facing down
    panel.na = panel.nb = 2;
    const std::vector<Light> lights = {pointLight({0.0, 2.5, 0.0}, 10.0), areaLight(panel, 5.0)};
    // Points under the slab's middle (every segment crosses it well inside) and far outside its
    // shadow (every segment free, far from its edges).
    std::vector<ShadingPoint> points;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            points.push_back({{-0.3 + 0.08 * i, 0.01, -0.3 + 0.08 * j}, {0.0, 1.0, 0.0}});
            points.push_back({{3.0 + 0.1 * i, 0.01, -3.5 + 0.1 * j}, {0.0, 1.0, 0.0}});
        }
    const std::vector<glm::dvec3> exact = irradiance(lighting, lights, points, LightingPath::Reference);
    const std::vector<glm::dvec3> yardstick = irradiance(lighting, lights, points, LightingPath::EmbreeFloat);
    int lit = 0;
    for (std::size_t j = 0; j < points.size(); ++j) {
        EXPECT_EQ(yardstick[j], exact[j]) << j;
        lit += exact[j].x > 0.0;
    }
    EXPECT_EQ(lit, 64);   // the far half
}

// A wall built of bands around a window (coplanar cells sharing edges): where a tile's shaft
// crosses several cells, no triangle or pair covers it, but the cells together do.
TEST(Lights, AWallOfBandsShadowsWholeTilesAndItsWindowLetsLightThrough)
{
    // The wall z = 0, x in [-3, 3], y in [0, 3], as 3 x 3 cells of 2 m x 1 m, welded, with the
    // middle cell (x in [-1, 1], y in [1, 2]) a window.
    Mesh wall;
    wall.name = "wall";
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            wall.positions.emplace_back(-3.0f + 2.0f * float(i), float(j), 0.0f);
    const auto at = [](int i, int j) { return std::uint32_t(i + 4 * j); };
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            if (i != 1 || j != 1)
                wall.indices.insert(wall.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    const Scene scene = test::sceneOf({wall});
    std::vector<ShadingPoint> points;
    for (int i = 0; i < 24; ++i)
        for (int j = 0; j < 16; ++j)
            points.push_back({{-2.9 + 0.25 * i, 0.01, 0.2 + 0.25 * j}, {0.0, 1.0, 0.0}});
    // A lamp low behind the wall: every segment crosses the bottom band, across its cells' seams.
    const std::vector<Light> low = {pointLight({0.0, 0.5, -1.5}, 20.0)};
    DirectLightStats stats;
    EXPECT_EQ(disagreements(scene, low, points, nullptr, nullptr, &stats), 0);
    EXPECT_EQ(stats.tilesCast, 0u);
    EXPECT_GE(stats.tilesProvenShadowed, 6u);
    EXPECT_EQ(stats.terms, 0u);   // proved shadowed before a term was weighed
    const LightingScene lighting(scene);
    DirectLightStats reference, counted;
    directIrradiance(lighting, low, points, {.path = LightingPath::Reference}, &reference);
    EXPECT_EQ(reference.terms, points.size());   // the lamp faces every point
    directIrradiance(lighting, low, points, {.countAllTerms = true}, &counted);
    EXPECT_EQ(counted.terms, points.size());
    EXPECT_EQ(counted.segmentsCast, 0u);
    for (const glm::dvec3& e : irradiance(lighting, low, points, LightingPath::Fast))
        EXPECT_EQ(e, glm::dvec3(0.0));
    // A panel high behind it shines through the window onto part of the floor.
    Patch panel;
    panel.corner = {-0.5, 2.6, -2.0};
    panel.u = {1.0, 0.0, 0.0};
    panel.v = {0.0, 0.0, 1.0};   // facing down
    panel.na = 4, panel.nb = 4;
    const std::vector<Light> high = {areaLight(panel, 10.0), pointLight({0.0, 1.8, -1.0}, 10.0)};
    EXPECT_EQ(disagreements(scene, high, points, nullptr), 0);
    int lit = 0;
    for (const glm::dvec3& e : irradiance(lighting, high, points, LightingPath::Fast))
        lit += e.x > 0.0;
    EXPECT_GT(lit, 10);
    EXPECT_LT(lit, int(points.size()));
}

// Random soups between an area light and a receiver grid (the bitmask's case, E&D §8), with point,
// spot and directional lights among them; the receiver's samples and scattered points, at the
// origin and 10 km out. Both paths must lie in the exact interval at every point.
TEST(Lights, BothPathsAgreeWithTheContractOnRandomScenes)
{
    int bitmaskCalls = 0, checked = 0;
    for (unsigned seed = 1; seed <= 8; ++seed) {
        test::RandomCase c = test::randomCase(seed);
        if (!c.valid())
            continue;
        // The receiver faces the light.
        std::swap(c.receiver.u, c.receiver.v);
        std::swap(c.receiver.na, c.receiver.nb);
        const double offset = seed % 2 ? 0.0 : 10000.0;
        Scene scene = c.scene;
        if (offset != 0.0)
            for (Instance& instance : scene.instances)
                instance.transform = glm::translate(glm::mat4(1.0f), glm::vec3(float(offset), float(-offset), 0.0f)) * instance.transform;
        const glm::dvec3 o(offset, -offset, 0.0);
        c.source.corner += o;
        c.receiver.corner += o;
        Light area = areaLight(c.source, 2.0);
        area.area.na = 8, area.area.nb = 8;
        area.colour = {1.0, 0.8, 0.6};
        const glm::dvec3 mid = 0.5 * (c.source.centre() + c.receiver.centre());
        const std::vector<Light> lights = {area, pointLight(mid + glm::dvec3(0.3, -0.2, -1.0), 3.0),
                                           spotLight(c.source.centre() + glm::dvec3(0, 0, -0.2), {0.1, 0.0, 1.0}, 0.3, 0.9, 4.0),
                                           directionalLight({0.2, 0.1, 1.0}, 1.5)};
        const std::vector<ShadingPoint> grid = patchShadingPoints(c.receiver);
        DirectLightStats stats;
        EXPECT_EQ(disagreements(scene, lights, grid, &c.receiver, &stats), 0) << "seed " << seed;
        bitmaskCalls += int(stats.bitmaskLights);
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        std::vector<ShadingPoint> scattered;
        for (int k = 0; k < 60; ++k)
            scattered.push_back({o + glm::dvec3(-1.0 + 3.5 * unit(rng), -1.0 + 3.5 * unit(rng), 0.5 + 3.0 * unit(rng)),
                                 {unit(rng) - 0.5, unit(rng) - 0.5, -1.0}});
        EXPECT_EQ(disagreements(scene, lights, scattered, nullptr), 0) << "seed " << seed;
        ++checked;
    }
    EXPECT_GE(checked, 5);
    EXPECT_GE(bitmaskCalls, 5);   // the area light went through the bitmask sampler
}

// Grazing and touching: an area light standing on the receiver's plane (no valid pair: rays), a
// box resting on the floor the points lie on (some inside it), a sun 3 degrees above the horizon.
TEST(Lights, GrazingLightsAndOccludersTouchingTheReceiver)
{
    Mesh box = test::closedBox();
    box.watertight = false;
    Scene scene = test::sceneOf({test::quad({-4, 0, -4}, {8, 0, 0}, {0, 0, 8}, "floor")});
    scene.addMeshInstance(box, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.5f, 0.0f)));
    Patch floor;
    floor.corner = {-2.0, 1e-3, 2.0};
    floor.u = {4.0, 0.0, 0.0};
    floor.v = {0.0, 0.0, -4.0};   // normal +y
    floor.na = 24, floor.nb = 24;
    Patch standing;
    standing.corner = {-1.5, 0.0, -1.5};
    standing.u = {3.0, 0.0, 0.0};
    standing.v = {0.0, 1.0, 0.0};   // facing +z, touching the floor
    standing.na = 6, standing.nb = 3;
    Patch above;
    above.corner = {-1.0, 2.0, -1.0};
    above.u = {2.0, 0.0, 0.0};
    above.v = {0.0, 0.0, 2.0};   // facing down: a valid pair with the floor
    above.na = 8, above.nb = 8;
    const std::vector<Light> lights = {areaLight(standing, 5.0), areaLight(above, 5.0), pointLight({1.2, 0.3, 0.0}, 2.0),
                                       directionalLight({1.0, -0.05, 0.0}, 3.0)};
    DirectLightStats stats;
    EXPECT_EQ(disagreements(scene, lights, patchShadingPoints(floor), &floor, &stats), 0);
    EXPECT_EQ(stats.bitmaskLights, 1u);
}

TEST(Lights, BadLightsAreRefusedNamingTheKey)
{
    const auto refused = [](Light light, const std::string& needle) {
        std::vector<Light> lights = {pointLight({0, 1, 0}, 1.0), light};
        try {
            validateLights(lights, "p.json");
            ADD_FAILURE() << "accepted: " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    refused(pointLight({0, 1, 0}, -1.0), "lights[1].intensity");
    refused(pointLight({0, NAN, 0}, 1.0), "lights[1].position");
    refused(pointLight({0, 2e6, 0}, 1.0), "lights[1].position");
    refused(pointLight({0, 1, 0}, 1.0, {1.0, -0.1, 0.0}), "lights[1].colour");
    refused(spotLight({0, 1, 0}, {0, -1, 0}, 0.8, 0.4, 1.0), "lights[1].inner_angle");
    refused(spotLight({0, 1, 0}, {0, 0, 0}, 0.1, 0.4, 1.0), "lights[1].direction");
    refused(directionalLight({0, -1, 0}, INFINITY), "lights[1].intensity");
    Patch flat;
    flat.u = {1.0, 0.0, 0.0};
    flat.v = {2.0, 0.0, 0.0};
    refused(areaLight(flat, 1.0), "'lights[1]' is a degenerate area light");
    Patch zero;
    zero.u = glm::dvec3(0.0);
    refused(areaLight(zero, 1.0), "degenerate");
    Light negative = areaLight(test::xyPatch(1.0, 4, 4), -2.0);
    refused(negative, "lights[1].radiance");

    std::vector<Light> many(kMaxLights + 1, pointLight({0, 1, 0}, 1.0));
    EXPECT_THROW(validateLights(many, "p.json"), Error);
    Light dense = areaLight(test::xyPatch(1.0, 1024, 1024), 1.0);
    std::vector<Light> tooManySamples = {dense, dense};
    EXPECT_THROW(validateLights(tooManySamples, "p.json"), Error);
}

// The fully-lit class: under a panel, floor tiles whose shaft holds no triangle are proved lit
// without a ray, those whose shaft a crate enters are cast; every path stays exact.
TEST(Lights, EmptyShaftsAreProvedLitAndTheRestCast)
{
    Mesh crate = test::closedBox();
    crate.watertight = false;
    Scene scene = test::sceneOf({test::quad({-4, 0, -4}, {8, 0, 0}, {0, 0, 8}, "floor")});
    scene.addMeshInstance(crate, glm::translate(glm::mat4(1.0f), glm::vec3(1.5f, 0.5f, 0.0f)));
    Patch panel;
    panel.corner = {-0.5, 3.0, -0.5};
    panel.u = {1.0, 0.0, 0.0};
    panel.v = {0.0, 0.0, 1.0};   // facing down
    panel.na = panel.nb = 4;
    std::vector<ShadingPoint> points;
    for (int i = 0; i < 32; ++i)
        for (int j = 0; j < 32; ++j)
            points.push_back({{-3.9 + 0.25 * i, 0.01, -3.9 + 0.25 * j}, {0.0, 1.0, 0.0}});
    DirectLightStats stats;
    EXPECT_EQ(disagreements(scene, {areaLight(panel, 10.0)}, points, nullptr, nullptr, &stats), 0);
    EXPECT_GE(stats.tilesProvenLit, 1u);
    EXPECT_GE(stats.tilesCast, 1u);
}
