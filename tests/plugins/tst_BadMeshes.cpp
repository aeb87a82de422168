// Bad OBJ/PLY/OFF/STL input: every case is refused with one line naming the file, the
// line (text formats) and what is wrong in words; never a crash, a hang, a huge allocation, or a
// load that quietly drops or invents geometry. The positive cases are inputs a careless fix would
// break: BOM, CR-only and CRLF line ends, relative indices, vt/vn forms, polygons.
// Every file is written by the test.

#include <sys/stat.h>

#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <string>

#include <gtest/gtest.h>

#include "TestFiles.h"
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


/// Loads `file` expecting a one-line error naming it and containing every one of `words`.
void expectRefused(const std::filesystem::path& file, std::initializer_list<const char*> words)
{
    SCOPED_TRACE(file.filename().string());
    const std::string message = expectOneLineError(file, [&] { loadScene(file); });
    for (const char* word : words)
        EXPECT_NE(message.find(word), std::string::npos) << "'" << word << "' not in: " << message;
}

// ASCII PLY of a triangle; vertex 1 (x) is on line 11, the face on line 13.
std::string asciiPly(const std::string& vertex1X = "1", const std::string& face = "3 0 1 2")
{
    return "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
           "0 0 0\n" + vertex1X + " 0 0\n0 1 0\n" + face + "\n";
}

/// Binary little-endian PLY: 3 vertices, `faces` triangles in the data, `declared` in the header.
std::string binaryPly(std::uint32_t declared, std::uint32_t faces, const std::string& list = "uchar")
{
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face " + std::to_string(declared) + "\nproperty list " + list +
                    " int vertex_indices\nend_header\n";
    s += f32(0) + f32(0) + f32(0) + f32(1) + f32(0) + f32(0) + f32(0) + f32(1) + f32(0);
    for (std::uint32_t f = 0; f < faces; ++f)
        s += (list == "uchar" ? u8(3) : u32(3)) + i32(0) + i32(1) + i32(2);
    return s;
}

const char* kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"; // lines 1-3

TEST(BadMeshes, AsciiPlyValuesMustBeFiniteDecimalFloats)
{
    TempDir dir;
    expectRefused(writeFile(dir / "nan.ply", asciiPly("nan")), {"line 11", "'nan'", "not finite"});
    expectRefused(writeFile(dir / "inf.ply", asciiPly("-inf")), {"line 11", "'-inf'", "not finite"});
    expectRefused(writeFile(dir / "abc.ply", asciiPly("abc")), {"line 11", "'abc'", "not a number"});
    expectRefused(writeFile(dir / "big.ply", asciiPly("1e39")), {"line 11", "'1e39'", "float range"});
    expectRefused(writeFile(dir / "hex.ply", asciiPly("0x1p3")), {"line 11", "'0x1p3'", "hexadecimal"});
    expectRefused(writeFile(dir / "short.ply", asciiPly("")), {"line 11", "vertex 1", "2 values", "fewer"});
}

TEST(BadMeshes, AsciiPlyFaceTokensAreChecked)
{
    TempDir dir;
    // A stray '-' once made OpenMesh's reader take garbage for a list count and allocate gigabytes.
    expectRefused(writeFile(dir / "minus.ply", asciiPly("1", "3 0 1 -")), {"line 13", "'-'", "not an integer"});
    expectRefused(writeFile(dir / "count.ply", asciiPly("1", "- 0 1 2")), {"line 13", "'-'", "not an integer"});
    expectRefused(writeFile(dir / "range.ply", asciiPly("1", "3 0 1 3")), {"line 13", "index 3", "out of range"});
    expectRefused(writeFile(dir / "two.ply", asciiPly("1", "2 0 1")), {"line 13", "2 vertices"});
    expectRefused(writeFile(dir / "long.ply", asciiPly("1", "3 0 1 2 2")), {"line 13", "more values"});
    expectRefused(writeFile(dir / "uchar.ply", asciiPly("1", "300 0 1 2")), {"line 13", "'300'", "uchar"});
}

TEST(BadMeshes, PlyCountsMustMatchTheData)
{
    TempDir dir;
    expectRefused(writeFile(dir / "cut.ply", binaryPly(20, 19)), {"header declares 20 faces", "data holds 19"});
    expectRefused(writeFile(dir / "extra.ply", binaryPly(19, 20)), {"19 faces", "continues"});
    std::string cut = asciiPly("1.0000000000");
    cut.replace(cut.find("face 1"), 6, "face 2");
    expectRefused(writeFile(dir / "cut_ascii.ply", cut), {"header declares 2 faces", "data holds 1"});
    expectRefused(writeFile(dir / "cut_line.ply", asciiPly().substr(0, asciiPly().size() - 2)),
                  {"line 13", "face 0 has 3 values, fewer"});
    expectRefused(writeFile(dir / "extra_ascii.ply", asciiPly() + "3 0 1 2\n"), {"line 14", "continues"});
    // Counts no file of this size can hold are refused from the header, before any allocation.
    std::string huge = binaryPly(1, 1);
    huge.replace(huge.find("vertex 3"), 8, "vertex 4000000000");
    expectRefused(writeFile(dir / "huge.ply", huge), {"4000000000 vertices", "bytes"});
    // A list count of 2^32-1 in the data: refused as truncated, not allocated.
    std::string list = binaryPly(1, 1, "uint");
    list.replace(list.size() - 16, 4, u32(0xffffffffu));
    expectRefused(writeFile(dir / "list.ply", list), {"face 0", "4294967295"});
}

TEST(BadMeshes, PlyGoodFilesStillLoad)
{
    TempDir dir;
    EXPECT_EQ(loadScene(writeFile(dir / "bin.ply", binaryPly(20, 20))).triangleCount(), 20u);
    std::string cr = asciiPly("+1.5e0");
    for (char& c : cr)
        c = c == '\n' ? '\r' : c;
    const Scene scene = loadScene(writeFile(dir / "cr.ply", cr));
    ASSERT_EQ(scene.triangleCount(), 1u);
    EXPECT_EQ(scene.meshes[0].positions[1].x, 1.5f);
}

TEST(BadMeshes, ObjFaceIndicesAreChecked)
{
    TempDir dir;
    auto obj = [&](const char* name, const std::string& face) { return writeFile(dir / name, kTriangle + face + "\n"); };
    expectRefused(obj("big.obj", "f 1 2 2147483648"), {"line 4", "face index 2147483648 is out of range (3 vertices)"});
    expectRefused(obj("huge.obj", "f 1 2 99999999999999999999"), {"line 4", "99999999999999999999"});
    expectRefused(obj("past.obj", "f 1 2 4"), {"line 4", "face index 4 is out of range (3 vertices)"});
    expectRefused(obj("back.obj", "f 1 2 -4"), {"line 4", "face index -4 is out of range (3 vertices)"});
    expectRefused(obj("zero.obj", "f 0 1 2"), {"line 4", "face index 0"});
    expectRefused(obj("x.obj", "f 1 2 x"), {"line 4", "'x'", "not an integer"});
    expectRefused(obj("frac.obj", "f 1 2 1.5"), {"line 4", "'1.5'", "not an integer"});
    expectRefused(obj("empty.obj", "f 1 2 /3"), {"line 4", "empty"});
    expectRefused(obj("vt.obj", "f 1/a 2 3"), {"line 4", "'a'"});
    expectRefused(obj("one.obj", "f 1"), {"line 4", "1 vertex", "3 or more"});
    expectRefused(obj("two.obj", "f 1 2"), {"line 4", "2 vertices", "3 or more"});
}

TEST(BadMeshes, ObjVerticesAreChecked)
{
    TempDir dir;
    auto obj = [&](const char* name, const std::string& vertex) {
        return writeFile(dir / name, "v 0 0 0\n" + vertex + "\nv 0 1 0\nf 1 2 3\n");
    };
    expectRefused(obj("dots.obj", "v 1.2.3 0 0"), {"line 2", "'1.2.3'", "not a number"});
    expectRefused(obj("big.obj", "v 1e39 0 0"), {"line 2", "'1e39'", "float range"});
    expectRefused(obj("inf.obj", "v 0 inf 0"), {"line 2", "'inf'", "not finite"});
    expectRefused(obj("hex.obj", "v 0x1p3 0 0"), {"line 2", "hexadecimal"});
    expectRefused(obj("short.obj", "v 1 0"), {"line 2", "2 coordinates"});
    expectRefused(writeFile(dir / "nul.obj", std::string(kTriangle) + "f 1 2 3\n" + std::string("v \0 0 0\n", 8)),
                  {"line 5", "NUL"});
}

TEST(BadMeshes, ObjLineEndsBomAndIndexFormsLoad)
{
    TempDir dir;
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    auto check = [](const Scene& scene) {
        ASSERT_EQ(scene.meshes.size(), 1u);
        ASSERT_EQ(scene.meshes[0].positions.size(), 4u);
        EXPECT_EQ(scene.meshes[0].positions[0], glm::vec3(0, 0, 0));
        EXPECT_EQ(scene.meshes[0].positions[2], glm::vec3(1, 1, 0));
        EXPECT_EQ(scene.meshes[0].indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3})); // fan
    };
    check(loadScene(writeFile(dir / "plain.obj", quad)));
    check(loadScene(writeFile(dir / "bom.obj", "\xEF\xBB\xBF" + quad)));
    std::string cr = quad, crlf;
    for (char& c : cr)
        c = c == '\n' ? '\r' : c;
    check(loadScene(writeFile(dir / "cr.obj", cr)));
    for (const char c : quad)
        crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    check(loadScene(writeFile(dir / "crlf.obj", crlf)));
    check(loadScene(writeFile(dir / "relative.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\n")));
    check(loadScene(writeFile(dir / "forms.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
                                                 "f 1/1/1 2//1 3/1 4/1/1\n")));
    check(loadScene(writeFile(dir / "extras.obj", "# comment\nmtllib a.mtl\no quad\ng g\ns off\nusemtl m\n"
                                                  "v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 1 1 0\nv +0 1e0 -0.0 # c\n"
                                                  "f 1 2 3 4 # comment\n")));
}

TEST(BadMeshes, OffTokensAndCountsAreChecked)
{
    TempDir dir;
    auto off = [&](const char* name, const std::string& vertex1, const std::string& face = "3 0 1 2",
                   const std::string& tail = "") {
        return writeFile(dir / name, "OFF\n3 1 0\n0 0 0\n" + vertex1 + "\n0 1 0\n" + face + "\n" + tail);
    };
    expectRefused(off("hex.off", "0x1p3 0 0"), {"line 4", "hexadecimal"});
    expectRefused(off("big.off", "1e39 0 0"), {"line 4", "float range"});
    expectRefused(off("inf.off", "1 inf 0"), {"line 4", "not finite"});
    expectRefused(off("two.off", "1 0 0", "2 0 1"), {"line 6", "2 vertices"});
    expectRefused(off("range.off", "1 0 0", "3 0 1 3"), {"line 6", "index 3", "out of range"});
    expectRefused(off("extra.off", "1 0 0", "3 0 1 2", "3 0 1 2\n"), {"line 7", "continues"});
    expectRefused(writeFile(dir / "cut.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                  {"header declares 3 vertices and 2 faces", "1 face"});
    std::string cr = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    for (char& c : cr)
        c = c == '\n' ? '\r' : c;
    EXPECT_EQ(loadScene(writeFile(dir / "cr.off", cr)).triangleCount(), 1u);
}

TEST(BadMeshes, StlValuesAndRange)
{
    TempDir dir;
    const auto facet = [](const char* v1) {
        return std::string("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex ") + v1 +
               "\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
    };
    expectRefused(writeFile(dir / "big.stl", facet("1e39 0 0")), {"line 5", "'1e39'", "float range"});
    expectRefused(writeFile(dir / "hex.stl", facet("0x1p3 0 0")), {"line 5", "hexadecimal"});
    // Normals are not used, and some exporters write NaN ones for degenerate facets.
    std::string nanNormal = facet("1 0 0");
    nanNormal.replace(nanNormal.find("normal 0 0 1"), 12, "normal nan -nan 0");
    EXPECT_EQ(loadScene(writeFile(dir / "normal.stl", nanNormal)).triangleCount(), 1u);
    // A flipped exponent bit in binary STL is finite but far out: the §2 coordinate range refuses it.
    std::string s(80, ' ');
    s += u32(1) + f32(0) + f32(0) + f32(1);
    s += f32(0) + f32(0) + f32(0) + f32(-1.2e38f) + f32(0) + f32(0) + f32(0) + f32(1) + f32(0);
    s += std::string(2, '\0');
    expectRefused(writeFile(dir / "far.stl", s), {"1000000 m"});
    // A binary STL that starts with "solid" and lost its last bytes names the facet count.
    std::string cut = "solid" + s.substr(5, s.size() - 10);
    expectRefused(writeFile(dir / "cut.stl", cut), {"1 facet", "bytes"});
}

TEST(BadMeshes, NonRegularAndHugeFilesAreRefusedBeforeReading)
{
    TempDir dir;
    for (const char* ext : {".obj", ".ply", ".off", ".stl"}) {
        const auto fifo = dir / (std::string("pipe") + ext);
        ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
        expectRefused(fifo, {"FIFO"}); // an open() would block forever
        const auto zero = dir / (std::string("zero") + ext);
        std::filesystem::create_symlink("/dev/zero", zero);
        expectRefused(zero, {"character device"});
        const auto huge = dir / (std::string("huge") + ext);
        writeFile(huge, "");
        std::filesystem::resize_file(huge, (std::uintmax_t(3) << 29)); // 1.5 GiB, sparse: no disk used
        expectRefused(huge, {"1536 MB", "limit"});
    }
}

} // namespace
