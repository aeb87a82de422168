// Quake map sources (.map) as scenes: the world's brushes (worldspawn, and the func_group and
// func_detail entities compilers merge into it), each brush's faces in metres with Y up (1 unit =
// 0.0254 m; Quake's Z up becomes Y, its Y becomes -Z, a rotation), wound counter-clockwise seen from
// outside the brush. Faces a player sees through or never sees are left out: liquids ("*..."),
// and the tool textures that compile to nothing visible (clip, trigger, skip, hint, origin, nodraw).
// Other brush entities (doors, lifts, triggers) move or vanish in the game and are left out, as the
// BSP importer leaves out the models they compile to. Brushes are not merged (no CSG), but a face
// inside another solid brush is left out: that brush's faces block every line that reaches it.

#include <algorithm>
#include <cctype>
#include <limits>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "BuiltinFormats.h"
#include "QuakeUnits.h"
#include "plugins/QuakeMap.h"
#include "base/Error.h"
#include "base/InputFile.h"

namespace sightline {

namespace {

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

bool isWorld(const std::string& classname)
{
    return classname == "worldspawn" || classname == "func_group" || classname.rfind("func_detail", 0) == 0;
}

/// Liquids (Quake's "*", Half-Life's "!") and tool textures: nothing a player's view stops at.
bool seenThrough(const std::string& texture)
{
    if (texture.empty())
        return false;
    if (texture[0] == '*' || texture[0] == '!')
        return true;
    std::string name = lower(texture);
    if (const std::size_t slash = name.rfind('/'); slash != std::string::npos)
        name = name.substr(slash + 1);   // Quake 2 and 3 name textures by path ("common/clip")
    static const char* const kTools[] = {"clip", "trigger", "skip", "hint", "hintskip", "origin", "nodraw",
                                         "null", "aaatrigger", "playerclip", "monsterclip", "clipmonster"};
    return std::find(std::begin(kTools), std::end(kTools), name) != std::end(kTools);
}

/// A world brush: its faces a player's view stops at, its box, and whether it is solid all round
/// (every face kept), so that what lies inside it is hidden.
struct WorldBrush {
    const MapBrush* brush = nullptr;
    std::vector<BrushFace> faces;
    bool solid = false;
    glm::dvec3 lo{0.0}, hi{0.0};
};

WorldBrush worldBrush(const MapBrush& brush, std::size_t& facesLeftOut)
{
    WorldBrush out{&brush, {}, true, glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(-std::numeric_limits<double>::max())};
    for (BrushFace& face : brushFaces(brush)) {
        for (const glm::dvec3& p : face.polygon)
            out.lo = glm::min(out.lo, p), out.hi = glm::max(out.hi, p);
        if (seenThrough(face.texture)) {
            ++facesLeftOut;
            out.solid = false;
            continue;
        }
        out.faces.push_back(std::move(face));
    }
    out.solid = out.solid && out.faces.size() >= 4;
    return out;
}

/// Whether a face of brush `own` lies within another solid brush: every segment that reaches it
/// from open space enters that brush first, through a face that blocks it, so the face blocks
/// nothing more (both sides of a triangle block, docs/design.md §2) and only flickers against the
/// faces it overlaps. A face lying in one of that brush's planes is covered by the brush's face
/// there; of two such faces the earlier brush's stays, so one of any coincident pair is kept.
bool buriedFace(const BrushFace& face, std::size_t own, const std::vector<WorldBrush>& brushes)
{
    constexpr double kOn = 1e-3;   // units
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::dvec3& p : face.polygon)
        lo = glm::min(lo, p), hi = glm::max(hi, p);
    for (std::size_t j = 0; j < brushes.size(); ++j) {
        const WorldBrush& other = brushes[j];
        if (j == own || !other.solid || glm::any(glm::lessThan(lo, other.lo - kOn)) || glm::any(glm::greaterThan(hi, other.hi + kOn)))
            continue;
        bool inside = true, onBoundary = false;
        for (const MapPlane& plane : other.brush->planes) {
            double highest = -std::numeric_limits<double>::max(), lowest = std::numeric_limits<double>::max();
            for (const glm::dvec3& p : face.polygon) {
                const double d = glm::dot(plane.normal, p) - plane.dist;
                highest = std::max(highest, d), lowest = std::min(lowest, d);
            }
            if (highest > kOn) {
                inside = false;
                break;
            }
            onBoundary = onBoundary || lowest >= -kOn;
        }
        if (inside && (!onBoundary || j < own))
            return true;
    }
    return false;
}

class QuakeMapImporter final : public SceneImporter {
public:
    std::string name() const override { return "Quake map"; }
    std::vector<std::string> extensions() const override { return {".map"}; }

    Scene load(const std::filesystem::path& file, std::vector<std::string>& warnings, const SceneLoadOptions&) const override
    {
        const std::string what = file.string();
        const QuakeMap map = parseQuakeMap(readInputFile(file, "scene"), what);
        std::vector<WorldBrush> brushes;
        std::size_t entitiesLeftOut = 0, facesLeftOut = 0;
        for (const MapEntity& entity : map.entities) {
            if (!isWorld(entity.classname())) {
                entitiesLeftOut += !entity.brushes.empty();
                continue;
            }
            for (const MapBrush& brush : entity.brushes)
                brushes.push_back(worldBrush(brush, facesLeftOut));
        }
        std::vector<glm::vec3> corners;
        std::size_t buried = 0;
        for (std::size_t i = 0; i < brushes.size(); ++i)
            for (const BrushFace& face : brushes[i].faces) {
                if (buriedFace(face, i, brushes)) {
                    ++buried;
                    continue;
                }
                for (std::size_t k = 1; k + 1 < face.polygon.size(); ++k)
                    for (std::size_t c : {std::size_t(0), k, k + 1})
                        corners.push_back(quakeToYUpMetres(face.polygon[c]));
            }
        if (entitiesLeftOut)
            warnings.push_back(what + ": " + std::to_string(entitiesLeftOut) + " brush entities (doors, lifts, triggers) left out");
        if (facesLeftOut)
            warnings.push_back(what + ": " + std::to_string(facesLeftOut) + " liquid and tool-textured faces left out (seen through)");
        if (buried)
            warnings.push_back(what + ": " + std::to_string(buried) + " faces inside other brushes left out (hidden by them)");
        if (map.degeneratePlanes)
            warnings.push_back(what + ": " + std::to_string(map.degeneratePlanes) + " planes of three points in a line left out");
        if (map.leftOut)
            warnings.push_back(what + ": " + std::to_string(map.leftOut) + " Quake 3 patches and brushDef blocks left out");
        if (corners.empty())
            warnings.push_back(what + ": no world brushes");

        return quakeLevelScene(corners, file);
    }
};

} // namespace

std::unique_ptr<SceneImporter> makeQuakeMapImporter() { return std::make_unique<QuakeMapImporter>(); }

} // namespace sightline
