// The shadow proofs of the lights' fast path (lighting/src/lights/ShaftBlocker.h): a triangle or a
// fused convex quadrilateral blocks a whole shaft only when every segment of it crosses, checked
// here against dense samples of the shaft's segments by the contract's own test.
#include <array>
#include <random>

#include <gtest/gtest.h>

#include "lights/ShaftBlocker.h"
#include "visibility/ExactSegment.h"

using namespace sightline;
using namespace sightline::lights;

namespace {

/// Whether every sampled segment from the light's corners' hull to the box crosses triangle abc
/// or triangle dcb (a brute-force reading of what the proofs claim).
bool everySampleBlocked(const std::vector<glm::dvec3>& from, const std::array<glm::dvec3, 8>& box, const glm::dvec3& a,
                        const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3* d)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int k = 0; k < 4000; ++k) {
        glm::dvec3 p(0.0), q(0.0);
        double wp = 0.0, wq = 0.0;
        for (const glm::dvec3& f : from) {
            const double w = unit(rng);
            p += w * f, wp += w;
        }
        for (const glm::dvec3& corner : box) {
            const double w = unit(rng);
            q += w * corner, wq += w;
        }
        p /= wp, q /= wq;
        if (!segmentCrossesTriangle(p, q, a, b, c) && !(d && segmentCrossesTriangle(p, q, *d, c, b)))
            return false;
    }
    return true;
}

std::array<glm::dvec3, 8> boxCorners(const glm::dvec3& lo, const glm::dvec3& hi)
{
    std::array<glm::dvec3, 8> corners;
    for (int c = 0; c < 8; ++c)
        corners[std::size_t(c)] = {(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
    return corners;
}

} // namespace

TEST(ShaftBlocker, ATriangleCoveringTheShaftBlocksItAndOneThatDoesNotDoesNot)
{
    const std::vector<glm::dvec3> light = {{0.0, 2.0, -2.0}};
    const auto box = boxCorners({-0.3, 0.0, 1.0}, {0.3, 0.2, 1.5});
    const glm::dvec3 a(-3, -1, 0), b(3, -1, 0), c(0, 4, 0);   // a big triangle in z = 0
    EXPECT_TRUE(triangleBlocksShaft(a, b, c, light, box));
    EXPECT_TRUE(everySampleBlocked(light, box, a, b, c, nullptr));
    const glm::dvec3 small(0.1, 0.5, 0);   // one that covers only part of the shaft
    EXPECT_FALSE(triangleBlocksShaft(a, b, small, light, box));
    EXPECT_FALSE(everySampleBlocked(light, box, a, b, small, nullptr));
    // A box reaching back through the triangle's plane is not separated from the light.
    EXPECT_FALSE(triangleBlocksShaft(a, b, c, light, boxCorners({-0.3, 0.0, -0.1}, {0.3, 0.2, 1.5})));
}

TEST(ShaftBlocker, AConvexQuadOfTwoCoplanarTrianglesBlocksWhereNeitherAloneDoes)
{
    // The quad x, y in [-1, 1] at z = 0, split along its diagonal from (-1, -1) to (1, 1).
    const glm::dvec3 a(1, -1, 0), b(-1, -1, 0), c(1, 1, 0), d(-1, 1, 0);   // (a, b, c) and (d, c, b)
    const std::vector<glm::dvec3> light = {{-0.2, -0.2, -1.0}, {0.2, -0.2, -1.0}, {-0.2, 0.2, -1.0}, {0.2, 0.2, -1.0}};
    const auto box = boxCorners({-0.3, -0.3, 1.0}, {0.3, 0.3, 1.2});
    EXPECT_FALSE(triangleBlocksShaft(a, b, c, light, box));
    EXPECT_FALSE(triangleBlocksShaft(d, c, b, light, box));
    EXPECT_TRUE(quadBlocksShaft(a, b, c, d, light, box));
    EXPECT_TRUE(everySampleBlocked(light, box, a, b, c, &d));
    // Not convex (d pulled inside across the diagonal's far side): refused, and indeed leaky.
    const glm::dvec3 dent(0.1, 0.1, 0.0);
    EXPECT_FALSE(quadBlocksShaft(a, b, c, dent, light, box));
    // Not exactly coplanar: refused.
    EXPECT_FALSE(quadBlocksShaft(a, b, c, glm::dvec3(-1, 1, 1e-9), light, box));
}

TEST(ShaftBlocker, ParallelSegmentsOfADirectionalLight)
{
    const auto box = boxCorners({-0.3, 0.0, -0.3}, {0.3, 0.1, 0.3});
    std::array<glm::dvec3, 8> ends;
    for (std::size_t k = 0; k < 8; ++k)
        ends[k] = box[k] + glm::dvec3(0.5, 50.0, 0.0);   // towards the sun, far above
    const glm::dvec3 a(-5, 3, -5), b(5, 3, -5), c(0, 3, 8);   // a roof triangle
    EXPECT_TRUE(triangleBlocksParallel(a, b, c, box, ends));
    EXPECT_FALSE(triangleBlocksParallel(a, b, glm::dvec3(0, 3, -4), box, ends));
}
