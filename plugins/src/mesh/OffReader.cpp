#include "mesh/MeshReaders.h"

#include <algorithm>

#include "base/Error.h"
#include "mesh/MeshText.h"

namespace sightline::meshio {

namespace {

/// The next line with a token after '#' comments are cut; false at the end of the text.
bool nextOffLine(Lines& lines, std::string_view& line)
{
    while (lines.next(line)) {
        line = line.substr(0, line.find('#'));
        if (std::string_view token; Tokens(line).next(token))
            return true;
    }
    return false;
}

/// "[ST][C][N]OFF" (the prefixes announce extra per-vertex data, which is not needed) with the
/// counts on its line or the next; binary and n-dimensional OFF are refused.
std::pair<std::size_t, std::size_t> offCounts(Lines& lines, const std::string& what)
{
    std::string_view line;
    if (!nextOffLine(lines, line))
        throw Error(what + ": empty OFF file");
    Tokens t(line);
    std::string_view keyword, token;
    t.next(keyword);
    const std::size_t prefix = keyword.size() >= 3 ? keyword.size() - 3 : 0;
    if (keyword.size() < 3 || keyword.substr(prefix) != "OFF" || keyword.substr(0, prefix).find_first_not_of("STCN") != npos)
        throw Error(what + ": not a supported OFF file (header " + quote(keyword) + ")");
    if (!t.next(token)) { // the counts are on the next line
        if (!nextOffLine(lines, line))
            throw Error(what + ": OFF header has no vertex and face counts");
        t = Tokens(line);
        t.next(token);
    }
    if (token == "BINARY")
        throw Error(what + ": binary OFF is not supported; save it as ASCII OFF, PLY or OBJ");
    long long counts[2] = {-1, -1};
    for (int k = 0; k < 2; ++k)
        if (const std::string why = readInteger(token, counts[k]); !why.empty() || counts[k] < 0 || (k == 0 && !t.next(token)))
            failAt(what, lines.number(), "OFF header has no valid vertex and face counts");
    return {static_cast<std::size_t>(counts[0]), static_cast<std::size_t>(counts[1])};
}

/// ASCII OFF, line by line: vertex lines "x y z ..." and face lines "n i1 .. in ..." (colours and
/// other trailing per-element data are not needed). Nothing is reserved from the header's counts.

} // namespace

Mesh readOff(std::string_view text, const std::string& what)
{
    Lines lines(text);
    const auto counts = offCounts(lines, what);
    const std::size_t vertices = counts.first, faces = counts.second;   // lambdas capture these (clang 14: not bindings)
    const auto truncated = [&](std::size_t v, std::size_t f) {
        throw Error(what + ": truncated: the header declares " + plural(vertices, "vertex") + " and " + plural(faces, "face") +
                    ", the data holds " + plural(v, "vertex") + " and " + plural(f, "face"));
    };
    Mesh mesh;
    std::string_view line, token;
    for (std::size_t i = 0; i < vertices; ++i) {
        if (!nextOffLine(lines, line))
            truncated(i, 0);
        Tokens t(line);
        glm::vec3 p(0.0f);
        for (int k = 0; k < 3; ++k) {
            if (!t.next(token))
                failAt(what, lines.number(), "vertex " + std::to_string(i) + " has fewer than 3 coordinates");
            if (const std::string why = readFloat(token, p[k]); !why.empty())
                failAt(what, lines.number(), "vertex " + std::to_string(i) + ": " + why);
        }
        mesh.positions.push_back(p);
    }
    std::vector<std::uint32_t> polygon;
    for (std::size_t f = 0; f < faces; ++f) {
        if (!nextOffLine(lines, line))
            truncated(vertices, f);
        const std::string face = "face " + std::to_string(f);
        Tokens t(line);
        long long n = 0;
        t.next(token);
        if (const std::string why = readInteger(token, n); !why.empty())
            failAt(what, lines.number(), face + ": vertex count " + why);
        if (n < 3)
            failAt(what, lines.number(), face + " " + polygonTooSmall(static_cast<std::size_t>(std::max(0ll, n))));
        polygon.clear();
        for (long long k = 0; k < n; ++k) {
            long long index = 0;
            if (!t.next(token))
                failAt(what, lines.number(), face + " announces " + std::to_string(n) + " vertices but lists " + std::to_string(k));
            if (const std::string why = readInteger(token, index); !why.empty())
                failAt(what, lines.number(), face + ": vertex index " + why);
            if (index < 0 || static_cast<unsigned long long>(index) >= vertices)
                failAt(what, lines.number(), face + ": vertex index " + std::to_string(index) + " is out of range (" +
                                                 plural(vertices, "vertex") + ")");
            polygon.push_back(static_cast<std::uint32_t>(index));
        }
        addFan(mesh, polygon);
    }
    if (nextOffLine(lines, line))
        failAt(what, lines.number(), "the data continues past the " + plural(faces, "face") + " the header declares");
    return mesh;
}

} // namespace sightline::meshio
