// OBJ, PLY (ascii and binary), OFF and STL import, mostly through OpenMesh's reader modules.
//
// OpenMesh's readers feed a BaseImporter. Its stock ImporterT builds a halfedge mesh, which
// silently drops faces that would make an edge non-manifold ("complex edge") - wrong for level
// geometry, where every triangle blocks rays. So a small importer here just collects vertices and
// fan-triangulated faces, checks face indices itself, and never drops a face.
// OpenMesh's readers are also fragile on real and malformed files, so each format is guarded:
//  - OFF: '#' comments and counts on the header line are misread, so ASCII OFF is normalised
//    (and its numbers checked) before OpenMesh parses it;
//  - PLY: malformed headers crash or hang the reader, so the header is validated strictly first;
//  - OBJ and PLY: unreadable or missing elements are skipped silently, so counts are compared;
//  - STL is parsed here directly: OpenMesh's STL reader drops degenerate facets and accepts
//    truncated or unreadable files as empty, and STL is a trivial format.

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "BuiltinFormats.h"
#include "visibility/Error.h"
#include "visibility/Scene.h"

namespace sightline {

namespace {

using namespace OpenMesh;
using IO::BaseImporter;

/// Collects points and polygons; every attribute setter is a deliberate no-op.
class CollectingImporter final : public BaseImporter {
public:
    Mesh mesh;
    std::string error;               ///< first problem found (readers cannot throw through OpenMesh)
    long long declaredVertices = -1; ///< counts from the file header, where the reader reports them
    long long declaredFaces = -1;
    long long faces = 0;             ///< polygons received, before triangulation

    // Only records the header's counts: a hostile header must not make us allocate.
    void reserve(unsigned int vertices, unsigned int, unsigned int polygons) override
    {
        declaredVertices = vertices;
        declaredFaces = polygons;
    }

    VertexHandle add_vertex(const Vec3f& p) override
    {
        mesh.positions.emplace_back(p[0], p[1], p[2]);
        return VertexHandle(static_cast<int>(mesh.positions.size() - 1));
    }
    VertexHandle add_vertex() override { return add_vertex(Vec3f(0.0f, 0.0f, 0.0f)); }
    void set_point(VertexHandle v, const Vec3f& p) override
    {
        if (v.is_valid() && static_cast<std::size_t>(v.idx()) < mesh.positions.size())
            mesh.positions[static_cast<std::size_t>(v.idx())] = {p[0], p[1], p[2]};
    }

    FaceHandle add_face(const VHandles& face) override
    {
        ++faces;
        for (VertexHandle v : face)
            if (!v.is_valid() || static_cast<std::size_t>(v.idx()) >= mesh.positions.size()) {
                if (error.empty())
                    error = "face vertex index " + std::to_string(v.idx()) + " is out of range (" +
                            std::to_string(mesh.positions.size()) + " vertices)";
                return FaceHandle();
            }
        if (face.size() < 3)
            return FaceHandle();
        const FaceHandle first(static_cast<int>(n_faces()));
        for (std::size_t k = 1; k + 1 < face.size(); ++k) // fan: a quad gives 2 triangles
            for (VertexHandle v : {face[0], face[k], face[k + 1]})
                mesh.indices.push_back(static_cast<std::uint32_t>(v.idx()));
        return first;
    }

    size_t n_vertices() const override { return mesh.positions.size(); }
    size_t n_faces() const override { return mesh.triangleCount(); }
    size_t n_edges() const override { return 0; }

    // Topology and attributes are not needed for visibility.
    HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
    FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
    void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
    void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
    void set_face_texindex(FaceHandle, int) override {}
    void set_halfedge(VertexHandle, HalfedgeHandle) override {}
    void set_normal(VertexHandle, const Vec3f&) override {}
    void set_normal(VertexHandle, const Vec3d&) override {}
    void set_color(VertexHandle, const Vec3uc&) override {}
    void set_color(VertexHandle, const Vec4uc&) override {}
    void set_color(VertexHandle, const Vec3f&) override {}
    void set_color(VertexHandle, const Vec4f&) override {}
    void set_texcoord(VertexHandle, const Vec2f&) override {}
    void set_status(VertexHandle, const Attributes::StatusInfo&) override {}
    void set_next(HalfedgeHandle, HalfedgeHandle) override {}
    void set_face(HalfedgeHandle, FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
    void set_texcoord(VertexHandle, const Vec3f&) override {}
    void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
    void set_status(HalfedgeHandle, const Attributes::StatusInfo&) override {}
    void set_color(EdgeHandle, const Vec3uc&) override {}
    void set_color(EdgeHandle, const Vec4uc&) override {}
    void set_color(EdgeHandle, const Vec3f&) override {}
    void set_color(EdgeHandle, const Vec4f&) override {}
    void set_status(EdgeHandle, const Attributes::StatusInfo&) override {}
    void set_normal(FaceHandle, const Vec3f&) override {}
    void set_normal(FaceHandle, const Vec3d&) override {}
    void set_color(FaceHandle, const Vec3uc&) override {}
    void set_color(FaceHandle, const Vec4uc&) override {}
    void set_color(FaceHandle, const Vec3f&) override {}
    void set_color(FaceHandle, const Vec4f&) override {}
    void set_status(FaceHandle, const Attributes::StatusInfo&) override {}
    void add_texture_information(int, std::string) override {}
};

/// OpenMesh reports problems by printing them; our errors carry the message instead.
void silenceOpenMesh()
{
    static const bool silenced = [] {
        omerr().disable();
        omlog().disable();
        omout().disable();
        return true;
    }();
    (void)silenced;
}

std::vector<std::string> tokens(const std::string& line)
{
    std::istringstream in(line);
    std::vector<std::string> out;
    for (std::string t; in >> t;)
        out.push_back(t);
    return out;
}

/// The whole token is a finite number (OpenMesh's stream parsing would stop at "nan" unnoticed).
bool isNumber(const std::string& token, bool integer)
{
    const char* begin = token.c_str();
    char* end = nullptr;
    errno = 0;
    double value = 0.0;
    if (integer)
        value = static_cast<double>(std::strtoll(begin, &end, 10));
    else
        value = std::strtod(begin, &end);
    return end != begin && *end == '\0' && errno == 0 && std::isfinite(value);
}

/// ASCII OFF rewritten in the strict form OpenMesh's reader handles: no comments, "OFF" alone on
/// its line, then the counts, vertex lines "x y z" and face lines "n i1 .. in" (per-vertex and
/// per-face colours, normals and texture coordinates are dropped: visibility needs none of them).
/// The counts are checked against the file, because OpenMesh trusts them and would loop over
/// elements a truncated file lacks.
std::string normalisedOff(const std::filesystem::path& file, const std::string& what)
{
    std::ifstream in(file, std::ios::binary);
    std::vector<std::vector<std::string>> lines;
    for (std::string line; std::getline(in, line);)
        if (auto t = tokens(line.substr(0, line.find('#'))); !t.empty())
            lines.push_back(std::move(t));
    if (lines.empty())
        throw Error(what + ": empty OFF file");
    std::vector<std::string> counts = lines.front();
    const std::string keyword = counts.front();
    counts.erase(counts.begin());
    if (std::find(counts.begin(), counts.end(), "BINARY") != counts.end())
        throw Error(what + ": binary OFF is not supported; save it as ASCII OFF, PLY or OBJ");
    // [ST][C][N]OFF: the prefixes only announce extra per-vertex data, which we drop.
    const std::size_t prefix = keyword.size() >= 3 ? keyword.size() - 3 : 0;
    if (keyword.size() < 3 || keyword.compare(prefix, 3, "OFF") != 0 ||
        keyword.substr(0, prefix).find_first_not_of("STCN") != std::string::npos)
        throw Error(what + ": not a supported OFF file (header '" + keyword + "')");

    std::size_t next = 1; // counts may share the header line ("OFF 836 1696 0") or follow it
    if (counts.empty() && lines.size() > 1)
        counts = lines[next++];
    long long vertices = -1, faces = -1;
    try {
        if (counts.size() >= 2) {
            vertices = std::stoll(counts[0]);
            faces = std::stoll(counts[1]);
        }
    } catch (const std::exception&) {
    }
    if (vertices < 0 || faces < 0)
        throw Error(what + ": OFF header has no valid vertex and face counts");
    const auto rest = static_cast<long long>(lines.size() - next);
    if (vertices > rest || faces > rest - vertices)
        throw Error(what + ": truncated: OFF header promises " + std::to_string(vertices) + " vertices and " +
                    std::to_string(faces) + " faces but only " + std::to_string(rest) + " lines follow");

    std::string body = "OFF\n" + std::to_string(vertices) + " " + std::to_string(faces) + " 0\n";
    for (long long i = 0; i < vertices + faces; ++i) {
        const std::vector<std::string>& t = lines[next + static_cast<std::size_t>(i)];
        const bool isVertex = i < vertices;
        const std::string where = what + ": OFF " + (isVertex ? "vertex " : "face ") +
                                  std::to_string(isVertex ? i : i - vertices);
        std::size_t keep = 3;
        if (!isVertex) {
            if (!isNumber(t.front(), true) || std::stoll(t.front()) < 3 || std::stoll(t.front()) > 1000000)
                throw Error(where + " does not start with a vertex count of 3 or more");
            keep = static_cast<std::size_t>(std::stoll(t.front())) + 1;
        }
        if (t.size() < keep)
            throw Error(where + " is incomplete");
        for (std::size_t k = isVertex ? 0 : 1; k < keep; ++k)
            if (!isNumber(t[k], !isVertex))
                throw Error(where + ": '" + t[k] + "' is not a number");
        for (std::size_t k = 0; k < keep; ++k)
            body += t[k] + (k + 1 < keep ? " " : "\n");
    }
    return body;
}

/// Bytes of a PLY scalar type; 0 if unknown.
std::size_t plyTypeSize(const std::string& type)
{
    static const std::map<std::string, std::size_t> sizes = {
        {"char", 1},  {"uchar", 1},  {"int8", 1},  {"uint8", 1},  {"short", 2},   {"ushort", 2},  {"int16", 2},
        {"uint16", 2}, {"int", 4},   {"uint", 4},  {"int32", 4},  {"uint32", 4},  {"float", 4},   {"float32", 4},
        {"double", 8}, {"float64", 8}};
    const auto it = sizes.find(type);
    return it == sizes.end() ? 0 : it->second;
}

/// OpenMesh's PLY reader crashes or loops forever on malformed headers and trusts element counts,
/// so the header is validated strictly first, and the counts are checked against the body's size.
void checkPly(const std::filesystem::path& file, const std::string& what)
{
    std::ifstream in(file, std::ios::binary);
    std::string line;
    if (!std::getline(in, line) || tokens(line) != std::vector<std::string>{"ply"})
        throw Error(what + ": not a PLY file (no 'ply' magic line)");
    std::string format;
    std::vector<std::pair<unsigned long long, std::size_t>> elements; // count, minimum bytes each
    for (int n = 2;; ++n) {
        if (!std::getline(in, line))
            throw Error(what + ": truncated PLY header (no end_header)");
        const std::vector<std::string> t = tokens(line);
        const std::string bad = what + ": malformed PLY header line " + std::to_string(n);
        if (t.empty() || t[0] == "comment" || t[0] == "obj_info")
            continue;
        if (t[0] == "end_header")
            break;
        if (t[0] == "format") {
            if (t.size() != 3 || t[2] != "1.0" ||
                (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian"))
                throw Error(bad);
            format = t[1];
        } else if (t[0] == "element") {
            if (t.size() != 3 || !isNumber(t[2], true) || t[2][0] == '-' || std::stoull(t[2]) > 0xffffffffull)
                throw Error(bad);
            elements.emplace_back(std::stoull(t[2]), 0);
        } else if (t[0] == "property" && !elements.empty()) {
            const bool list = t.size() == 5 && t[1] == "list" && plyTypeSize(t[2]) && t[2] != "float" &&
                              t[2] != "float32" && t[2] != "double" && t[2] != "float64" && plyTypeSize(t[3]);
            if (!list && !(t.size() == 3 && plyTypeSize(t[1])))
                throw Error(bad);
            elements.back().second += plyTypeSize(list ? t[2] : t[1]);
        } else {
            throw Error(bad);
        }
    }
    if (format.empty())
        throw Error(what + ": PLY header has no format line");

    // Every element needs at least its minimum size in a binary body, or a line in an ASCII one.
    unsigned long long needed = 0;
    for (const auto& [count, bytes] : elements)
        needed += count * (format == "ascii" ? 1 : bytes);
    unsigned long long available = 0;
    if (format == "ascii") {
        while (std::getline(in, line))
            available += tokens(line).empty() ? 0 : 1;
    } else {
        const auto body = in.tellg();
        in.seekg(0, std::ios::end);
        available = static_cast<unsigned long long>(in.tellg() - body);
    }
    if (needed > available)
        throw Error(what + ": truncated: the PLY header declares more elements than the file holds");
}

/// OpenMesh skips vertex lines it cannot parse ("v nan 0 0") and stops early at a truncated end,
/// which would silently shift or drop geometry; compare what it delivered with what the file says.
void checkCounts(const CollectingImporter& got, const std::filesystem::path& file, const std::string& ext,
                 const std::string& what)
{
    const auto vertices = static_cast<long long>(got.mesh.positions.size());
    if (ext == ".obj") {
        std::ifstream in(file, std::ios::binary);
        long long lines = 0;
        for (std::string line; std::getline(in, line);)
            if (const auto t = tokens(line); !t.empty() && t.front() == "v")
                ++lines;
        if (lines != vertices)
            throw Error(what + ": " + std::to_string(lines - vertices) + " of " + std::to_string(lines) +
                        " vertex lines could not be read (non-numeric coordinates?)");
    } else if (ext == ".ply" || ext == ".off") { // their readers report the header counts via reserve()
        if (got.declaredVertices >= 0 && got.declaredVertices != vertices)
            throw Error(what + ": truncated or malformed: header declares " + std::to_string(got.declaredVertices) +
                        " vertices, " + std::to_string(vertices) + " were read");
        if (got.declaredFaces >= 0 && got.declaredFaces != got.faces)
            throw Error(what + ": truncated or malformed: header declares " + std::to_string(got.declaredFaces) +
                        " faces, " + std::to_string(got.faces) + " were read");
    }
}

/// The three coordinates at t[at..at+2]; `index` names the vertex in errors.
glm::vec3 stlVertex(const std::vector<std::string>& t, std::size_t at, std::size_t index, const std::string& what)
{
    glm::vec3 v;
    for (std::size_t k = 0; k < 3; ++k) {
        if (at + k >= t.size() || !isNumber(t[at + k], false))
            throw Error(what + ": STL vertex " + std::to_string(index) + " is truncated or not numeric");
        v[static_cast<int>(k)] = std::stof(t[at + k]);
    }
    return v;
}

/// ASCII STL: "solid name (facet normal n n n outer loop (vertex x y z){3,} endloop endfacet)*
/// endsolid", possibly several solids. Loops with more than 3 vertices are fan-triangulated.
Mesh readAsciiStl(const std::string& text, const std::string& what)
{
    const std::vector<std::string> t = tokens(text);
    Mesh mesh;
    std::size_t i = 0;
    auto expect = [&](const char* word) {
        if (i >= t.size() || t[i] != word)
            throw Error(what + ": malformed or truncated STL: expected '" + word + "' at token " + std::to_string(i));
        ++i;
    };
    while (i < t.size()) {
        expect("solid");
        while (i < t.size() && t[i] != "facet" && t[i] != "endsolid")
            ++i; // the solid's name
        while (i < t.size() && t[i] == "facet") {
            ++i;
            expect("normal");
            i += 3;
            expect("outer");
            expect("loop");
            const auto first = static_cast<std::uint32_t>(mesh.positions.size());
            while (i < t.size() && t[i] == "vertex") {
                mesh.positions.push_back(stlVertex(t, i + 1, mesh.positions.size(), what));
                i += 4;
            }
            const auto count = static_cast<std::uint32_t>(mesh.positions.size()) - first;
            if (count < 3)
                throw Error(what + ": STL facet with " + std::to_string(count) + " vertices");
            for (std::uint32_t k = 1; k + 1 < count; ++k)
                mesh.indices.insert(mesh.indices.end(), {first, first + k, first + k + 1});
            expect("endloop");
            expect("endfacet");
        }
        expect("endsolid");
        while (i < t.size() && t[i] != "solid")
            ++i; // the name after endsolid
    }
    return mesh;
}

/// Binary STL: 80-byte header, u32 count, then per facet 12 floats (normal, 3 vertices) + u16.
Mesh readBinaryStl(const std::string& bytes)
{
    static_assert(sizeof(glm::vec3) == 12, "vertices are copied as 3 packed floats");
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    Mesh mesh;
    mesh.positions.resize(std::size_t(count) * 3);
    for (std::size_t f = 0; f < count; ++f)
        std::memcpy(&mesh.positions[3 * f], bytes.data() + 84 + 50 * f + 12, 36);
    mesh.indices.resize(mesh.positions.size());
    for (std::size_t k = 0; k < mesh.indices.size(); ++k)
        mesh.indices[k] = static_cast<std::uint32_t>(k);
    return mesh;
}

/// A file is binary STL exactly when its size matches its facet count; "solid" starts an ASCII one.
Mesh readStl(const std::filesystem::path& file, const std::string& what)
{
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() >= 84) {
        std::uint32_t count = 0;
        std::memcpy(&count, bytes.data() + 80, 4);
        if (bytes.size() == 84 + 50 * std::uint64_t(count))
            return readBinaryStl(bytes);
    }
    if (bytes.compare(0, 5, "solid") == 0)
        return readAsciiStl(bytes, what);
    throw Error(what + ": not an STL file, or a truncated binary one (size does not match the facet count)");
}

std::string lowerExtension(const std::filesystem::path& file)
{
    std::string e = file.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e;
}

class OpenMeshImporter final : public SceneImporter {
public:
    std::string name() const override { return "OBJ/PLY/OFF (OpenMesh), STL"; }
    std::vector<std::string> extensions() const override { return {".obj", ".ply", ".off", ".stl"}; }

    Scene load(const std::filesystem::path& file, std::vector<std::string>& warnings) const override
    {
        const std::string what = file.string();
        const std::string ext = lowerExtension(file);
        if (ext == ".stl")
            return oneInstance(readStl(file, what), file);
        silenceOpenMesh();
        CollectingImporter importer;
        IO::Options options;
        bool ok = false;
        try {
            if (ext == ".ply")
                checkPly(file, what);
            if (ext == ".off") {
                std::istringstream stream(normalisedOff(file, what));
                ok = IO::IOManager().read(stream, "off", importer, options);
            } else {
                ok = IO::IOManager().read(what, importer, options);
            }
        } catch (const Error&) {
            throw;
        } catch (const std::exception& e) { // readers may throw on hostile input (e.g. bad_alloc)
            throw Error(what + ": cannot be read (" + e.what() + ")");
        }
        checkCounts(importer, file, ext, what); // first: a skipped vertex is the root cause of bad indices
        if (!importer.error.empty())
            throw Error(what + ": " + importer.error);
        if (!ok)
            throw Error(what + ": cannot be read (malformed, truncated or unsupported file)");
        if (importer.mesh.positions.empty())
            warnings.push_back(what + ": no vertices");

        return oneInstance(std::move(importer.mesh), file);
    }

private:
    /// The file's one mesh, named after the file, at the origin. These formats carry no
    /// watertight flag: a closed, outward mesh earns it (watertight culling, §7).
    static Scene oneInstance(Mesh mesh, const std::filesystem::path& file)
    {
        mesh.name = file.stem().string();
        mesh.watertight = closedAndOutward(mesh);
        Scene scene;
        scene.addMeshInstance(std::move(mesh));
        validate(scene, file.string());
        return scene;
    }
};

} // namespace

std::unique_ptr<SceneImporter> makeOpenMeshImporter() { return std::make_unique<OpenMeshImporter>(); }

} // namespace sightline
