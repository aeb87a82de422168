// The GL path for many lights (octahedral shadow maps, lighting/GlDirectLight.h) against the exact
// answer, pair by pair: a (point, emitter) pair may differ only where the maps' tolerance explains
// it, i.e. the exact answer becomes the GL one when the point moves towards the emitter by the bias
// plus a texel and/or sideways by up to a texel; where every pair of a point agrees, its
// irradiance is the reference's up to float summation.
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "GlContextTest.h"
#include "TestLights.h"
#include "TestScenes.h"
#include "lighting/DirectLight.h"
#include "lighting/GlDirectLight.h"
#include "lighting/LightEmission.h"
#include "lighting/ShadowAgreement.h"

using namespace sightline;
using namespace sightline::test;

namespace {

class GlDirectLightTest : public GlContextTest {};

/// A floor with a box on it, a thin wall, a table top and a closed box room offset by `offset`.
Scene furnishedFloor(const glm::vec3& offset)
{
    Scene scene = sceneOf({quad(offset + glm::vec3(-4.0f, 0.0f, -4.0f), {0.0f, 0.0f, 8.0f}, {8.0f, 0.0f, 0.0f}, "floor"),
                           quad(offset + glm::vec3(2.0f, 0.0f, -3.0f), {0.0f, 2.0f, 0.0f}, {0.0f, 0.0f, 2.5f}, "wall"),
                           quad(offset + glm::vec3(-2.5f, 0.8f, 1.0f), {1.2f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.8f}, "table")});
    scene.addMeshInstance(closedBox(), glm::translate(glm::mat4(1.0f), offset + glm::vec3(0.0f, 0.5f, 0.0f)));
    return scene;
}

std::vector<Light> allKinds(const glm::dvec3& offset)
{
    Patch panel;
    panel.corner = offset + glm::dvec3(-1.0, 2.8, -1.5);
    panel.u = {1.0, 0.0, 0.0};
    panel.v = {0.0, 0.0, 1.0};   // u x v = -y: it shines down
    panel.na = panel.nb = 4;
    std::vector<Light> lights = {pointLight(offset + glm::dvec3(0.3, 3.0, -0.2), 10.0, {1.0, 0.8, 0.6}),
                                 spotLight(offset + glm::dvec3(-2.0, 2.5, 1.0), glm::normalize(glm::dvec3(0.6, -1.0, -0.4)), 0.3, 0.8, 20.0),
                                 areaLight(panel, 3.0), directionalLight(glm::normalize(glm::dvec3(0.3, -1.0, 0.2)), 2.0),
                                 pointLight(offset + glm::dvec3(1.2, 1.0, -1.5), 4.0)};
    lights.back().range = 2.5;   // its map holds only the triangles within reach (the wall, 0.8 m away)
    validateLights(lights, "test");
    return lights;
}

/// A grid over the floor, and points on the box's top and the wall's side, lifted 1 mm.
std::vector<ShadingPoint> floorPoints(const glm::dvec3& offset, int n)
{
    std::vector<ShadingPoint> points;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            points.push_back({offset + glm::dvec3(-3.9 + 7.8 * (i + 0.5) / n, 1e-3, -3.9 + 7.8 * (j + 0.5) / n), {0.0, 1.0, 0.0}});
    for (int k = 0; k < 10; ++k) {
        points.push_back({offset + glm::dvec3(-0.45 + 0.09 * k, 1.001, 0.1), {0.0, 1.0, 0.0}});
        points.push_back({offset + glm::dvec3(1.999, 0.1 + 0.18 * k, -2.0), {-1.0, 0.0, 0.0}});
    }
    validateShadingPoints(points, "test");
    return points;
}

/// Whether the exact answer for `emitter` at `x` becomes `lit` when x moves within the tolerance.
bool explained(const LightingScene& scene, const GlDirectLight& gl, const Light& light, const glm::dvec3& emitter,
               const ShadingPoint& p, bool lit)
{
    const bool directional = light.type == LightType::Directional;
    const glm::dvec3 end = directional ? scene.reach().end(light, p.position) : emitter;
    const double t = glm::length(end - p.position);
    const glm::dvec3 l = (end - p.position) / t;
    const double lateral = directional ? gl.directionalTexel() : t * gl.texelAngle();
    const double towards = gl.bias(directional, t, glm::dot(p.normal, l)) + lateral;
    // Sideways within the point's own surface (its tangent plane): a move off it would reach
    // through that surface and explain anything.
    const glm::dvec3 helper = std::abs(p.normal.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 a = glm::normalize(glm::cross(helper, p.normal)), b = glm::cross(p.normal, a);
    std::vector<glm::dvec3> moved = {p.position + towards * l};
    for (int k = 0; k < 16; ++k) {
        const double angle = 2.0 * 3.14159265358979 * k / 16.0;
        const glm::dvec3 side = lateral * (std::cos(angle) * a + std::sin(angle) * b);
        moved.push_back(p.position + side);
        moved.push_back(p.position + 0.5 * side);
        moved.push_back(p.position + side + towards * l);
    }
    for (const glm::dvec3& x : moved) {
        const glm::dvec3 to = directional ? scene.reach().end(light, x) : emitter;
        std::uint8_t blocked = 0;
        scene.rays().segmentsBlocked(x, std::span(&to, 1), &blocked);
        if (bool(!blocked) == lit)
            return true;
    }
    return false;
}

struct Judged {
    ShadowAgreement agreement;
    std::size_t settledPairs = 0;     ///< with classes: pairs a class settled (non-zero terms)
    std::size_t settledWrong = 0;     ///< of those, differing from the exact answer
    std::size_t maps = 0;
    std::size_t unexplained = 0;
    std::size_t pointsAllAgreeing = 0;
    double worstAgreeingRelative = 0.0;
};

Judged judge(const gl::Functions& functions, const Scene& scene, const std::vector<Light>& lights,
             const std::vector<ShadingPoint>& points, int resolution, bool pyramid = false)
{
    const LightingScene lighting(scene);
    GlDirectLight gl(functions, lighting.triangles(), {.resolution = resolution});
    EmitterBits bits;
    GlDirectLightStats stats;
    const TileClasses classes = classifyTiles(lighting, lights, points);
    const std::vector<glm::dvec3> fromGl = gl.irradiance(lights, points, &stats, &bits, pyramid ? &classes : nullptr);
    EXPECT_EQ(stats.emitters, lightEmitters(lights).size());
    const EmitterBits exact = exactEmitterBits(lighting, lights, points);
    const std::vector<glm::dvec3> reference = directIrradiance(lighting, lights, points, {.path = LightingPath::Reference});
    const std::vector<Emitter> emitters = lightEmitters(lights);
    Judged out;
    out.maps = stats.maps;
    out.agreement = compareEmitterBits(lights, points, bits, exact);
    for (std::size_t j = 0; j < points.size(); ++j) {
        bool allAgree = true;
        for (std::size_t e = 0; e < emitters.size(); ++e) {
            const Light& light = lights[emitters[e].light];
            if (emitterTerm(light, emitters[e].position, points[j].position, points[j].normal) <= 0.0)
                continue;
            const bool differs = bits.lit(j, e) != exact.lit(j, e);
            allAgree = allAgree && !differs;
            if (pyramid && classes.at(j, emitters[e].light) != TileClass::Partial) {
                ++out.settledPairs;
                out.settledWrong += differs;   // a proof's answer: never explained by a tolerance
                continue;
            }
            if (!differs)
                continue;
            if (!explained(lighting, gl, light, emitters[e].position, points[j], bits.lit(j, e))) {
                ++out.unexplained;
                ADD_FAILURE() << "point " << j << " (" << points[j].position.x << ", " << points[j].position.y << ", "
                              << points[j].position.z << "), emitter " << e << ": GL says " << (bits.lit(j, e) ? "lit" : "shadowed")
                              << ", and no move within the tolerance makes it so";
            }
        }
        if (!allAgree)
            continue;
        ++out.pointsAllAgreeing;
        for (int c = 0; c < 3; ++c)
            out.worstAgreeingRelative = std::max(out.worstAgreeingRelative,
                                                 std::abs(fromGl[j][c] - reference[j][c]) / std::max(reference[j][c], 1e-9));
    }
    return out;
}

} // namespace

TEST_F(GlDirectLightTest, AnUnshadowedFloorAgreesEverywhereAndSumsTheReferencesTerms)
{
    const Scene scene = sceneOf({quad({-4.0f, 0.0f, -4.0f}, {0.0f, 0.0f, 8.0f}, {8.0f, 0.0f, 0.0f}, "floor")});
    const std::vector<Light> lights = allKinds(glm::dvec3(0.0));
    const std::vector<ShadingPoint> points = floorPoints(glm::dvec3(0.0), 24);
    const Judged judged = judge(context->functions(), scene, lights, points, 256);
    EXPECT_GT(judged.agreement.pairs, 10000u);
    // Only the wall and box points stand in open air here: every pair is lit, and the floor's own
    // map never shadows the points above it.
    EXPECT_EQ(judged.agreement.differing(), 0u);
    EXPECT_EQ(judged.pointsAllAgreeing, points.size());
    EXPECT_LT(judged.worstAgreeingRelative, 1e-4);
}

TEST_F(GlDirectLightTest, EveryDifferenceOnAFurnishedFloorLiesWithinTheMapsTolerance)
{
    const std::vector<ShadingPoint> points = floorPoints(glm::dvec3(0.0), 48);
    const Judged judged = judge(context->functions(), furnishedFloor(glm::vec3(0.0f)), allKinds(glm::dvec3(0.0)), points, 512);
    EXPECT_EQ(judged.unexplained, 0u);
    EXPECT_GT(judged.agreement.pairs, 40000u);
    EXPECT_LT(double(judged.agreement.differing()), 0.02 * double(judged.agreement.pairs));
    EXPECT_GT(judged.pointsAllAgreeing, points.size() * 9 / 10);
    EXPECT_LT(judged.worstAgreeingRelative, 1e-4);
}

// Barczak's occlusion pyramid: pairs in tiles proved unreached, shadowed or lit take the proof's
// answer, which is the exact one, and only lights with a partial tile get maps.
TEST_F(GlDirectLightTest, TheOcclusionPyramidsClassesSettlePairsExactlyAndSpareMaps)
{
    const std::vector<ShadingPoint> points = floorPoints(glm::dvec3(0.0), 48);
    const Scene scene = furnishedFloor(glm::vec3(0.0f));
    std::vector<Light> lights = allKinds(glm::dvec3(0.0));
    Light far = pointLight({30.0, 2.0, 0.0}, 5.0);   // its range reaches no point: no map
    far.range = 5.0;
    lights.push_back(far);
    validateLights(lights, "test");
    const Judged plain = judge(context->functions(), scene, lights, points, 512);
    const Judged judged = judge(context->functions(), scene, lights, points, 512, true);
    EXPECT_EQ(judged.unexplained, 0u);
    EXPECT_GT(judged.settledPairs, 10000u);
    EXPECT_EQ(judged.settledWrong, 0u);
    EXPECT_EQ(plain.maps, lightEmitters(lights).size());
    EXPECT_LT(judged.maps, plain.maps);
    EXPECT_LE(judged.agreement.differing(), plain.agreement.differing());
    EXPECT_LT(judged.worstAgreeingRelative, 1e-4);
}

TEST_F(GlDirectLightTest, TenKilometresFromTheOriginTheToleranceStillExplainsEveryDifference)
{
    const glm::dvec3 offset(10000.0, 0.0, -10000.0);
    const std::vector<ShadingPoint> points = floorPoints(offset, 32);
    const Judged judged = judge(context->functions(), furnishedFloor(glm::vec3(offset)), allKinds(offset), points, 512);
    EXPECT_EQ(judged.unexplained, 0u);
    EXPECT_LT(double(judged.agreement.differing()), 0.02 * double(judged.agreement.pairs));
    EXPECT_LT(judged.worstAgreeingRelative, 1e-4);
}

TEST_F(GlDirectLightTest, ALightSealedInABoxLightsNothingOutsideIt)
{
    Scene scene = sceneOf({quad({-4.0f, 0.0f, -4.0f}, {0.0f, 0.0f, 8.0f}, {8.0f, 0.0f, 0.0f}, "floor")});
    scene.addMeshInstance(closedBox(), glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 0.0f)), glm::vec3(2.0f)));
    std::vector<Light> lights = {pointLight({0.2, 1.3, -0.1}, 50.0)};
    validateLights(lights, "test");
    std::vector<ShadingPoint> outside, inside;
    for (int k = 0; k < 40; ++k) {
        const double angle = 2.0 * 3.14159265358979 * k / 40.0;
        outside.push_back({{(1.5 + 0.05 * k) * std::cos(angle), 1e-3, (1.5 + 0.05 * k) * std::sin(angle)}, {0.0, 1.0, 0.0}});
        outside.push_back({{0.3 * std::cos(angle), 2.0 + 0.01 + 0.02 * k, 0.3 * std::sin(angle)}, {0.0, 1.0, 0.0}});
        inside.push_back({{0.8 * std::cos(angle), 0.001, 0.8 * std::sin(angle)}, {0.0, 1.0, 0.0}});
    }
    const LightingScene lighting(scene);
    GlDirectLight gl(context->functions(), lighting.triangles(), {.resolution = 256});
    for (const glm::dvec3& e : gl.irradiance(lights, outside))
        EXPECT_EQ(e, glm::dvec3(0.0));
    const std::vector<glm::dvec3> lit = gl.irradiance(lights, inside);
    const std::vector<glm::dvec3> reference = directIrradiance(lighting, lights, inside, {.path = LightingPath::Reference});
    for (std::size_t j = 0; j < inside.size(); ++j) {
        EXPECT_GT(reference[j].x, 0.0);
        EXPECT_NEAR(lit[j].x, reference[j].x, 1e-5 * reference[j].x);
    }
}

TEST_F(GlDirectLightTest, BatchesOfFewerMapsGiveTheSameAnswer)
{
    const Scene scene = furnishedFloor(glm::vec3(0.0f));
    const std::vector<Light> lights = allKinds(glm::dvec3(0.0));
    const std::vector<ShadingPoint> points = floorPoints(glm::dvec3(0.0), 16);
    const LightingScene lighting(scene);
    GlDirectLight all(context->functions(), lighting.triangles(), {.resolution = 128});
    GlDirectLight threeAtATime(context->functions(), lighting.triangles(), {.resolution = 128, .mapBytes = 3 * 128 * 128 * 4});
    GlDirectLightStats stats;
    const std::vector<glm::dvec3> a = all.irradiance(lights, points);
    const std::vector<glm::dvec3> b = threeAtATime.irradiance(lights, points, &stats);
    EXPECT_EQ(stats.batches, (lightEmitters(lights).size() + 2) / 3);
    for (std::size_t j = 0; j < points.size(); ++j)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(a[j][c], b[j][c], 1e-5 * std::max(a[j][c], 1e-9));
}

TEST_F(GlDirectLightTest, AResolutionOutsideItsRangeIsRefused)
{
    const Scene scene;
    const LightingScene lighting(scene);
    EXPECT_THROW(GlDirectLight(context->functions(), lighting.triangles(), {.resolution = 8}), Error);
    EXPECT_THROW(GlDirectLight(context->functions(), lighting.triangles(), {.resolution = 100000}), Error);
}
