#pragma once
// The project document (docs/design.md §3, a contract): the scene file, the two patches and the
// occluders the designer placed. Shared by the CLI and the editor.
//
// Unknown keys survive a load/save round trip at every level (the document, each patch, each
// occluder), so files written by newer tools or edited by hand keep what we do not understand.
// Errors name the file and the offending key: "level.json: source.samples must be two integers".

#include <array>
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline {

inline constexpr int kProjectVersion = 1;

/// An object the designer placed: a built-in mesh ("box": unit cube [-0.5, 0.5]^3; "plane": unit
/// square [-0.5, 0.5]^2 in XZ with normal +Y) or a mesh file, placed by a column-major transform.
struct OccluderSpec {
    std::string name;
    std::string mesh;
    glm::mat4 transform{1.0f};
    nlohmann::json extra = nlohmann::json::object();   ///< unknown keys, kept
};

struct Project {
    /// Folder that relative paths are resolved against (the project file's folder).
    std::filesystem::path folder;
    /// Names the project in errors (its file name as given).
    std::string name = "project";
    /// Lets relative paths leave `folder` (--allow-outside-paths; base/PathRule.h). Not saved:
    /// it is the user's choice for one run, not the file's.
    bool allowOutsidePaths = false;
    /// Read the level's and the occluders' colour textures into their albedos
    /// (SceneLoadOptions::textureAlbedos): what indirect light needs and nothing else does. Not
    /// saved: the run asks for it.
    bool textureAlbedos = false;
    /// Scene file as written in the project (relative or absolute); empty for none.
    std::string scene;
    Patch source;
    Patch receiver;
    std::vector<OccluderSpec> occluders;
    /// Objects of the scene file the designer moved: instance index -> world transform replacing
    /// the file's ("scene_transforms": [{"instance": 3, "transform": [16 numbers]}]).
    std::map<std::size_t, glm::mat4> sceneTransforms;
    /// Unknown keys of each scene_transforms entry, by instance, kept for saving.
    std::map<std::size_t, nlohmann::json> sceneTransformExtra;
    /// Every transform as the file wrote it, by the float32 matrix it reads as: saving writes an
    /// unedited matrix back exactly as read (1234567.891 stays, not the float's 1234567.875).
    std::map<std::array<float, 16>, nlohmann::json> transformsAsWritten;
    /// Unknown keys of the document and of each patch, kept for saving.
    nlohmann::json extra = nlohmann::json::object();
    nlohmann::json sourceExtra = nlohmann::json::object();
    nlohmann::json receiverExtra = nlohmann::json::object();

    /// The file a path written in the project means (scene, occluder mesh, light image, ...);
    /// `key` says where it was written ("scene"). A relative path that leaves `folder` throws
    /// sightline::Error unless allowOutsidePaths (base/PathRule.h). Every place a project
    /// names a file goes through here.
    std::filesystem::path resolve(const std::string& path, const std::string& key) const;
};

/// Parses a project document. `what` names it in errors (the file name). Patch geometry is read
/// as given; the pair is validated where it is sampled (validatePatchPair), so that an editor can
/// still open and fix a file whose patches are invalid.
Project parseProject(const nlohmann::json& document, const std::filesystem::path& folder, const std::string& what);
struct ProjectLoadOptions {
    bool allowOutsidePaths = false;   ///< see Project::allowOutsidePaths
    bool textureAlbedos = false;      ///< see Project::textureAlbedos
};
/// Reads and parses a project file (a regular file of bounded size, base/InputFile.h).
Project loadProject(const std::filesystem::path& file, const ProjectLoadOptions& options = {});

nlohmann::json toJson(const Project& project);
/// Atomic: a temporary file beside `file`, then a rename.
void saveProject(const Project& project, const std::filesystem::path& file);

/// The same project to be saved in `folder`: every path it names (scene, occluder meshes, the
/// light texture, receiver heights) rewritten to mean the same file from there; absolute when
/// `absolute`, or where the relative form would climb out of `folder` (PathRule.h refuses that).
Project rebasedProject(Project project, const std::filesystem::path& folder, bool absolute);

/// The built-in occluder meshes by name ("box", "plane"); throws sightline::Error for others.
Mesh builtinMesh(const std::string& name);
bool isBuiltinMesh(const std::string& name);

/// Replaces the transforms of the scene file's instances that the project moved. Throws
/// sightline::Error for an instance index the scene does not have.
void applySceneTransforms(const Project& project, Scene& sceneFile);

/// An occluder's mesh(es) in object space: a built-in mesh or the file's scene.
Scene loadOccluderMesh(const Project& project, const OccluderSpec& spec, std::vector<std::string>* warnings = nullptr);
/// Appends an occluder to `scene`, placed by its transform and named after it.
void appendOccluder(Scene& scene, const Scene& mesh, const OccluderSpec& spec);

/// The meshes a project refers to, loaded once: the scene file (its moved objects placed) and each
/// occluder's mesh in object space. An animation moves occluders every frame; reassembling from
/// these costs a copy instead of a file load.
struct ProjectMeshes {
    Scene level;
    std::vector<Scene> occluders;   ///< one per project.occluders entry
};
ProjectMeshes loadProjectMeshes(const Project& project, std::vector<std::string>* warnings = nullptr);
/// The level plus every occluder placed by `project`'s transforms (which may differ from those the
/// meshes were loaded with; the occluder list must have the same length). Throws sightline::Error.
Scene assembleScene(const Project& project, const ProjectMeshes& meshes);

/// The scene file plus every occluder, as one Scene ready for sampling. Throws sightline::Error.
Scene buildScene(const Project& project, std::vector<std::string>* warnings = nullptr);

} // namespace sightline
