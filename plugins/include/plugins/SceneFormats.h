#pragma once
// Scene importers and exporters behind one small registry keyed by file extension.
//
// Built-in formats register exactly like any later plugin would: glTF 2.0 (.gltf/.glb, tinygltf;
// import and export) and OBJ/PLY/OFF/STL (strict readers of our own, MeshFileImporter.cpp: import). Every importer returns a validated
// Scene (sightline::validate) or throws sightline::Error with one line naming the file and the
// problem. Non-fatal oddities (points/lines ignored, missing textures) go to `warnings`.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "visibility/Scene.h"

namespace sightline {

struct SceneLoadOptions {
    /// Decode the materials' colour textures into the albedos (Mesh::albedo: glTF's base colour
    /// textures, OBJ's map_Kd). Only indirect light reads albedos, and decoding a level's textures
    /// can cost seconds, so it is asked for; without it a textured material's albedo is unknown.
    bool textureAlbedos = false;
};

class SceneImporter {
public:
    virtual ~SceneImporter() = default;
    virtual std::string name() const = 0;                      ///< e.g. "glTF 2.0"
    virtual std::vector<std::string> extensions() const = 0;   ///< lower case, with dot: ".glb"
    virtual Scene load(const std::filesystem::path& file, std::vector<std::string>& warnings,
                       const SceneLoadOptions& options) const = 0;
};

class SceneExporter {
public:
    virtual ~SceneExporter() = default;
    virtual std::string name() const = 0;
    virtual std::vector<std::string> extensions() const = 0;
    /// Writes atomically (writeFileAtomically): a failed export never leaves a truncated file.
    virtual void save(const Scene& scene, const std::filesystem::path& file) const = 0;
};

class SceneFormatRegistry {
public:
    /// The registry with every built-in format.
    static const SceneFormatRegistry& builtin();

    void add(std::unique_ptr<SceneImporter> importer);
    void add(std::unique_ptr<SceneExporter> exporter);

    /// By the file's extension, case-insensitively; nullptr if none.
    const SceneImporter* importerFor(const std::filesystem::path& file) const;
    const SceneExporter* exporterFor(const std::filesystem::path& file) const;
    /// "*.gltf *.glb *.obj ..." for file dialogs and error messages.
    std::string importFilter() const;

private:
    std::vector<std::unique_ptr<SceneImporter>> importers_;
    std::vector<std::unique_ptr<SceneExporter>> exporters_;
};

/// Loads any supported scene file. Throws sightline::Error: missing file, unknown extension
/// (naming the supported ones), or the importer's own error.
Scene loadScene(const std::filesystem::path& file, std::vector<std::string>* warnings = nullptr,
                const SceneLoadOptions& options = {});

/// Saves a scene in the format its extension names (currently .gltf/.glb).
void saveScene(const Scene& scene, const std::filesystem::path& file);

} // namespace sightline
