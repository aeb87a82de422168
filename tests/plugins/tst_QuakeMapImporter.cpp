// Quake map sources: the parser against hand-written brushes (standard and Valve 220 alignment,
// comments, Quake 3 blocks), and id's dm4.map against the dm4.bsp id's tools compiled from it:
// a point well inside a world brush is solid in the BSP, and no open point of the BSP lies well
// inside one. Bad text gets one line naming the line.

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <random>

#include <glm/geometric.hpp>
#include <unistd.h>

#include "plugins/QuakeMap.h"
#include "plugins/SceneFormats.h"
#include "visibility/Error.h"
#include "visibility/InputFile.h"
#include "visibility/bsp/QuakeBsp.h"

using namespace sightline;
namespace fs = std::filesystem;

namespace {

const std::string kMap = SIGHTLINE_TEST_DATA "/levels/quake-dm4.map";
const std::string kBsp = SIGHTLINE_TEST_DATA "/levels/quake-dm4.bsp";

/// A 64-unit cube at the origin, in id's plane order, then the same in Valve 220 form.
const char* const kCube = R"(// a comment
{
"classname" "worldspawn"
{
( 0 0 0 ) ( 0 64 0 ) ( 0 64 64 ) WALL 0 0 0 1 1
( 64 64 0 ) ( 64 0 0 ) ( 64 0 64 ) WALL 0 0 0 1 1
( 64 0 0 ) ( 0 0 0 ) ( 0 0 64 ) {GRATE 0 0 0 1 1
( 0 64 0 ) ( 64 64 0 ) ( 64 64 64 ) WALL 0 0 0 1 1
( 0 64 0 ) ( 0 0 0 ) ( 64 0 0 ) *WATER 0 0 0 1 1
( 0 0 64 ) ( 0 64 64 ) ( 64 64 64 ) WALL [ 1 0 0 0 ] [ 0 -1 0 0 ] 0 1 1
}
{
patchDef2
{
NULL
( 3 3 0 0 0 )
( ( ( 0 0 0 0 0 ) ) )
}
}
}
{
"classname" "func_door"
{
( 0 0 0 ) ( 0 64 0 ) ( 0 64 64 ) DOOR 0 0 0 1 1
( 64 64 0 ) ( 64 0 0 ) ( 64 0 64 ) DOOR 0 0 0 1 1
( 64 0 0 ) ( 0 0 0 ) ( 0 0 64 ) DOOR 0 0 0 1 1
( 0 64 0 ) ( 64 64 0 ) ( 64 64 64 ) DOOR 0 0 0 1 1
( 0 64 0 ) ( 0 0 0 ) ( 64 0 0 ) DOOR 0 0 0 1 1
( 0 0 64 ) ( 0 64 64 ) ( 64 64 64 ) DOOR 0 0 0 1 1
}
}
)";

} // namespace

TEST(QuakeMap, ReadsBrushesAsConvexSolidsWithOutwardFaces)
{
    const QuakeMap map = parseQuakeMap(kCube, "cube.map");
    ASSERT_EQ(map.entities.size(), 2u);
    EXPECT_EQ(map.entities[0].classname(), "worldspawn");
    EXPECT_EQ(map.leftOut, 1u);
    ASSERT_EQ(map.entities[0].brushes.size(), 1u);
    const MapBrush& cube = map.entities[0].brushes[0];
    ASSERT_EQ(cube.planes.size(), 6u);
    EXPECT_EQ(cube.planes[2].texture, "{GRATE");
    EXPECT_TRUE(insideBrush(cube, {32, 32, 32}, 1.0));
    EXPECT_FALSE(insideBrush(cube, {32, 32, 65}, 0.0));
    const std::vector<BrushFace> faces = brushFaces(cube);
    ASSERT_EQ(faces.size(), 6u);
    for (const BrushFace& face : faces) {
        ASSERT_EQ(face.polygon.size(), 4u);
        glm::dvec3 centre(0.0);
        for (const glm::dvec3& p : face.polygon) {
            for (int a = 0; a < 3; ++a)
                EXPECT_TRUE(std::abs(p[a]) < 1e-6 || std::abs(p[a] - 64.0) < 1e-6) << "a corner of the cube";
            centre += p / 4.0;
        }
        // Counter-clockwise seen from outside: the winding's normal points out of the cube.
        const glm::dvec3 n = glm::cross(face.polygon[1] - face.polygon[0], face.polygon[2] - face.polygon[0]);
        EXPECT_GT(glm::dot(n, centre - glm::dvec3(32.0)), 0.0);
    }

    // As a scene: the water face and the door are left out, each said once.
    const fs::path file = fs::temp_directory_path() / ("sightline_cube_" + std::to_string(::getpid()) + ".map");
    std::ofstream(file) << kCube;
    std::vector<std::string> warnings;
    const Scene scene = loadScene(file, &warnings);
    fs::remove(file);
    EXPECT_EQ(scene.triangleCount(), 10u);
    EXPECT_EQ(warnings.size(), 3u);
}

TEST(QuakeMap, Dm4sBrushesAreTheSolidOfTheBspCompiledFromIt)
{
    const QuakeMap map = parseQuakeMap(readInputFile(kMap, "dm4.map"), "dm4.map");
    const bsp::QuakeBsp level = bsp::readQuakeBsp(readInputFile(kBsp, "dm4.bsp"), "dm4.bsp");
    std::vector<const MapBrush*> solid;   // world brushes of plain textures: solid in hull 0
    for (const MapEntity& e : map.entities) {
        if (e.classname() != "worldspawn")
            continue;
        for (const MapBrush& b : e.brushes) {
            bool plain = true;
            for (const MapPlane& p : b.planes) {
                std::string t = p.texture;
                for (char& c : t)
                    c = char(std::tolower(static_cast<unsigned char>(c)));
                plain = plain && t[0] != '*' && t.rfind("sky", 0) != 0 && t != "clip" && t != "trigger";
            }
            if (plain)
                solid.push_back(&b);
        }
    }
    ASSERT_GT(solid.size(), 500u);

    std::size_t insideChecked = 0, openChecked = 0;
    // Inside: each brush's face centres pulled towards the brush's centre.
    for (const MapBrush* b : solid) {
        const std::vector<BrushFace> faces = brushFaces(*b);
        glm::dvec3 centre(0.0);
        std::size_t corners = 0;
        for (const BrushFace& f : faces)
            for (const glm::dvec3& p : f.polygon)
                centre += p, ++corners;
        centre /= double(corners);
        for (const BrushFace& f : faces) {
            glm::dvec3 middle(0.0);
            for (const glm::dvec3& p : f.polygon)
                middle += p / double(f.polygon.size());
            const glm::dvec3 q = middle + (centre - middle) * 0.5;
            if (!insideBrush(*b, q, 2.0))
                continue;   // a brush too thin to hold a point 2 units from every face
            ++insideChecked;
            EXPECT_EQ(level.leaves[std::size_t(bsp::leafAt(level, q))].contents, bsp::kContentsSolid)
                << "brush at line " << b->line << ", point " << q.x << " " << q.y << " " << q.z;
        }
    }
    // Open: random points the BSP calls empty lie in no world brush.
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> x(level.mins.x, level.maxs.x), y(level.mins.y, level.maxs.y),
        z(level.mins.z, level.maxs.z);
    for (int k = 0; k < 200000; ++k) {
        const glm::dvec3 q(x(random), y(random), z(random));
        if (level.leaves[std::size_t(bsp::leafAt(level, q))].contents != bsp::kContentsEmpty)
            continue;
        ++openChecked;
        for (const MapBrush* b : solid)
            ASSERT_FALSE(insideBrush(*b, q, 1.0)) << "brush at line " << b->line;
    }
    EXPECT_GT(insideChecked, 1000u);
    EXPECT_GT(openChecked, 1000u);

    std::vector<std::string> warnings;
    const Scene scene = loadScene(kMap, &warnings);
    EXPECT_GT(scene.triangleCount(), 5000u);
    const Bounds bounds = scene.bounds();
    // The same place as the compiled level's (metres, Y up): within a brush's thickness.
    EXPECT_NEAR(bounds.min.y, level.mins.z * 0.0254, 0.5);
    EXPECT_NEAR(bounds.max.y, level.maxs.z * 0.0254, 0.5);
}

TEST(QuakeMap, BadTextGetsOneLineNamingTheLine)
{
    auto refuses = [](const std::string& text, const std::string& words) {
        try {
            parseQuakeMap(text, "bad.map");
            ADD_FAILURE() << "accepted; expected: " << words;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        }
    };
    refuses("{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 0 nan 0 ) ( 1 1 1 ) T 0 0 0 1 1\n}\n}", "bad.map:4: expected a number");
    refuses("{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1e300 1 1 ) T 0 0 0 1 1\n}\n}", "beyond");
    refuses("{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 1 1 ) T 0 0 0 1 1\n", "found the end");
    refuses("{\n\"classname\" \"worldspawn\n}", "not closed");
    refuses("}", "expected '{'");
    refuses("{ \"key\" }", "no quoted value");
    refuses("{ { junk } }", "patchDef/brushDef");
}
