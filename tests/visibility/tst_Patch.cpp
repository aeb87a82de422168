#include <gtest/gtest.h>

#include "TestScenes.h"
#include "base/Error.h"
#include "visibility/Patch.h"

using namespace sightline;
using namespace sightline::test;

TEST(Patch, SamplePositionsAndBitIndexFollowTheContract)
{
    Patch p;
    p.corner = {1, 2, 3};
    p.u = {4, 0, 0};
    p.v = {0, 0, -2};
    p.na = 4;
    p.nb = 2;
    // (a, b) = (3, 1): c + 3.5/4 u + 1.5/2 v
    const glm::dvec3 s = p.sample(3, 1);
    EXPECT_DOUBLE_EQ(s.x, 1 + 3.5);
    EXPECT_DOUBLE_EQ(s.y, 2);
    EXPECT_DOUBLE_EQ(s.z, 3 - 1.5);
    EXPECT_EQ(p.sample(1 * 4 + 3), s);   // bit index b * na + a
    EXPECT_EQ(p.sampleCount(), 8);
    const glm::dvec3 n = p.normal();     // (4,0,0) x (0,0,-2) = (0, 8, 0)
    EXPECT_DOUBLE_EQ(n.y, 1.0);
}

TEST(Patch, ValidPairsAcceptedInvalidOnesRefused)
{
    EXPECT_NO_THROW(validatePatchPair(xyPatch(0, 32, 32), xyPatch(5, 32, 32)));
    // Perpendicular but each on one side of the other: a floor patch seen from a wall patch.
    Patch floor;
    floor.corner = {0, -1, 1};
    floor.u = {1, 0, 0};
    floor.v = {0, 0, 1};
    EXPECT_NO_THROW(validatePatchPair(xyPatch(0, 4, 4), floor));
    // Touching the other's plane with one corner.
    floor.corner = {0, -1, 0};
    EXPECT_THROW(validatePatchPair(xyPatch(0, 4, 4), floor), Error);
    // Receiver in the source plane but source not in... (crossing)
    Patch crossing = xyPatch(2, 4, 4);
    crossing.corner.z = -1;
    crossing.v = {0, 1, 3};
    EXPECT_THROW(validatePatchPair(xyPatch(0, 4, 4), crossing), Error);
    // Limits: 1x1 and 32x32 source, 1024 source samples, 512x512 receiver.
    EXPECT_NO_THROW(validatePatchPair(xyPatch(0, 1, 1), xyPatch(2, 512, 512)));
    EXPECT_NO_THROW(validatePatchPair(xyPatch(0, 32, 32), xyPatch(2, 1, 1)));
    EXPECT_NO_THROW(validatePatchPair(xyPatch(0, 1024, 1), xyPatch(2, 1, 1)));
    EXPECT_THROW(validatePatchPair(xyPatch(0, 1025, 1), xyPatch(2, 1, 1)), Error);
    EXPECT_THROW(validatePatchPair(xyPatch(0, 4, 4), xyPatch(2, 4, 2000)), Error);
    try {
        validatePatchPair(xyPatch(0, 0, 8), xyPatch(2, 8, 8));
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("source"), std::string::npos);
    }
}
