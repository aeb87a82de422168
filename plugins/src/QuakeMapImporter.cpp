// Quake map sources (.map) as scenes: the world's brushes (worldspawn, and the func_group and
// func_detail entities compilers merge into it), each brush's faces in metres with Y up (1 unit =
// 0.0254 m; Quake's Z up becomes Y, its Y becomes -Z, a rotation), wound counter-clockwise seen from
// outside the brush. Faces a player sees through or never sees are left out: liquids ("*..."),
// and the tool textures that compile to nothing visible (clip, trigger, skip, hint, origin, nodraw).
// Other brush entities (doors, lifts, triggers) move or vanish in the game and are left out, as the
// BSP importer leaves out the models they compile to. Brushes are not merged (no CSG): faces
// inside solid stay, which no line of sight from open space can reach.

#include <algorithm>
#include <cctype>
#include <string>

#include "BuiltinFormats.h"
#include "QuakeUnits.h"
#include "plugins/QuakeMap.h"
#include "visibility/Error.h"
#include "visibility/InputFile.h"

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

class QuakeMapImporter final : public SceneImporter {
public:
    std::string name() const override { return "Quake map"; }
    std::vector<std::string> extensions() const override { return {".map"}; }

    Scene load(const std::filesystem::path& file, std::vector<std::string>& warnings) const override
    {
        const std::string what = file.string();
        const QuakeMap map = parseQuakeMap(readInputFile(file, "scene"), what);
        std::vector<glm::vec3> corners;
        std::size_t entitiesLeftOut = 0, facesLeftOut = 0;
        for (const MapEntity& entity : map.entities) {
            if (!isWorld(entity.classname())) {
                entitiesLeftOut += !entity.brushes.empty();
                continue;
            }
            for (const MapBrush& brush : entity.brushes)
                for (const BrushFace& face : brushFaces(brush)) {
                    if (seenThrough(face.texture)) {
                        ++facesLeftOut;
                        continue;
                    }
                    for (std::size_t k = 1; k + 1 < face.polygon.size(); ++k)
                        for (std::size_t c : {std::size_t(0), k, k + 1})
                            corners.push_back(quakeToYUpMetres(face.polygon[c]));
                }
        }
        if (entitiesLeftOut)
            warnings.push_back(what + ": " + std::to_string(entitiesLeftOut) + " brush entities (doors, lifts, triggers) left out");
        if (facesLeftOut)
            warnings.push_back(what + ": " + std::to_string(facesLeftOut) + " liquid and tool-textured faces left out (seen through)");
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
