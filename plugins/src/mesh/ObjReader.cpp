#include "mesh/MeshReaders.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "base/Error.h"
#include "mesh/MeshText.h"

namespace sightline::meshio {

namespace {

/// "v x y z [w | r g b [a]]": every value must be a number; only x, y, z are kept.
glm::vec3 objVertex(Tokens& t, const std::string& what, std::size_t line)
{
    glm::vec3 p(0.0f);
    int n = 0;
    for (std::string_view token; t.next(token); ++n) {
        float value = 0.0f;
        if (const std::string why = readFloat(token, value); !why.empty())
            failAt(what, line, "vertex value " + why);
        if (n < 3)
            p[n] = value;
    }
    if (n < 3)
        failAt(what, line, "vertex has " + std::to_string(n) + " coordinates, 3 are needed");
    if (n > 7)
        failAt(what, line, "vertex has " + std::to_string(n) + " values (x y z, then at most w or r g b [a])");
    return p;
}

/// "vt u [v [w]]": (u, v), v = 0 when absent; not finite where a value is not a number (texture
/// coordinates colour albedos only, so such a vt is not refused: what uses it is left uncoloured).
glm::dvec2 objTexCoord(Tokens& t)
{
    glm::dvec2 uv(0.0);
    int n = 0;
    for (std::string_view token; t.next(token); ++n) {
        float value = 0.0f;
        if (!readFloat(token, value).empty() || n > 2)
            return glm::dvec2(NAN);
        if (n < 2)
            uv[n] = value;
    }
    return n == 0 ? glm::dvec2(NAN) : uv;
}

/// A 1-based or negative OBJ index resolved against `count` elements read so far; -1 where it
/// names none.
long long resolveIndex(long long k, std::size_t count)
{
    const long long resolved = k > 0 ? k - 1 : static_cast<long long>(count) + k;
    return k == 0 || resolved < 0 || resolved >= static_cast<long long>(count) ? -1 : resolved;
}

/// One face corner "v", "v/vt", "v//vn" or "v/vt/vn" as a 0-based position index. Positive
/// indices count from 1, negative ones back from the last vertex so far; both must name a vertex
/// already read (OBJ defines them that way). vt and vn must be integers; `texCoord` is vt's
/// 0-based index, -1 where the corner has none or it names no vt read so far (albedos only: not
/// refused). vn is not needed.
std::uint32_t objCorner(std::string_view token, std::size_t vertices, std::size_t texCoords, long long& texCoord, const std::string& what,
                        std::size_t line)
{
    const std::string_view index = token.substr(0, token.find('/'));
    if (index.empty())
        failAt(what, line, "face index is empty in " + quote(token));
    texCoord = -1;
    for (std::size_t at = token.find('/'), parts = 1; at != npos; at = token.find('/', at + 1), ++parts) {
        const std::size_t end = token.find('/', at + 1);
        const std::string_view part = token.substr(at + 1, end == npos ? npos : end - at - 1);
        long long value = 0;
        if (parts >= 3)
            failAt(what, line, "face corner " + quote(token) + " has more than v/vt/vn");
        if (!part.empty())
            if (const std::string why = readInteger(part, value); !why.empty())
                failAt(what, line, "face corner " + quote(token) + ": " + why);
        if (parts == 1 && !part.empty())
            texCoord = resolveIndex(value, texCoords);
    }
    long long k = 0;
    if (const std::string why = readInteger(index, k); !why.empty())
        failAt(what, line, "face index " + why);
    if (k == 0)
        failAt(what, line, "face index 0 is invalid (OBJ counts from 1, or back from -1)");
    const long long resolved = resolveIndex(k, vertices);
    if (resolved < 0)
        failAt(what, line, "face index " + std::string(index) + " is out of range (" + plural(vertices, "vertex") + ")");
    return static_cast<std::uint32_t>(resolved);
}

/// Statements that carry no surface geometry (attributes, grouping, texture maps, curve settings).
bool objIgnorable(std::string_view keyword)
{
    static const char* const kIgnored[] = {"vn", "vp", "o", "g", "s", "mg", "maplib",
                                           "usemap", "lod", "shadow_obj", "trace_obj", "ctech", "stech", "bevel",
                                           "c_interp", "d_interp", "cstype", "deg", "bmat", "step", "parm",
                                           "trim", "hole", "scrv", "sp", "end", "con", "call", "csh"};
    return std::find(std::begin(kIgnored), std::end(kIgnored), keyword) != std::end(kIgnored);
}

/// OBJ read by a strict line scanner: v and f (fo) make the mesh; points and lines block no rays and
/// are counted in a warning; free-form curves and surfaces would be geometry lost, so they are
/// refused; unknown statements are warned about, and a line that starts with no keyword is refused.

} // namespace

Mesh readObj(std::string_view text, const std::string& what, std::vector<std::string>& warnings, ObjMaterialUse* materials)
{
    Mesh mesh;
    ObjMaterialUse use;
    std::unordered_map<std::string, int> materialIndex;
    int current = -1;
    Lines lines(text);
    std::vector<std::uint32_t> polygon;
    std::vector<long long> polygonCoords;
    std::size_t pointsAndLines = 0, unknown = 0, firstUnknown = 0;
    std::string unknownKeyword;
    for (std::string_view line; lines.next(line);) {
        const std::size_t number = lines.number();
        if (line.find('\0') != npos)
            failAt(what, number, "contains a NUL byte (binary data, not OBJ text)");
        Tokens t(line.substr(0, line.find('#')));
        std::string_view keyword;
        if (!t.next(keyword))
            continue;
        if (keyword == "v") {
            mesh.positions.push_back(objVertex(t, what, number));
        } else if (keyword == "vt") {
            use.texCoords.push_back(objTexCoord(t));
        } else if (keyword == "f" || keyword == "fo") {
            polygon.clear();
            polygonCoords.clear();
            for (std::string_view token; t.next(token);) {
                long long texCoord = -1;
                polygon.push_back(objCorner(token, mesh.positions.size(), use.texCoords.size(), texCoord, what, number));
                polygonCoords.push_back(texCoord);
            }
            if (polygon.size() < 3)
                failAt(what, number, "face " + polygonTooSmall(polygon.size()));
            addFan(mesh, polygon);
            use.triangleMaterial.insert(use.triangleMaterial.end(), polygon.size() - 2, current);
            for (std::size_t k = 1; k + 1 < polygonCoords.size(); ++k)   // as addFan
                use.triangleTexCoords.push_back({std::int32_t(polygonCoords[0]), std::int32_t(polygonCoords[k]), std::int32_t(polygonCoords[k + 1])});
        } else if (keyword == "usemtl") {
            const std::string name(t.rest());
            const auto [at, added] = materialIndex.try_emplace(name, int(use.names.size()));
            if (added)
                use.names.push_back(name);
            current = at->second;
        } else if (keyword == "mtllib") {
            for (std::string_view file; t.next(file);)   // names are separated by spaces
                use.libraries.emplace_back(file);
        } else if (keyword == "p" || keyword == "l") {
            ++pointsAndLines;
        } else if (keyword == "curv" || keyword == "curv2" || keyword == "surf") {
            failAt(what, number, "free-form curves and surfaces are not supported (export the mesh as polygons)");
        } else if (!std::isalpha(static_cast<unsigned char>(keyword[0]))) {
            failAt(what, number, quote(keyword) + " is not an OBJ statement");
        } else if (!objIgnorable(keyword) && unknown++ == 0) {
            firstUnknown = number;
            unknownKeyword = std::string(keyword);
        }
    }
    if (pointsAndLines > 0)
        warnings.push_back(what + ": " + std::to_string(pointsAndLines) +
                           " point and line statements ignored (they block no rays)");
    if (unknown > 0)
        warnings.push_back(what + ": " + std::to_string(unknown) + " unknown statements ignored (the first, " +
                           quote(unknownKeyword) + ", at line " + std::to_string(firstUnknown) + ")");
    if (materials)
        *materials = std::move(use);
    return mesh;
}

} // namespace sightline::meshio
