// Compiled Quake 1 and Half-Life levels (.bsp: BSP29, BSP2, BSP30) as scenes: the world model's faces, in metres with Y
// up (1 Quake unit = 1 inch = 0.0254 m; Quake's Z up becomes Y, its Y becomes -Z, a rotation),
// each polygon fan-triangulated and wound counter-clockwise seen from its front as glTF winds.
// Liquid surfaces (textures named "*...", in Half-Life "!...") are left out: a player sees through them. Sky faces
// stay: they close the level. Brush entities (doors, lifts: models 1..n) are not the world and
// are left out, as scripts/quake_bsp_to_obj.py leaves them.

#include <string>

#include "BuiltinFormats.h"
#include "QuakeUnits.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "visibility/bsp/QuakeBsp.h"

namespace sightline {

namespace {

class QuakeBspImporter final : public SceneImporter {
public:
    std::string name() const override { return "Quake BSP"; }
    std::vector<std::string> extensions() const override { return {".bsp"}; }

    Scene load(const std::filesystem::path& file, std::vector<std::string>& warnings, const SceneLoadOptions&) const override
    {
        const std::string what = file.string();
        const bsp::QuakeBsp level = bsp::readQuakeBsp(readInputFile(file, "scene"), what);
        std::vector<glm::vec3> corners;
        std::size_t liquids = 0;
        for (const bsp::BspFace& face : bsp::worldFaces(level, what)) {
            if (!face.texture.empty() && (face.texture[0] == '*' || (level.format == bsp::BspFormat::HalfLife30 && face.texture[0] == '!'))) {
                ++liquids;
                continue;
            }
            // Quake winds clockwise seen from the front: walk the polygon backwards.
            const std::size_t n = face.polygon.size();
            for (std::size_t k = 1; k + 1 < n; ++k) {
                corners.push_back(quakeToYUpMetres(face.polygon[0]));
                corners.push_back(quakeToYUpMetres(face.polygon[n - k]));
                corners.push_back(quakeToYUpMetres(face.polygon[n - k - 1]));
            }
        }
        if (liquids)
            warnings.push_back(what + ": " + std::to_string(liquids) + " liquid surfaces left out (seen through)");
        if (corners.empty())
            warnings.push_back(what + ": the world model has no faces");

        return quakeLevelScene(corners, file);
    }
};

} // namespace

std::unique_ptr<SceneImporter> makeQuakeBspImporter() { return std::make_unique<QuakeBspImporter>(); }

} // namespace sightline
