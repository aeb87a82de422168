#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <new>
#include <unordered_map>

#include "BuiltinFormats.h"
#include "TextureMean.h"
#include "mesh/MeshReaders.h"
#include "plugins/MeshTopology.h"
#include "base/Error.h"
#include "base/ImageFile.h"
#include "base/InputFile.h"
#include "base/PathRule.h"
#include "visibility/Scene.h"

// OBJ, PLY, OFF and STL as scenes: one mesh per file, read by mesh/MeshReaders.h. An OBJ's
// triangles take their material's diffuse colour (its .mtl libraries, read from the OBJ's folder)
// as their albedo for indirect light, times the mean of its diffuse texture (map_Kd) over the
// triangle where it has one.

namespace sightline {

namespace {

/// A material as an OBJ's triangles take it: its library's entry and, where it has a texture, the
/// texture's file resolved (empty where it is refused or missing: the albedo is then unknown).
struct ObjMaterial {
    meshio::MtlMaterial mtl;
    std::filesystem::path texture;
};

/// Where a file a material library names lies: relative to that library's folder, and read only
/// where it resolves inside the OBJ's folder (PathRule.h; absolute paths are refused, as glTF's
/// URIs). Missing or refused: a warning (`what` names it) and an empty path.
std::filesystem::path referencedFile(const std::string& written, const std::filesystem::path& from, const std::filesystem::path& folder,
                                     const std::string& what, std::vector<std::string>& warnings)
{
    const std::filesystem::path path = from / written;
    std::error_code error;
    const bool absolute = std::filesystem::path(written).is_absolute();
    if (!absolute && !std::filesystem::exists(path, error)) {
        warnings.push_back(what + " is not there");
        return {};
    }
    if (absolute || !resolvesInside(path, folder)) {
        warnings.push_back(what + " is outside the OBJ's folder: not read");
        return {};
    }
    return path;
}

/// The materials an OBJ's libraries define, their textures' files resolved where `textures`. A
/// library or texture that is missing, unreadable or outside the OBJ's folder is a warning: the
/// level does not need it.
std::unordered_map<std::string, ObjMaterial> readMaterialLibraries(const std::vector<std::string>& libraries, const std::filesystem::path& file,
                                                                   bool textures, std::vector<std::string>& warnings)
{
    std::unordered_map<std::string, ObjMaterial> materials;
    const std::filesystem::path folder = file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
    for (const std::string& written : libraries) {
        const std::string what = file.string() + ": material library '" + written + "'";
        const std::filesystem::path path = referencedFile(written, folder, folder, what, warnings);
        if (path.empty()) {
            warnings.back() += ", its materials' albedos unknown";
            continue;
        }
        try {
            for (auto& [name, mtl] : meshio::readMtl(readInputFile(path, "material library"), path.string(), warnings)) {
                ObjMaterial material{mtl, {}};
                if (!mtl.texture.empty() && textures) {
                    material.texture = referencedFile(mtl.texture, path.parent_path(), folder,
                                                      path.string() + ": texture '" + mtl.texture + "' of material '" + name + "'", warnings);
                    if (material.texture.empty())
                        warnings.back() += "; its albedo is unknown";
                }
                materials.try_emplace(name, std::move(material));   // the first library to define a name holds it
            }
        } catch (const Error& e) {
            warnings.push_back(std::string(e.what()) + "; its materials' albedos unknown");
        }
    }
    return materials;
}

/// A textured material's albedo on one triangle: Kd (white without one) times its texture's mean
/// over the triangle's vt (TextureMean.h; OBJ's v runs up, the texture's rows down); unknown where
/// a corner has no usable vt.
glm::vec3 texturedAlbedo(const ObjMaterial& material, const std::vector<RgbImage>& mips, const meshio::ObjMaterialUse& use, std::size_t triangle)
{
    const meshio::MtlMaterial& mtl = material.mtl;
    if (mtl.diffuseGiven && mtl.diffuse == kUnknownAlbedo)
        return kUnknownAlbedo;
    glm::dvec2 uv[3];
    for (int k = 0; k < 3; ++k) {
        const std::int32_t index = use.triangleTexCoords[triangle][std::size_t(k)];
        if (index < 0)
            return kUnknownAlbedo;
        const glm::dvec2 moved = use.texCoords[std::size_t(index)] * mtl.scale + mtl.offset;
        if (!std::isfinite(moved.x) || !std::isfinite(moved.y))
            return kUnknownAlbedo;
        uv[k] = {moved.x, 1.0 - moved.y};
    }
    const int wrap = mtl.clamp ? texture::kWrapClamp : texture::kWrapRepeat;
    return (mtl.diffuseGiven ? mtl.diffuse : glm::vec3(1.0f)) * texture::meanOverTriangle(mips, uv[0], uv[1], uv[2], {wrap, wrap});
}

/// Each triangle's albedo from its material (Mesh::albedo); none when no triangle's is known.
/// Without `textures`, a textured material's albedo is unknown (its texture not read).
void applyObjMaterials(Mesh& mesh, const meshio::ObjMaterialUse& use, const std::filesystem::path& file, bool textures,
                       std::vector<std::string>& warnings)
{
    if (use.names.empty())
        return;
    const std::unordered_map<std::string, ObjMaterial> known = readMaterialLibraries(use.libraries, file, textures, warnings);
    std::vector<const ObjMaterial*> byIndex(use.names.size(), nullptr);
    std::size_t undefined = 0;
    for (std::size_t m = 0; m < use.names.size(); ++m) {
        const auto found = known.find(use.names[m]);
        if (found != known.end())
            byIndex[m] = &found->second;
        else if (undefined++ == 0)
            warnings.push_back(file.string() + ": material '" + use.names[m] + "' is not defined by its libraries"
                               " (the first of the undefined); its albedo is unknown");
    }
    texture::DecodedTextures decoded;
    mesh.albedo.reserve(use.triangleMaterial.size());
    bool anyKnown = false;
    std::size_t uncoloured = 0;   // textured triangles without usable vt
    int lastMaterial = -1;
    const std::vector<RgbImage>* mips = nullptr;   // lastMaterial's texture
    for (std::size_t t = 0; t < use.triangleMaterial.size(); ++t) {
        const int m = use.triangleMaterial[t];
        const ObjMaterial* material = m < 0 ? nullptr : byIndex[std::size_t(m)];
        glm::vec3 albedo = kUnknownAlbedo;
        if (material && material->mtl.texture.empty()) {
            albedo = material->mtl.diffuse;
        } else if (material && !material->texture.empty()) {
            if (m != lastMaterial) {   // a kept chain stays put until another one is decoded
                const std::filesystem::path& image = material->texture;
                mips = decoded.get(image.string(), [&] { return loadRgbImage(image); }, warnings);
                lastMaterial = m;
            }
            if (mips) {
                albedo = texturedAlbedo(*material, *mips, use, t);
                uncoloured += albedo == kUnknownAlbedo;
            }
        }
        mesh.albedo.push_back(albedo);
        anyKnown = anyKnown || albedo != kUnknownAlbedo;
    }
    if (uncoloured > 0)
        warnings.push_back(file.string() + ": " + std::to_string(uncoloured) +
                           " triangles of textured materials have no usable texture coordinates (vt); their albedo is unknown");
    if (!anyKnown)
        mesh.albedo.clear();
}

std::string lowerExtension(const std::filesystem::path& file)
{
    std::string e = file.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e;
}

class MeshFileImporter final : public SceneImporter {
public:
    std::string name() const override { return "OBJ/PLY/OFF/STL"; }
    std::vector<std::string> extensions() const override { return {".obj", ".ply", ".off", ".stl"}; }

    Scene load(const std::filesystem::path& file, std::vector<std::string>& warnings, const SceneLoadOptions& options) const override
    {
        const std::string what = file.string();
        // The importer interface has no role: these files are scenes or occluder meshes of one.
        const std::string bytes = readInputFile(file, "scene");
        const std::string ext = lowerExtension(file);
        Mesh mesh;
        meshio::ObjMaterialUse materials;
        try {
            mesh = ext == ".stl"   ? meshio::readStl(bytes, what)
                   : ext == ".obj" ? meshio::readObj(bytes, what, warnings, &materials)
                   : ext == ".ply" ? meshio::readPly(bytes, what)
                                   : meshio::readOff(bytes, what);
        } catch (const std::bad_alloc&) {
            // Memory grows with the geometry a file holds (a few times its size): still one line.
            throw Error(what + ": out of memory while reading " + std::to_string(bytes.size() >> 20) + " MB of geometry");
        }
        if (mesh.positions.empty())
            warnings.push_back(what + ": no vertices");
        applyObjMaterials(mesh, materials, file, options.textureAlbedos, warnings);
        return oneInstance(std::move(mesh), file);
    }

private:
    /// The file's one mesh, named after the file, at the origin. These formats carry no
    /// watertight flag: a closed, outward mesh earns it (watertight culling, §7).
    static Scene oneInstance(Mesh mesh, const std::filesystem::path& file)
    {
        mesh.name = file.stem().string();
        mesh.watertight = meshTopology(mesh).closedAndOutward();
        Scene scene;
        scene.addMeshInstance(std::move(mesh));
        validate(scene, file.string());
        return scene;
    }
};

} // namespace

std::unique_ptr<SceneImporter> makeMeshFileImporter() { return std::make_unique<MeshFileImporter>(); }

} // namespace sightline
