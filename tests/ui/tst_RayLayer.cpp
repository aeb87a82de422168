// How the viewport draws many rays (editor/RayLayer.h): each ray's opacity from the expected overlap,
// the layer's resolution, the rays listed for drawing, and the picture itself: a dense
// bundle is a haze of the same density at any ray count, never an opaque slab.
#include <cmath>

#include <gtest/gtest.h>

#include "editor/Camera.h"
#include "EditorDocument.h"
#include "OffscreenRender.h"
#include "editor/RayLayer.h"
#include "UiTestScene.h"
#include "editor/ViewSettings.h"
#include "editor/ViewportRenderer.h"

using namespace sightline;
using namespace sightline::ui;
using namespace sightline::test;

TEST(RayLayer, EachRaysOpacityMakesAnOpenShaftReachTheCoverageAtAnyDensity)
{
    for (const double coverage : {0.3, 0.8}) {
        for (const double overlap : {0.25, 1.0, 3.0, 40.0, 5000.0}) {
            for (const int divisor : {1, 2, 4, 8}) {
                const double a = rayOpacity(coverage, overlap, divisor);
                EXPECT_GT(a, 0.0);
                EXPECT_LE(a, coverage + 1e-7) << "a single ray is never more than the coverage";
                // overlap x divisor rays cross a pixel of the layer.
                const double n = overlap * divisor;
                if (n >= 1.0) {
                    EXPECT_NEAR(1.0 - std::pow(1.0 - a, n), coverage, 1e-5) << overlap << " " << divisor;
                }
            }
        }
    }
    // Opaque rays stay opaque (tests and prints ask for crisp colours).
    EXPECT_EQ(rayOpacity(1.0, 5000.0, 4), 1.0f);
    // Sparse rays are drawn at full resolution; dense ones in a coarser layer.
    EXPECT_EQ(rayLayerDivisor(1.5), 1);
    EXPECT_EQ(rayLayerDivisor(5.0), 2);
    EXPECT_EQ(rayLayerDivisor(100.0), 4);
    EXPECT_EQ(rayLayerDivisor(5000.0), 8);
}

TEST(RayLayer, TheBundleOnScreenIsTheHullOfThePatchesCorners)
{
    const auto [source, receiver] = floorPatches();
    const Camera camera = shaftView(source, receiver);
    const glm::mat4 viewProj = camera.projection(1280.0 / 720.0, 16.0) * camera.view();
    const auto bundle = bundleOnScreen(viewProj, 1280, 720, source, receiver);
    ASSERT_TRUE(bundle);
    // The corners' rectangle holds both centres (y from the bottom in GL's pixels).
    for (const glm::dvec3& centre : {source.centre(), receiver.centre()}) {
        const glm::dvec3 p = toPixels(camera, centre, 1280, 720);
        EXPECT_GE(p.x, bundle->min.x - 1e-6);
        EXPECT_LE(p.x, bundle->max.x + 1e-6);
        EXPECT_GE(720.0 - p.y, bundle->min.y - 1e-6);
        EXPECT_LE(720.0 - p.y, bundle->max.y + 1e-6);
    }
    const double s = glm::length(glm::dvec2(toPixels(camera, source.centre(), 1280, 720)) -
                                 glm::dvec2(toPixels(camera, receiver.centre(), 1280, 720)));
    EXPECT_NEAR(bundle->length, s, 1e-3);   // float matrices
    const glm::dvec2 extent = bundle->max - bundle->min;
    EXPECT_GT(bundle->area, 0.2 * extent.x * extent.y);
    EXPECT_LE(bundle->area, extent.x * extent.y + 1e-6);
    EXPECT_NEAR(expectedOverlap(*bundle, 4096), 4096.0 * bundle->length / bundle->area, 1e-9);

    // A corner behind the eye: no estimate.
    Camera inside = camera;
    inside.target = 0.5 * (source.centre() + receiver.centre());
    inside.distance = 0.1;
    EXPECT_FALSE(bundleOnScreen(inside.projection(1280.0 / 720.0, 16.0) * inside.view(), 1280, 720, source, receiver));
}

TEST(RayLayer, TheDrawnRaysAreListedNotTheWholeMap)
{
    HiddenSampleMap map(64, 32, 32);   // 64 source samples, 32 x 32 receiver samples
    for (int j = 0; j < 1024; ++j)
        for (int i = 0; i < 64; ++i)
            if ((i + j) % 3 == 0)
                map.setBlocked(j, i);
    for (const int cap : {1 << 16, 4096}) {
        const RaySubset subset = raySubset(64, 1024, cap);
        const std::vector<std::uint32_t> free = freeDrawnRays(map, subset);
        const std::vector<std::uint32_t> bits = blockedDrawnRays(map, subset);
        ASSERT_EQ(bits.size(), (subset.count() + 31) / 32);
        std::size_t expected = 0;
        for (std::uint32_t k = 0, next = 0; k < subset.count(); ++k) {
            const auto [j, i] = subsetRay(subset, k);
            ASSERT_EQ(((bits[k / 32] >> (k % 32)) & 1u) != 0, map.blocked(int(j), int(i))) << k;
            if (map.blocked(int(j), int(i)))
                continue;
            ++expected;
            ASSERT_LT(next, free.size());
            ASSERT_EQ(free[next++], k);
        }
        EXPECT_EQ(free.size(), expected);
        EXPECT_NEAR(double(free.size()) / double(subset.count()), 2.0 / 3.0, 0.02);
    }
}

namespace {

/// How far a pixel went from `under` towards `over`, in the channel where they differ most.
double coverageAt(QRgb pixel, QRgb under, const glm::vec3& over)
{
    const double channels[3][2] = {{double(qRed(pixel)), double(qRed(under))},
                                   {double(qGreen(pixel)), double(qGreen(under))},
                                   {double(qBlue(pixel)), double(qBlue(under))}};
    int best = 0;
    double spread = 0.0;
    for (int c = 0; c < 3; ++c)
        if (std::abs(255.0 * over[c] - channels[c][1]) > spread) {
            spread = std::abs(255.0 * over[c] - channels[c][1]);
            best = c;
        }
    return (channels[best][0] - channels[best][1]) / (255.0 * over[best] - channels[best][1]);
}

} // namespace

// 1M rays drawn were an opaque slab (each ray's opacity fell only as 1/sqrt(count)).
TEST(OffscreenRender, ADenseBundleIsAHazeOfTheSameDensityAtAnyRayCount)
{
    const auto folder = freshFolder("ray-density");
    EditorDocument document;
    document.open(writeFloorObj(folder));
    auto [source, receiver] = floorPatches();
    source.na = source.nb = receiver.na = receiver.nb = 32;   // 1,048,576 rays
    document.setState({ObjectKind::Source, 0}, source, "place");
    document.setState({ObjectKind::Receiver, 0}, receiver, "place");
    const Camera camera = shaftView(source, receiver);
    ViewStyle style;
    const glm::dvec3 inside = source.centre() + 0.15 * (receiver.centre() - source.centre());
    const glm::dvec3 pixel = toPixels(camera, inside, 320, 240);
    style.showRays = false;
    const QRgb under = renderOffscreen(document, camera, style, 320, 240).image.pixel(int(pixel.x), int(pixel.y));
    style.showRays = true;
    std::vector<double> coverages;
    for (const int cap : {4096, 65536, 1 << 20}) {
        style.rayCap = cap;
        const OffscreenResult image = renderOffscreen(document, camera, style, 320, 240);
        if (const char* shots = std::getenv("SIGHTLINE_RAY_SHOTS"))
            image.image.save(QString("%1/density-%2.png").arg(shots).arg(cap));
        ASSERT_EQ(image.raysDrawn, std::uint64_t(cap));
        const double c = coverageAt(image.image.pixel(int(pixel.x), int(pixel.y)), under, glm::vec3(style.freeColour));
        EXPECT_GT(c, 0.5) << cap << " rays: the open shaft reads clearly";
        EXPECT_LT(c, 0.95) << cap << " rays: not an opaque slab";
        coverages.push_back(c);
    }
    EXPECT_NEAR(coverages[1], coverages[0], 0.12);
    EXPECT_NEAR(coverages[2], coverages[0], 0.12);
}
