// OBJ/PLY/OFF/STL import: exact triangle counts (non-manifold and polygon faces included), the
// instance layout, and one-line errors for malformed files. Every file is written by the test.

#include <algorithm>
#include <cstring>
#include <iterator>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>

#include "TestFiles.h"
#include "TestImages.h"
#include "TextureMean.h"
#include "plugins/SceneFormats.h"

using namespace sightline;
using sightline::test::expectOneLineError;
using sightline::test::TempDir;
using sightline::test::writeFile;
using sightline::test::f32;
using sightline::test::i32;
using sightline::test::u32;
using sightline::test::u8;

namespace {


// Binary little-endian PLY: 4 vertices, one quad and one triangle = 3 triangles.
std::string binaryPly()
{
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (const auto& p : v)
        s += f32(p[0]) + f32(p[1]) + f32(p[2]);
    s += u8(4) + i32(0) + i32(1) + i32(2) + i32(3);
    s += u8(3) + i32(0) + i32(2) + i32(3);
    return s;
}

TEST(MeshFileImporter, ObjKeepsNonManifoldAndPolygonFaces)
{
    TempDir dir;
    // Three triangles share edge 0-1 (a "complex edge" a halfedge mesh would drop), plus a pentagon.
    const auto file = writeFile(dir / "fins.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                                                  "f 1 2 3\nf 1 2 4\nf 2 1 5\n"
                                                  "v 2 0 0\nv 3 0 0\nv 3.5 1 0\nv 2.5 2 0\nv 1.5 1 0\n"
                                                  "f 6 7 8 9 10\n");
    const Scene scene = loadScene(file);
    ASSERT_EQ(scene.meshes.size(), 1u);
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_EQ(scene.meshes[0].positions.size(), 10u);
    EXPECT_EQ(scene.triangleCount(), 3u + 3u); // pentagon fan = 3 triangles
    EXPECT_EQ(scene.meshes[0].name, "fins");
    EXPECT_EQ(scene.instances[0].transform, glm::mat4(1.0f));
    // The third triangle is (2, 1, 5) in 1-based indices, order preserved.
    const std::vector<std::uint32_t> third(scene.meshes[0].indices.begin() + 6, scene.meshes[0].indices.begin() + 9);
    EXPECT_EQ(third, (std::vector<std::uint32_t>{1, 0, 4}));
}

TEST(MeshFileImporter, ObjMaterialsGiveTheirDiffuseColourAsAlbedo)
{
    TempDir dir;
    writeFile(dir / "level.mtl", "# a library\nnewmtl red brick\nKd 0.9 0.1 0.1\nKs 1 1 1\n"
                                 "newmtl grey\nKd 0.5\nnewmtl painted\nKd 0.2 0.3 0.4\nmap_Kd wall.png\n"
                                 "newmtl glowing\nKd 1.5 0 0\nnewmtl measured\nKd spectral rough.rfl\n");
    const auto file = writeFile(dir / "level.obj", "mtllib level.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                                   "f 1 2 3\nusemtl red brick\nf 1 2 3 4\nusemtl grey\nf 1 2 3\n"
                                                   "usemtl painted\nf 1 2 3\nusemtl glowing\nf 1 2 3\n"
                                                   "usemtl measured\nf 1 2 3\nusemtl nowhere\nf 1 2 3\n");
    std::vector<std::string> warnings;
    const Scene scene = loadScene(file, &warnings);
    const glm::vec3 red(0.9f, 0.1f, 0.1f), unknown = kUnknownAlbedo;
    // Before any usemtl; the quad's two triangles; grey from one value; a texture; Kd out of
    // range; a spectral Kd; a material no library defines.
    EXPECT_EQ(scene.meshes.at(0).albedo,
              (std::vector<glm::vec3>{unknown, red, red, glm::vec3(0.5f), unknown, unknown, unknown, unknown}));
    std::string all;
    for (const std::string& w : warnings)
        all += w + "\n";
    EXPECT_NE(all.find("level.mtl: line 11: Kd not read ('1.5' is outside [0, 1]) and 1 more"), std::string::npos) << all;
    EXPECT_NE(all.find("material 'nowhere' is not defined"), std::string::npos) << all;

    // Libraries that are missing or outside the OBJ's folder are warnings, the level loads.
    std::filesystem::create_directories(dir / "sub");
    writeFile(dir / "outside.mtl", "newmtl red\nKd 1 0 0\n");
    const auto escaping = writeFile(dir / "sub" / "level.obj", "mtllib ../outside.mtl missing.mtl\nusemtl red\n"
                                                               "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
    warnings.clear();
    const Scene alone = loadScene(escaping, &warnings);
    EXPECT_EQ(alone.triangleCount(), 1u);
    EXPECT_TRUE(alone.meshes.at(0).albedo.empty());   // nothing known
    ASSERT_GE(warnings.size(), 2u);
    EXPECT_NE(warnings[0].find("outside the OBJ's folder"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[1].find("is not there"), std::string::npos) << warnings[1];

    // Without materials: no albedos.
    EXPECT_TRUE(loadScene(writeFile(dir / "plain.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n")).meshes.at(0).albedo.empty());
}

TEST(MeshFileImporter, ObjDiffuseTexturesGiveTheirMeanOverEachTriangle)
{
    TempDir dir;
    writeFile(dir / "four colours.png", test::fourColourPng());
    std::filesystem::create_directories(dir / "level");
    writeFile(dir / "level" / "tex.png", test::fourColourPng());
    // Kd times the texture; -s and -o move it, -clamp on clamps it; a name may hold spaces; a
    // texture outside the OBJ's folder is not read.
    writeFile(dir / "level" / "level.mtl", "newmtl half red\nKd 0.5 1 1\nmap_Kd -clamp on -bm 1 tex.png\n"
                                           "newmtl moved\nmap_Kd -s 0.25 0.25 1 -o 0.75 0 0 -clamp on tex.png\n"
                                           "newmtl escaping\nmap_Kd ../four colours.png\n");
    const auto file = writeFile(dir / "level" / "level.obj",
                                "mtllib level.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                // the top-left texel's outer quarter (OBJ's v runs up), then the unit square
                                "vt 0 0.75\nvt 0.25 0.75\nvt 0.25 1\nvt 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                "usemtl half red\nf 1/1 2/2 3/3 4/4\n"
                                "usemtl moved\nf 1/5 2/6 3/7 4/8\n"
                                "usemtl escaping\nf 1/5 2/6 3/7\n"
                                "usemtl half red\nf 1 2 3\nf 1/1 2/2 3/99\n");
    std::vector<std::string> warnings;
    // Not asked for: the textured materials' albedos unknown, their textures not read.
    EXPECT_TRUE(loadScene(file, &warnings).meshes.at(0).albedo.empty());   // none known
    EXPECT_TRUE(std::none_of(warnings.begin(), warnings.end(), [](const std::string& w) { return w.find("texture") != std::string::npos; }));
    warnings.clear();
    const Scene scene = loadScene(file, &warnings, {.textureAlbedos = true});
    const std::vector<glm::vec3>& albedo = scene.meshes.at(0).albedo;
    ASSERT_EQ(albedo.size(), 7u);
    const glm::vec3 grey(texture::srgbToLinear(188.0f / 255.0f));
    const glm::vec3 expected[] = {{0.5f, 0, 0}, {0.5f, 0, 0}, grey, grey};
    for (std::size_t t = 0; t < 4; ++t)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(albedo[t][c], expected[t][c], 1e-6) << "triangle " << t;
    // Escaping; no vt; a vt index past those read: unknown, each said.
    EXPECT_EQ(albedo[4], kUnknownAlbedo);
    EXPECT_EQ(albedo[5], kUnknownAlbedo);
    EXPECT_EQ(albedo[6], kUnknownAlbedo);
    std::string all;
    for (const std::string& w : warnings)
        all += w + "\n";
    EXPECT_NE(all.find("texture '../four colours.png' of material 'escaping' is outside the OBJ's folder"), std::string::npos) << all;
    EXPECT_NE(all.find("2 triangles of textured materials have no usable texture coordinates"), std::string::npos) << all;
}

TEST(MeshFileImporter, ObjWithNaNVertexIsRefused)
{
    TempDir dir;
    const auto file = writeFile(dir / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    expectOneLineError(file, [&] { loadScene(file); });
}

TEST(MeshFileImporter, ObjUnreadableVertexNeverShiftsIndices)
{
    TempDir dir;
    // A reader that skipped the bad line would make face 1 2 3 silently use the wrong vertices.
    const auto file = writeFile(dir / "shift.obj", "v 0 0 0\nv x 0 0\nv 0 1 0\nv 1 1 1\nf 1 2 3\n");
    EXPECT_NE(expectOneLineError(file, [&] { loadScene(file); }).find("line 2: vertex value 'x' is not a number"),
              std::string::npos);
}

TEST(MeshFileImporter, BinaryPlyWithNaNVertexIsRefused)
{
    TempDir dir;
    std::string ply = binaryPly();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    ply.replace(ply.find("end_header\n") + 11 + 12, 4, f32(nan)); // x of vertex 1
    const auto file = writeFile(dir / "nan.ply", ply);
    EXPECT_NE(expectOneLineError(file, [&] { loadScene(file); }).find("not finite"), std::string::npos);
}

TEST(MeshFileImporter, TruncatedAsciiPlyIsRefused)
{
    TempDir dir;
    const auto file = writeFile(dir / "short.ply", "ply\nformat ascii 1.0\nelement vertex 900000000\nproperty float x\n"
                                                   "property float y\nproperty float z\nend_header\n0 0 0\n");
    expectOneLineError(file, [&] { loadScene(file); });
}

TEST(MeshFileImporter, ObjFaceIndexOutOfRangeIsRefused)
{
    TempDir dir;
    const auto file = writeFile(dir / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    expectOneLineError(file, [&] { loadScene(file); });
}

TEST(MeshFileImporter, OffFaceIndexOutOfRangeIsRefused)
{
    TempDir dir;
    const auto file = writeFile(dir / "range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
    expectOneLineError(file, [&] { loadScene(file); });
}

TEST(MeshFileImporter, OffWithCommentsColoursAndInlineCounts)
{
    TempDir dir;
    const auto file = writeFile(dir / "quad.off", "COFF 4 1 0 # counts on the header line\n"
                                                  "# a comment line\n"
                                                  "0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n"
                                                  "1 1 0 255 0 0 255 # trailing comment\n0 1 0 255 0 0 255\n"
                                                  "4 0 1 2 3 0.5 0.5 0.5 1.0\n");
    const Scene scene = loadScene(file);
    EXPECT_EQ(scene.triangleCount(), 2u);
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.meshes[0].positions[2], glm::vec3(1, 1, 0));
}

TEST(MeshFileImporter, TruncatedOrGarbledOffIsRefused)
{
    TempDir dir;
    const std::string cases[] = {
        "OFF\n2000000000 1 0\n0 0 0\n",                         // counts the file does not hold
        "OFF\n0 1 0\n-1.63 0 1.15\n",                           // negative face size (hung OpenMesh)
        "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",        // NaN coordinate
        "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n",        // fractional index
        "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n",          // face shorter than announced
    };
    int n = 0;
    for (const std::string& text : cases) {
        const auto file = writeFile(dir / ("bad" + std::to_string(n++) + ".off"), text);
        SCOPED_TRACE(file.filename().string());
        expectOneLineError(file, [&] { loadScene(file); });
    }
}

TEST(MeshFileImporter, AsciiPlyCounts)
{
    TempDir dir;
    const auto file = writeFile(dir / "quad.ply", "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                                                  "property float y\nproperty float z\nelement face 2\n"
                                                  "property list uchar int vertex_indices\nend_header\n"
                                                  "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n4 0 1 2 3\n3 0 1 4\n");
    const Scene scene = loadScene(file);
    EXPECT_EQ(scene.meshes.at(0).positions.size(), 5u);
    EXPECT_EQ(scene.triangleCount(), 3u);
    EXPECT_EQ(scene.meshes[0].positions[4], glm::vec3(0, 0, 1));
}

TEST(MeshFileImporter, BinaryPlyCounts)
{
    TempDir dir;
    const auto file = writeFile(dir / "quad_bin.ply", binaryPly());
    const Scene scene = loadScene(file);
    EXPECT_EQ(scene.meshes.at(0).positions.size(), 4u);
    EXPECT_EQ(scene.triangleCount(), 3u);
    EXPECT_EQ(scene.meshes[0].positions[2], glm::vec3(1, 1, 0));
}

TEST(MeshFileImporter, TruncatedBinaryPlyIsRefused)
{
    TempDir dir;
    const std::string full = binaryPly();
    const auto file = writeFile(dir / "cut.ply", full.substr(0, full.size() - 20)); // part of the faces is gone
    expectOneLineError(file, [&] { loadScene(file); });
    const auto early = writeFile(dir / "cut_early.ply", full.substr(0, full.find("end_header") + 11 + 20));
    expectOneLineError(early, [&] { loadScene(early); });
}

TEST(MeshFileImporter, GarbagePlyIsRefused)
{
    TempDir dir;
    const auto file = writeFile(dir / "garbage.ply", "this is not a mesh\n\x01\x02\x03");
    expectOneLineError(file, [&] { loadScene(file); });
}

TEST(MeshFileImporter, MalformedPlyHeadersAreRefused)
{
    // Each of these crashed or hung OpenMesh's PLY reader before the header check.
    TempDir dir;
    const std::string ply = binaryPly();
    const std::string header = ply.substr(0, ply.find("end_header"));
    const std::string cases[] = {
        header.substr(0, header.find("property float y") + 3),        // header cut off mid-line
        std::string(ply).replace(ply.find("property list"), 13, "property "), // list without types
        std::string(ply).replace(ply.find("element vertex"), 7, "elem\x87nt"), // unknown keyword
        std::string(ply).replace(ply.find("float y"), 5, "flPat"),     // unknown type
    };
    int n = 0;
    for (const std::string& bytes : cases) {
        const auto file = writeFile(dir / ("bad" + std::to_string(n++) + ".ply"), bytes);
        SCOPED_TRACE(file.filename().string());
        expectOneLineError(file, [&] { loadScene(file); });
    }
}

TEST(MeshFileImporter, AsciiStlCounts)
{
    TempDir dir;
    const auto file = writeFile(dir / "two.stl", "solid two\n"
                                                 " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
                                                 "   vertex 1 0 0\n   vertex 1 1 0\n  endloop\n endfacet\n"
                                                 " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
                                                 "   vertex 1 1 0\n   vertex 0 1 0\n  endloop\n endfacet\n"
                                                 "endsolid two\n");
    const Scene scene = loadScene(file);
    EXPECT_EQ(scene.triangleCount(), 2u);
    const Bounds b = scene.bounds();
    EXPECT_EQ(b.min, glm::vec3(0, 0, 0));
    EXPECT_EQ(b.max, glm::vec3(1, 1, 0));
}

TEST(MeshFileImporter, BinaryStlCounts)
{
    TempDir dir;
    std::string s(80, ' ');
    s += u32(2);
    const float tris[2][3][3] = {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {{0, 0, 0}, {1, 1, 0}, {0, 1, 2}}};
    for (const auto& t : tris) {
        s += f32(0) + f32(0) + f32(1);
        for (const auto& v : t)
            s += f32(v[0]) + f32(v[1]) + f32(v[2]);
        s += std::string(2, '\0');
    }
    const auto file = writeFile(dir / "two_bin.stl", s);
    const Scene scene = loadScene(file);
    EXPECT_EQ(scene.triangleCount(), 2u);
    EXPECT_EQ(scene.bounds().max, glm::vec3(1, 1, 2));
}

std::string asciiFacet(const char* a, const char* b, const char* c)
{
    return std::string(" facet normal 0 0 1\n  outer loop\n   vertex ") + a + "\n   vertex " + b + "\n   vertex " + c +
           "\n  endloop\n endfacet\n";
}

TEST(MeshFileImporter, StlKeepsDegenerateFacets)
{
    TempDir dir;
    // A zero-area facet still counts: the file's triangle count is kept exactly.
    const auto file = writeFile(dir / "degenerate.stl", "solid d\n" + asciiFacet("0 0 0", "0 0 0", "1 1 1") +
                                                            asciiFacet("0 0 0", "1 0 0", "0 1 0") + "endsolid d\n");
    EXPECT_EQ(loadScene(file).triangleCount(), 2u);
}

TEST(MeshFileImporter, MalformedStlIsRefused)
{
    TempDir dir;
    const std::string good = asciiFacet("0 0 0", "1 0 0", "0 1 0");
    const std::string cases[] = {
        "solid t\n" + good.substr(0, good.size() - 30),                               // truncated
        "solid t\n" + asciiFacet("0 0 0", "nan 0 0", "0 1 0") + "endsolid t\n",        // NaN
        "solid t\n" + asciiFacet("0 0 0", "1 0", "0 1 0") + "endsolid t\n",            // short vertex
        std::string(80, ' ') + std::string("\x02\0\0\0", 4) + std::string(60, '\0'), // binary, count 2, 1 facet
    };
    int n = 0;
    for (const std::string& bytes : cases) {
        const auto file = writeFile(dir / ("bad" + std::to_string(n++) + ".stl"), bytes);
        SCOPED_TRACE(file.filename().string());
        expectOneLineError(file, [&] { loadScene(file); });
    }
}

TEST(MeshFileImporter, UppercaseExtensionIsAccepted)
{
    TempDir dir;
    const auto file = writeFile(dir / "TRI.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_EQ(loadScene(file).triangleCount(), 1u);
}

namespace {

// The unit cube [0, 1]^3 as OBJ quads, counter-clockwise seen from outside; face 3 is +y.
const char* kCubeVertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
const std::vector<std::string> kCubeFaces = {"f 1 4 3 2\n", "f 5 6 7 8\n", "f 1 2 6 5\n",
                                             "f 4 8 7 3\n", "f 1 5 8 4\n", "f 2 3 7 6\n"};

std::string cubeObj(std::size_t missingFace = 99, std::size_t flippedFace = 99)
{
    std::string obj = kCubeVertices;
    for (std::size_t f = 0; f < kCubeFaces.size(); ++f) {
        if (f == missingFace)
            continue;
        if (f != flippedFace) {
            obj += kCubeFaces[f];
            continue;
        }
        std::istringstream in(kCubeFaces[f].substr(2));   // "f a b c d" -> "f d c b a"
        std::vector<std::string> v{std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
        obj += "f " + v[3] + " " + v[2] + " " + v[1] + " " + v[0] + "\n";
    }
    return obj;
}

} // namespace

TEST(MeshFileImporter, ClosedOutwardMeshesEarnTheWatertightFlag)
{
    TempDir dir;
    const Scene closed = loadScene(writeFile(dir / "cube.obj", cubeObj()));
    ASSERT_EQ(closed.triangleCount(), 12u);
    EXPECT_TRUE(closed.meshes[0].watertight);
    const Scene open = loadScene(writeFile(dir / "open.obj", cubeObj(3)));
    ASSERT_EQ(open.triangleCount(), 10u);
    EXPECT_FALSE(open.meshes[0].watertight);
    const Scene flipped = loadScene(writeFile(dir / "flipped.obj", cubeObj(99, 3)));
    ASSERT_EQ(flipped.triangleCount(), 12u);
    EXPECT_FALSE(flipped.meshes[0].watertight);

    // STL repeats every vertex per facet: the check welds equal positions first.
    std::string stl = "solid cube\n";
    const Mesh& cube = closed.meshes[0];
    auto text = [&](std::uint32_t i) {
        const glm::vec3& p = cube.positions[i];
        return std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z);
    };
    for (std::size_t t = 0; t < cube.triangleCount(); ++t)
        stl += asciiFacet(text(cube.indices[3 * t]).c_str(), text(cube.indices[3 * t + 1]).c_str(),
                          text(cube.indices[3 * t + 2]).c_str());
    stl += "endsolid cube\n";
    const Scene fromStl = loadScene(writeFile(dir / "cube.stl", stl));
    ASSERT_EQ(fromStl.meshes[0].positions.size(), 36u);
    EXPECT_TRUE(fromStl.meshes[0].watertight);
}

TEST(SceneFormatRegistry, MissingFileAndUnknownExtension)
{
    TempDir dir;
    const auto missing = dir / "nothing.obj";
    EXPECT_NE(expectOneLineError(missing, [&] { loadScene(missing); }).find("no such file"), std::string::npos);
    const auto unknown = writeFile(dir / "scene.xyz", "1 2 3\n");
    const std::string message = expectOneLineError(unknown, [&] { loadScene(unknown); });
    for (const char* ext : {"*.gltf", "*.glb", "*.obj", "*.ply", "*.off", "*.stl"})
        EXPECT_NE(message.find(ext), std::string::npos) << ext;
    EXPECT_EQ(SceneFormatRegistry::builtin().importerFor("a.GLB"), SceneFormatRegistry::builtin().importerFor("b.gltf"));
    EXPECT_NE(SceneFormatRegistry::builtin().exporterFor("a.glb"), nullptr);
    EXPECT_EQ(SceneFormatRegistry::builtin().exporterFor("a.obj"), nullptr);
}

} // namespace
