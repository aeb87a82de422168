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
#include "base/Error.h"
#include "base/InputFile.h"
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

namespace {

/// Whether segment p-q crosses triangle abc strictly between its ends (double, Moeller-Trumbore).
bool crosses(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    const glm::dvec3 d = q - p, e1 = b - a, e2 = c - a, h = glm::cross(d, e2);
    const double det = glm::dot(e1, h);
    if (std::abs(det) < 1e-12)
        return false;
    const glm::dvec3 s = p - a;
    const double u = glm::dot(s, h) / det;
    const glm::dvec3 k = glm::cross(s, e1);
    const double v = glm::dot(d, k) / det, t = glm::dot(e2, k) / det;
    return u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 1e-9 && t < 1.0 - 1e-9;
}

std::string cube(glm::dvec3 lo, glm::dvec3 hi, const std::string& texture = "WALL")
{
    auto pt = [](double x, double y, double z) {
        return "( " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + " ) ";
    };
    const double x0 = lo.x, y0 = lo.y, z0 = lo.z, x1 = hi.x, y1 = hi.y, z1 = hi.z;
    return "{\n" + pt(x0, y0, z0) + pt(x0, y1, z0) + pt(x0, y1, z1) + texture + " 0 0 0 1 1\n" +
           pt(x1, y1, z0) + pt(x1, y0, z0) + pt(x1, y0, z1) + texture + " 0 0 0 1 1\n" +
           pt(x1, y0, z0) + pt(x0, y0, z0) + pt(x0, y0, z1) + texture + " 0 0 0 1 1\n" +
           pt(x0, y1, z0) + pt(x1, y1, z0) + pt(x1, y1, z1) + texture + " 0 0 0 1 1\n" +
           pt(x0, y1, z0) + pt(x0, y0, z0) + pt(x1, y0, z0) + texture + " 0 0 0 1 1\n" +
           pt(x0, y0, z1) + pt(x0, y1, z1) + pt(x1, y1, z1) + texture + " 0 0 0 1 1\n}\n";
}

} // namespace

// Faces inside other brushes (overlaps, brushes touching, a brush given twice) are left out, and
// the level still blocks exactly the segments the brushes' every face blocks.
TEST(QuakeMap, FacesInsideOtherBrushesGoAndBlockNothingMore)
{
    const std::string text = "{\n\"classname\" \"worldspawn\"\n" + cube({0, 0, 0}, {64, 64, 64}) + cube({32, 16, 16}, {96, 48, 48}) +
                             cube({0, 0, 64}, {64, 64, 80}) + cube({0, 0, 64}, {64, 64, 80}) +
                             cube({100, 0, 0}, {164, 64, 64}, "*WATER") + cube({120, 16, 16}, {140, 48, 48}) + "}\n";
    const fs::path file = fs::temp_directory_path() / ("sightline_overlap_" + std::to_string(::getpid()) + ".map");
    std::ofstream(file) << text;
    std::vector<std::string> warnings;
    const Scene scene = loadScene(file, &warnings);
    fs::remove(file);
    // Every face of every brush, as the reader gives them (the water's left out).
    const QuakeMap map = parseQuakeMap(text, "overlap.map");
    std::vector<glm::dvec3> all;
    for (const MapBrush& b : map.entities[0].brushes)
        for (const BrushFace& f : brushFaces(b))
            if (f.texture[0] != '*')
                for (std::size_t k = 1; k + 1 < f.polygon.size(); ++k)
                    all.insert(all.end(), {f.polygon[0], f.polygon[k], f.polygon[k + 1]});
    const Mesh& mesh = scene.meshes[0];
    std::vector<glm::dvec3> kept;
    for (std::uint32_t i : mesh.indices) {
        const glm::vec3 p = mesh.positions[i];
        kept.push_back(glm::dvec3(p.x, -p.z, p.y) / 0.0254);
    }
    EXPECT_LT(kept.size(), all.size()) << "buried faces left out";
    bool said = false;
    for (const std::string& w : warnings)
        said = said || w.find("inside other brushes") != std::string::npos;
    EXPECT_TRUE(said);
    // The duplicated slab keeps one copy of its top: some triangle still lies at z = 80.
    bool top = false;
    for (const glm::dvec3& p : kept)
        top = top || std::abs(p.z - 80.0) < 1e-3;
    EXPECT_TRUE(top);

    // Segments between random points outside every brush: blocked by the kept faces exactly when by all.
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> coordinate(-40.0, 200.0);
    int segments = 0;
    while (segments < 3000) {
        glm::dvec3 ends[2];
        bool open = true;
        for (glm::dvec3& e : ends) {
            e = {coordinate(random), coordinate(random) * 0.6, coordinate(random) * 0.6};
            for (const MapBrush& b : map.entities[0].brushes)
                open = open && !insideBrush(b, e, -0.5);
        }
        if (!open)
            continue;
        ++segments;
        auto blocked = [&](const std::vector<glm::dvec3>& t) {
            for (std::size_t k = 0; k + 2 < t.size(); k += 3)
                if (crosses(ends[0], ends[1], t[k], t[k + 1], t[k + 2]))
                    return true;
            return false;
        };
        ASSERT_EQ(blocked(kept), blocked(all)) << "segment " << segments;
    }
}
