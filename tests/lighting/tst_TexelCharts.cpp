// Light-map charts (lighting/TexelCharts.h): coplanar neighbours share one grid, so a floor of
// many triangles has no seam; texels sample the surface; an evenly lit floor has no step across
// its triangles' shared edges.
#include <cmath>

#include <gtest/gtest.h>

#include "TestScenes.h"
#include "lighting/DirectLight.h"
#include "lighting/TexelCharts.h"
#include "base/Error.h"
#include "visibility/ExactJudge.h"

using namespace sightline;

namespace {

/// An n x n grid of unit quads in y = 0 (2 n^2 triangles), facing up, and a wall x = 0 beside it.
Scene floorAndWall(int n)
{
    Mesh floor;
    floor.name = "floor";
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            floor.positions.emplace_back(float(i), 0.0f, float(j));
    const auto at = [&](int i, int j) { return std::uint32_t(i * (n + 1) + j); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            floor.indices.insert(floor.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    return test::sceneOf({floor, test::quad({0, 0, 0}, {0, 0, float(n)}, {0, 2, 0}, "wall")});
}

double distanceToSurface(const AoOccluders& occluders, const glm::dvec3& p)
{
    double best = INFINITY;
    for (std::size_t t = 0; t < occluders.triangleCount(); ++t) {
        const glm::dvec3 a(occluders.vertices[occluders.indices[3 * t]]), b(occluders.vertices[occluders.indices[3 * t + 1]]),
            c(occluders.vertices[occluders.indices[3 * t + 2]]);
        best = std::min(best, std::sqrt(judge_detail::pointTriangleDistance2(p, a, b, c)));
    }
    return best;
}

} // namespace

TEST(TexelCharts, CoplanarNeighboursShareOneGridWithoutSeams)
{
    const Scene scene = floorAndWall(4);
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points;
    const ChartLayout layout = chartTexelPoints(occluders, 4.0, points);
    ASSERT_EQ(layout.charts.size(), 2u);   // the floor's 32 triangles, the wall's 2
    EXPECT_EQ(layout.charts[0].triangles.size(), 32u);
    EXPECT_EQ(layout.charts[1].triangles.size(), 2u);
    // A vertex has one uv whichever floor triangle it is taken from: no seam.
    for (std::uint32_t t = 0; t < 32; ++t)
        for (std::uint32_t u = 0; u < 32; ++u)
            for (int c = 0; c < 3; ++c)
                for (int d = 0; d < 3; ++d)
                    if (occluders.vertices[occluders.indices[3 * t + std::uint32_t(c)]] == occluders.vertices[occluders.indices[3 * u + std::uint32_t(d)]]) {
                        EXPECT_EQ(layout.uv(occluders, t, c), layout.uv(occluders, u, d));
                    }
    // 4 m at 4 texels a metre, with a one-texel border.
    EXPECT_EQ(layout.charts[0].width, 18);
    EXPECT_EQ(layout.charts[0].height, 18);
    ASSERT_EQ(points.size(), std::size_t(18 * 18 + layout.charts[1].width * layout.charts[1].height));
    int ok = 0;
    for (std::size_t k = 0; k < points.size(); ++k)
        if (points.status[k] == AoPointStatus::Ok) {
            ++ok;
            EXPECT_LT(distanceToSurface(occluders, glm::dvec3(points.positions[k])), 1e-6) << k;
            EXPECT_NEAR(glm::length(points.normals[k]), 1.0f, 1e-6f);
        }
    EXPECT_EQ(ok, int(points.size()));   // rectangles: every texel is on or next to the surface
    EXPECT_THROW(chartTexelPoints(occluders, 0.0, points), Error);
    EXPECT_THROW(chartTexelPoints(occluders, 1e5, points), Error);   // far too many texels: refused
}

TEST(TexelCharts, AnEvenlyLitFloorHasNoStepAcrossItsDiagonals)
{
    // A panel far above the floor lights it smoothly; texels on either side of every triangle's
    // diagonal and shared edge follow that smooth field.
    const Scene scene = floorAndWall(4);
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points;
    const ChartLayout layout = chartTexelPoints(occluders, 8.0, points);
    const TexelChart& floor = layout.charts[0];
    std::vector<ShadingPoint> shading;
    for (int q = 0; q < floor.height; ++q)
        for (int s = 0; s < floor.width; ++s) {
            const std::size_t k = floor.firstPoint + std::size_t(q * floor.width + s);
            shading.push_back({glm::dvec3(points.positions[k]) + 1e-3 * glm::dvec3(points.normals[k]), glm::dvec3(points.normals[k])});
        }
    Light panel;
    panel.type = LightType::Area;
    panel.area.corner = {1.0, 6.0, 1.0};
    panel.area.u = {2.0, 0.0, 0.0};
    panel.area.v = {0.0, 0.0, 2.0};   // u x v = -y: facing down
    panel.area.na = panel.area.nb = 4;
    std::vector<Light> lights = {panel};
    validateLights(lights, "test");
    const LightingScene lighting(scene);
    const std::vector<glm::dvec3> e = directIrradiance(lighting, lights, shading);
    // Unshadowed, the irradiance is smooth in position: on one grid its second differences are
    // tiny everywhere; a texel displaced at a seam would show as a spike.
    double largestBend = 0.0, mean = 0.0;
    const auto at = [&](int s, int q) { return e[std::size_t(q * floor.width + s)].x; };
    for (int q = 2; q + 3 < floor.height; ++q)
        for (int s = 2; s + 3 < floor.width; ++s) {
            largestBend = std::max({largestBend, std::abs(at(s + 1, q) - 2.0 * at(s, q) + at(s - 1, q)),
                                    std::abs(at(s, q + 1) - 2.0 * at(s, q) + at(s, q - 1))});
            mean += at(s, q);
        }
    mean /= double((floor.height - 5) * (floor.width - 5));
    EXPECT_GT(mean, 0.0);
    EXPECT_LT(largestBend, 0.002 * mean);
}

// A density too fine for the atlas is refused naming one that fits: the suggestion is taken
// (the level keeps that many texels) and a density 5% above it is refused again; where no
// density fits (every chart keeps its bordered texel), the refusal says so.
TEST(TexelCharts, ARefusedDensityNamesOneThatFits)
{
    const AoOccluders occluders = aoOccluders(floorAndWall(8));
    constexpr std::uint64_t kPixels = 1u << 14;
    std::string message;
    try {
        AoPoints points;
        chartTexelPoints(occluders, 500.0, points, kPixels);
        FAIL() << "500 texels a metre fitted " << kPixels << " pixels";
    } catch (const Error& e) {
        message = e.what();
    }
    const std::size_t at = message.find("try --texel ");
    ASSERT_NE(at, std::string::npos) << message;
    const double suggested = std::stod(message.substr(at + 12));
    ASSERT_GT(suggested, 0.0);
    AoPoints points;
    const ChartLayout layout = chartTexelPoints(occluders, suggested, points, kPixels);
    EXPECT_LE(std::uint64_t(layout.width) * std::uint64_t(layout.height), kPixels);
    EXPECT_GT(points.size(), kPixels / 4);   // not a timid suggestion: a good share of the budget
    AoPoints more;
    EXPECT_THROW(chartTexelPoints(occluders, suggested * 1.05, more, kPixels), Error);
    try {
        AoPoints none;
        chartTexelPoints(occluders, 1.0, none, 8);   // two charts of at least 3 x 3 texels
        FAIL() << "8 pixels held two charts";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("at any density"), std::string::npos) << e.what();
    }
}

// Dilation grows the filled pixels one ring a pass, each new pixel the mean of its filled
// 8-neighbours; pixels beyond the passes stay unfilled, and filled pixels never change.
TEST(TexelCharts, DilationFillsOneRingAPassWithTheNeighboursMean)
{
    const int w = 9, h = 5;
    std::vector<glm::vec3> pixels(w * h, glm::vec3(0.0f));
    std::vector<std::uint8_t> filled(w * h, 0);
    const auto at = [&](int x, int y) { return std::size_t(y * w + x); };
    pixels[at(1, 2)] = glm::vec3(1.0f, 0.0f, 0.0f), filled[at(1, 2)] = 1;
    pixels[at(5, 2)] = glm::vec3(0.0f, 0.0f, 1.0f), filled[at(5, 2)] = 1;
    dilateAtlas(w, h, pixels, filled, 1);
    EXPECT_EQ(pixels[at(0, 1)], glm::vec3(1.0f, 0.0f, 0.0f));   // next to the red one only
    EXPECT_EQ(pixels[at(6, 3)], glm::vec3(0.0f, 0.0f, 1.0f));
    EXPECT_FALSE(filled[at(3, 2)]);   // two pixels from both: not yet
    EXPECT_FALSE(filled[at(8, 2)]);
    dilateAtlas(w, h, pixels, filled, 1);
    ASSERT_TRUE(filled[at(3, 2)]);
    EXPECT_EQ(pixels[at(3, 2)], glm::vec3(0.5f, 0.0f, 0.5f));   // between them: the mean of both sides
    EXPECT_EQ(pixels[at(1, 2)], glm::vec3(1.0f, 0.0f, 0.0f));   // the texels themselves unchanged
    EXPECT_FALSE(filled[at(8, 2)]);   // three pixels from the blue one
    dilateAtlas(w, h, pixels, filled, 10);
    for (std::size_t k = 0; k < filled.size(); ++k)
        EXPECT_TRUE(filled[k]) << k;
    std::vector<std::uint8_t> wrong(3, 0);
    EXPECT_THROW(dilateAtlas(w, h, pixels, wrong, 1), Error);
}

