#include <algorithm>
#include <cctype>
#include <filesystem>
#include <new>
#include <unordered_map>

#include "BuiltinFormats.h"
#include "mesh/MeshReaders.h"
#include "plugins/MeshTopology.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "base/PathRule.h"
#include "visibility/Scene.h"

// OBJ, PLY, OFF and STL as scenes: one mesh per file, read by mesh/MeshReaders.h. An OBJ's
// triangles take their material's diffuse colour (its .mtl libraries, read from the OBJ's folder)
// as their albedo for indirect light.

namespace sightline {

namespace {

/// The albedos of the materials an OBJ's libraries define. A library that is missing, unreadable
/// or outside the OBJ's folder (PathRule.h; absolute paths too, as glTF's URIs) is a warning: the
/// level does not need it.
std::unordered_map<std::string, glm::vec3> readMaterialLibraries(const std::vector<std::string>& libraries,
                                                                 const std::filesystem::path& file,
                                                                 std::vector<std::string>& warnings)
{
    std::unordered_map<std::string, glm::vec3> albedo;
    const std::filesystem::path folder = file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
    for (const std::string& written : libraries) {
        const std::filesystem::path path = folder / written;
        const std::string what = file.string() + ": material library '" + written + "'";
        std::error_code error;
        const bool absolute = std::filesystem::path(written).is_absolute();
        if (!absolute && !std::filesystem::exists(path, error)) {
            warnings.push_back(what + " is not there: its materials' albedos unknown");
            continue;
        }
        if (absolute || !resolvesInside(path, folder)) {
            warnings.push_back(what + " is outside the OBJ's folder: not read, its materials' albedos unknown");
            continue;
        }
        try {
            for (auto& [name, colour] : meshio::readMtl(readInputFile(path, "material library"), path.string(), warnings))
                albedo.try_emplace(name, colour);   // the first library to define a name holds it
        } catch (const Error& e) {
            warnings.push_back(std::string(e.what()) + "; its materials' albedos unknown");
        }
    }
    return albedo;
}

/// Each triangle's albedo from its material (Mesh::albedo); none when no triangle's is known.
void applyObjMaterials(Mesh& mesh, const meshio::ObjMaterialUse& use, const std::filesystem::path& file,
                       std::vector<std::string>& warnings)
{
    if (use.names.empty())
        return;
    const std::unordered_map<std::string, glm::vec3> known = readMaterialLibraries(use.libraries, file, warnings);
    std::vector<glm::vec3> byIndex(use.names.size(), kUnknownAlbedo);
    std::size_t undefined = 0;
    for (std::size_t m = 0; m < use.names.size(); ++m) {
        const auto found = known.find(use.names[m]);
        if (found != known.end())
            byIndex[m] = found->second;
        else if (undefined++ == 0)
            warnings.push_back(file.string() + ": material '" + use.names[m] + "' is not defined by its libraries"
                               " (the first of the undefined); its albedo is unknown");
    }
    mesh.albedo.reserve(use.triangleMaterial.size());
    bool anyKnown = false;
    for (const int m : use.triangleMaterial) {
        mesh.albedo.push_back(m < 0 ? kUnknownAlbedo : byIndex[std::size_t(m)]);
        anyKnown = anyKnown || mesh.albedo.back() != kUnknownAlbedo;
    }
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

    Scene load(const std::filesystem::path& file, std::vector<std::string>& warnings) const override
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
        applyObjMaterials(mesh, materials, file, warnings);
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
