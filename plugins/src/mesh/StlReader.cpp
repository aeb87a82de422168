#include "mesh/MeshReaders.h"

#include <cstring>

#include "base/Error.h"
#include "mesh/MeshText.h"

namespace sightline::meshio {

namespace {

/// ASCII STL: "solid name (facet normal n n n outer loop (vertex x y z){3,} endloop endfacet)*
/// endsolid", possibly several solids. Loops with more than 3 vertices are fan-triangulated.
Mesh readAsciiStl(std::string_view text, const std::string& what)
{
    TextTokens t(text);
    std::string_view token;
    bool more = t.next(token);
    const auto advance = [&] { more = t.next(token); };
    const auto expect = [&](const char* word) {
        if (!more || token != word)
            failAt(what, t.line(), "malformed or truncated STL: expected '" + std::string(word) + "', found " +
                                       (more ? quote(token) : std::string("the end of the file")));
        advance();
    };
    const auto number = [&](const char* role) {
        float v = 0.0f;
        if (!more)
            failAt(what, t.line(), "STL " + std::string(role) + " is truncated");
        if (const std::string why = readFloat(token, v); !why.empty())
            failAt(what, t.line(), "STL " + std::string(role) + ": " + why);
        advance();
        return v;
    };
    Mesh mesh;
    std::vector<std::uint32_t> loop;
    while (more) {
        expect("solid");
        while (more && token != "facet" && token != "endsolid")
            advance(); // the solid's name
        while (more && token == "facet") {
            advance();
            expect("normal");
            for (int k = 0; k < 3; ++k) { // unused, and some exporters write "nan" for degenerate facets
                if (!more || token == "outer")
                    failAt(what, t.line(), "STL facet normal has fewer than 3 values");
                advance();
            }
            expect("outer");
            expect("loop");
            loop.clear();
            while (more && token == "vertex") {
                advance();
                glm::vec3 p;
                for (int k = 0; k < 3; ++k)
                    p[k] = number("vertex");
                loop.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
                mesh.positions.push_back(p);
            }
            if (loop.size() < 3)
                failAt(what, t.line(), "STL facet " + polygonTooSmall(loop.size()));
            addFan(mesh, loop);
            expect("endloop");
            expect("endfacet");
        }
        expect("endsolid");
        while (more && token != "solid")
            advance(); // the name after endsolid
    }
    return mesh;
}

/// Binary STL: 80-byte header, u32 count, then per facet 12 floats (normal, 3 vertices) + u16.
Mesh readBinaryStl(std::string_view bytes)
{
    static_assert(sizeof(glm::vec3) == 12, "vertices are copied as 3 packed floats");
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    Mesh mesh;
    mesh.positions.resize(std::size_t(count) * 3); // the caller matched the count to the file's size
    for (std::size_t f = 0; f < count; ++f)
        std::memcpy(&mesh.positions[3 * f], bytes.data() + 84 + 50 * f + 12, 36);
    mesh.indices.resize(mesh.positions.size());
    for (std::size_t k = 0; k < mesh.indices.size(); ++k)
        mesh.indices[k] = static_cast<std::uint32_t>(k);
    return mesh;
}

/// A file is binary STL exactly when its size matches its facet count; "solid" starts an ASCII one,
/// unless it holds NUL bytes (binary exporters often start their header with "solid" too).

} // namespace

Mesh readStl(std::string_view bytes, const std::string& what)
{
    std::uint32_t count = 0;
    if (bytes.size() >= 84) {
        std::memcpy(&count, bytes.data() + 80, 4);
        if (bytes.size() == 84 + 50 * std::uint64_t(count))
            return readBinaryStl(bytes);
    }
    if (bytes.substr(0, 5) == "solid" && bytes.find('\0') == npos)
        return readAsciiStl(bytes, what);
    if (bytes.size() >= 84)
        throw Error(what + ": truncated or corrupt binary STL: the header declares " + plural(count, "facet") + " (" +
                    std::to_string(84 + 50 * std::uint64_t(count)) + " bytes), the file has " +
                    std::to_string(bytes.size()) + " bytes");
    throw Error(what + ": not an STL file (too short for binary STL, and not ASCII STL)");
}

} // namespace sightline::meshio
