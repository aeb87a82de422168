// One bounce of indirect light by VPLs (lighting/Indirect.h) against a closed form: inside a
// closed sphere of radius R and albedo rho, every point's first bounce is rho Phi / (4 pi R^2)
// wherever the light is (the form factor between two points of a sphere, cos cos / (pi d^2) dA,
// is dA / (4 pi R^2) everywhere), and each VPL contributes exactly its share of it. The
// Monte-Carlo gathering reference answers the same within its noise.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "TestLights.h"
#include "TestScenes.h"
#include "lighting/DirectLight.h"
#include "lighting/Indirect.h"
#include "base/Error.h"

using namespace sightline;

namespace {

constexpr double kR = 2.0;

/// A closed latitude-longitude sphere of radius kR around the origin.
Mesh sphere(int rings, int segments)
{
    Mesh m;
    m.name = "sphere";
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const double theta = std::numbers::pi * i / rings, phi = 2.0 * std::numbers::pi * j / segments;
            m.positions.emplace_back(float(kR * std::sin(theta) * std::cos(phi)), float(kR * std::cos(theta)),
                                     float(kR * std::sin(theta) * std::sin(phi)));
        }
    const auto at = [&](int i, int j) { return std::uint32_t(i * segments + (j % segments)); };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j)
            m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    return m;
}

/// Points on the sphere's inside, facing its centre, 1 cm in.
std::vector<ShadingPoint> insidePoints()
{
    std::vector<ShadingPoint> points;
    for (int k = 0; k < 24; ++k) {
        const double theta = 0.3 + 2.5 * k / 23.0, phi = 2.4 * k;
        const glm::dvec3 out(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
        points.push_back({(kR - 0.01) * out, -out});
    }
    return points;
}

} // namespace

TEST(Indirect, VplsInsideASphereGiveTheClosedForm)
{
    const Scene scene = test::sceneOf({sphere(96, 192)});
    const LightingScene lighting(scene);
    std::vector<Light> lights = {test::pointLight({0.5, 0.3, -0.2}, 10.0)};
    validateLights(lights, "test");
    IndirectOptions options;
    options.vpls = 2000;
    options.albedo = 0.6;
    options.clampMetres = 0.0;
    const VplSet vpls = traceVpls(lighting, lights, options);
    const double phi = 4.0 * std::numbers::pi * 10.0;
    EXPECT_EQ(vpls.photons, 2000);
    EXPECT_EQ(vpls.vpls.size(), 2000u);   // a closed sphere keeps every photon
    EXPECT_NEAR(vpls.emitted.x, phi, 1e-9 * phi);
    const double expected = options.albedo * phi / (4.0 * std::numbers::pi * kR * kR);
    const std::vector<ShadingPoint> points = insidePoints();
    const IndirectResult result = vplIrradiance(lighting, vpls, points, options);
    for (const glm::dvec3& e : result.irradiance)
        EXPECT_NEAR(e.x, expected, 0.015 * expected);   // the tessellation's share only
    EXPECT_EQ(result.clampLoss, 0.0);

    // The clamp takes energy from VPLs nearer than it, and says how much.
    options.clampMetres = 0.5;
    const IndirectResult clamped = vplIrradiance(lighting, traceVpls(lighting, lights, options), points, options);
    EXPECT_GT(clamped.clampLoss, 0.0);
    EXPECT_LT(clamped.clampLoss, 0.05);
    for (std::size_t j = 0; j < points.size(); ++j)
        EXPECT_LE(clamped.irradiance[j].x, result.irradiance[j].x * (1.0 + 1e-12));

    // The gathering reference, 400 directions a point: within its noise.
    options.clampMetres = 0.0;
    const std::vector<glm::dvec3> gathered = gatheredIndirect(lighting, lights, points, 400, options);
    double mean = 0.0;
    for (const glm::dvec3& e : gathered)
        mean += e.x / double(gathered.size());
    EXPECT_NEAR(mean, expected, 0.01 * expected);
}

// Each surface's own albedo, per channel: with a point light at the centre each hemisphere takes
// half the flux, and the uniform form factor spreads each half evenly, so every point's bounce is
// (rho_upper + rho_lower) / 2 x Phi / (4 pi R^2), channel by channel. The lower half's albedo is
// unknown (a texture not decoded): the options' albedo stands in for it there alone.
TEST(Indirect, SurfaceAlbedosColourTheBouncePerChannel)
{
    const int rings = 96, segments = 192;
    Mesh coloured = sphere(rings, segments);
    const glm::vec3 upper(0.8f, 0.0f, 0.2f);
    for (int i = 0; i < rings; ++i)   // two triangles per (ring, segment), ring 0 at the top
        coloured.albedo.insert(coloured.albedo.end(), std::size_t(2 * segments), i < rings / 2 ? upper : kUnknownAlbedo);
    const Scene scene = test::sceneOf({coloured});
    const LightingScene lighting(scene);
    std::vector<Light> lights = {test::pointLight({0.0, 0.0, 0.0}, 10.0)};
    validateLights(lights, "test");
    IndirectOptions options;
    options.vpls = 20000;
    options.albedo = 0.3;
    options.clampMetres = 0.0;
    const double phi = 4.0 * std::numbers::pi * 10.0;
    const glm::dvec3 expected = 0.5 * (glm::dvec3(upper) + glm::dvec3(options.albedo)) * phi / (4.0 * std::numbers::pi * kR * kR);
    const std::vector<ShadingPoint> points = insidePoints();
    const IndirectResult result = vplIrradiance(lighting, traceVpls(lighting, lights, options), points, options);
    const std::vector<glm::dvec3> gathered = gatheredIndirect(lighting, lights, points, 400, options);
    glm::dvec3 gatheredMean(0.0);
    for (std::size_t j = 0; j < points.size(); ++j) {
        for (int c = 0; c < 3; ++c)   // the tessellation's share and the photons' split between the halves
            EXPECT_NEAR(result.irradiance[j][c], expected[c], 0.03 * expected[c]) << "point " << j << " channel " << c;
        gatheredMean += gathered[j] / double(points.size());
    }
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(gatheredMean[c], expected[c], 0.03 * expected[c]) << "channel " << c;
}

TEST(Indirect, VplsAreDeterministicPerSeedAndOptionsAreChecked)
{
    const Scene scene = test::sceneOf({sphere(16, 32)});
    const LightingScene lighting(scene);
    std::vector<Light> lights = {test::pointLight({0.0, 0.5, 0.0}, 1.0)};
    validateLights(lights, "test");
    IndirectOptions options;
    options.vpls = 50;
    const VplSet a = traceVpls(lighting, lights, options), b = traceVpls(lighting, lights, options);
    ASSERT_EQ(a.vpls.size(), b.vpls.size());
    for (std::size_t k = 0; k < a.vpls.size(); ++k)
        EXPECT_EQ(a.vpls[k].area.corner, b.vpls[k].area.corner);
    options.seed = 2;
    EXPECT_NE(traceVpls(lighting, lights, options).vpls[0].area.corner, a.vpls[0].area.corner);
    for (const auto& bad : {IndirectOptions{.vpls = 0}, IndirectOptions{.vpls = 2000000}, IndirectOptions{.albedo = 1.0},
                            IndirectOptions{.albedo = -0.1}, IndirectOptions{.clampMetres = -1.0},
                            IndirectOptions{.clampMetres = NAN}})
        EXPECT_THROW(validateIndirectOptions(bad), Error);
}
