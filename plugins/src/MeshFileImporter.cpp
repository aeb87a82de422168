#include <algorithm>
#include <cctype>
#include <new>

#include "BuiltinFormats.h"
#include "mesh/MeshReaders.h"
#include "plugins/MeshTopology.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "visibility/Scene.h"

// OBJ, PLY, OFF and STL as scenes: one mesh per file, read by mesh/MeshReaders.h.

namespace sightline {

namespace {

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
        try {
            mesh = ext == ".stl"   ? meshio::readStl(bytes, what)
                   : ext == ".obj" ? meshio::readObj(bytes, what, warnings)
                   : ext == ".ply" ? meshio::readPly(bytes, what)
                                   : meshio::readOff(bytes, what);
        } catch (const std::bad_alloc&) {
            // Memory grows with the geometry a file holds (a few times its size): still one line.
            throw Error(what + ": out of memory while reading " + std::to_string(bytes.size() >> 20) + " MB of geometry");
        }
        if (mesh.positions.empty())
            warnings.push_back(what + ": no vertices");
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
