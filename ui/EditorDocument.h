#pragma once
// The document the editor works on: a Project (docs/design.md §3) plus the scene it names, loaded
// once, the undo stack of every edit, the file it lives in and the current selection.
//
// Every edit goes through an undo command (EditCommands.h). Commands call the apply*() setters,
// which change the data and emit changed(); views never change the project directly. Selection is
// not undone (as in most editors).

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <QObject>
#include <QUndoStack>

#include "editor/ObjectEdits.h"
#include "editor/ObjectFlags.h"
#include "lighting/Light.h"
#include "project/CoarseOccluders.h"
#include "project/Project.h"
#include "project/SceneImport.h"

namespace sightline::ui {

/// What an edit touched; views redo only what depends on it.
enum Change : unsigned {
    PatchesChanged = 1u << 0,     ///< source or receiver (geometry or samples)
    OccludersChanged = 1u << 1,   ///< placed occluders added, removed or moved
    SceneFileChanged = 1u << 2,   ///< an object of the scene file moved
    DocumentReset = 1u << 3,      ///< new or opened document: everything
    NamesChanged = 1u << 4,       ///< an occluder renamed: nothing to sample or draw again
    ProjectKeysChanged = 1u << 5, ///< a top-level key ("recorded_path", "pvs" overrides): no geometry
    FlagsChanged = 1u << 6,       ///< hidden, locked or isolated: what is drawn and picked, no ray
    LightsChanged = 1u << 7,      ///< a light added, removed, moved or edited: the lit view, no ray
    CoarseOccludersChanged = 1u << 8, ///< a level object's coarse stand-in: rays only, nothing drawn
};

class EditorDocument : public QObject {
    Q_OBJECT
public:
    explicit EditorDocument(QObject* parent = nullptr);
    ~EditorDocument() override;

    const Project& project() const { return project_; }
    /// The scene file's objects (moved ones where the project says so).
    const Scene& sceneFile() const { return sceneFile_; }
    /// Only the placed occluders, in world space (instance i = occluder i when each is one mesh).
    const Scene& occluderScene() const;
    /// The scene file then the occluders (what buildScene gives): what is drawn, lit and baked.
    const Scene& scene() const;
    /// What the rays between the patches are tested against: scene() with the coarse stand-ins
    /// of the project's "coarse_occluders" (buildRayScene).
    const Scene& rayScene() const;
    /// Which occluder each instance of occluderScene() belongs to.
    const std::vector<std::size_t>& occluderOfInstance() const;
    /// The meshes as loaded (the scene file with its moved objects, each occluder's mesh in object
    /// space), for a ProjectSampler: what loadProjectMeshes would read from disk, without reading.
    ProjectMeshes projectMeshes() const;

    QUndoStack* undoStack() { return &undo_; }
    const std::filesystem::path& filePath() const { return file_; }
    bool isModified() const { return !undo_.isClean(); }
    QString displayName() const;

    /// An empty level with default patches (no file).
    void newDocument();
    /// A project (.json) or a mesh file (.glb, .gltf, .obj, .ply, .off, .stl: a new project on
    /// it, patches placed across the level). Throws sightline::Error; the document is unchanged
    /// then.
    void open(const std::filesystem::path& file);
    /// Whether files the project names may lie outside its folder by a relative path
    /// (base/PathRule.h): the editor's setting or --allow-outside-paths, applied to every
    /// document opened from now on and to the current one.
    void setAllowOutsidePaths(bool allow);
    bool allowOutsidePaths() const { return allowOutsidePaths_; }
    /// Saves atomically; relative paths are rewritten for the new folder (absolute where the
    /// relative form would leave it). Throws sightline::Error.
    void save(const std::filesystem::path& file);
    /// Writes the recovery copy (absolute paths), without touching the clean state.
    void saveRecovery(const std::filesystem::path& file) const;
    /// Editor-only settings stored in the project (e.g. the view), unknown to the CLI.
    void setEditorSettings(const nlohmann::json& settings);
    nlohmann::json editorSettings() const;

    // ---- edits (each pushes one undo command) ----
    ObjectState state(ObjectRef object) const;
    /// `before` is the state the command restores on undo (the state at the start of a drag).
    void editState(ObjectRef object, const ObjectState& before, const ObjectState& after, const QString& text);
    void setState(ObjectRef object, const ObjectState& after, const QString& text);
    /// Adds an occluder ("box", "plane" or a mesh file) and selects it.
    void addOccluder(const OccluderSpec& spec);
    void removeSelected();
    void duplicateSelected();
    /// Renames placed occluder `index` (the level's own objects keep the file's names).
    void renameOccluder(std::size_t index, const std::string& name);

    // ---- lights (the project's "lights"; a level whose glTF places lights and whose project
    // names none shows the file's lights, written into "lights" at the first edit) ----
    const std::vector<Light>& lights() const { return lights_; }
    /// The "lights" array as it would be saved.
    nlohmann::json lightsJson() const;
    /// The level's box (the scene file's), where a sun is drawn (LightObjects.h).
    const Bounds& levelBounds() const { return levelBounds_; }
    /// Adds a light (one entry of "lights") and selects it. Throws sightline::Error, naming the
    /// key, for a light that is not valid; the document is unchanged then.
    void addLight(const nlohmann::json& light);
    /// Replaces light `index` with `light`, one undoable step; throws like addLight.
    void editLight(std::size_t index, const nlohmann::json& light, const QString& text);

    // ---- coarse occluders (project/CoarseOccluders.h) ----
    std::vector<CoarseOccluder> coarseOccluders() const;
    /// The stand-in answering level object `instance`'s rays, or none (its full mesh): one
    /// undoable step. The stand-in is made first: sightline::Error where it does not apply (the
    /// document unchanged then).
    void setCoarseOccluder(std::size_t instance, const std::optional<CoarseOccluder>& spec);
    /// The stand-in's triangles for level object `instance` (made before, or now), for messages.
    std::size_t standInTriangles(std::size_t instance, const CoarseOccluder& spec) const;

    // ---- hide, isolate, lock (ObjectFlags.h says what each means) ----
    ObjectFlags flags(ObjectRef object) const;
    /// One undoable step (hidden and locked are kept in the project).
    void setFlags(ObjectRef object, ObjectFlags flags, const QString& text);
    /// Shows every hidden object (one undoable step) and ends isolation.
    void showAll();
    /// Isolation: only `object` (and the patches) drawn and picked; None ends it. View state:
    /// neither undone nor saved; a new document or a change of the occluder list ends it.
    void setIsolated(ObjectRef object);
    ObjectRef isolated() const { return isolated_; }
    /// Drawn: not hidden, and not isolated away.
    bool isShown(ObjectRef object) const;
    /// Picked by a click in the view: shown and not locked.
    bool isPickable(ObjectRef object) const { return isShown(object) && !flags(object).locked; }
    /// Per level instance (SceneObject) or placed occluder (Occluder), 1 where it is not shown.
    std::vector<std::uint8_t> hiddenMask(ObjectKind kind) const;

    // ---- applied by the undo commands only ----
    void applyState(ObjectRef object, const ObjectState& state);
    void insertOccluder(std::size_t index, const OccluderSpec& spec);
    void eraseOccluder(std::size_t index);
    void applyOccluderName(std::size_t index, const std::string& name);
    void applyFlags(ObjectRef object, ObjectFlags flags);
    const OccluderSpec& occluder(std::size_t index) const { return project_.occluders.at(index); }
    /// Sets (or, with a null value, removes) a top-level key of the project kept for other tools,
    /// such as "recorded_path" (RecordingControls.h). Changes nothing the views draw.
    void applyProjectKey(const std::string& key, const nlohmann::json& value);

    // ---- import settings (project/SceneImport.h) ----
    SceneImport sceneImportSettings() const;
    /// guessSceneUp of the level as its file has it (before the turn).
    std::string guessedFileUp() const;
    /// Turns and scales the level anew (undoable; one step). Patches, occluders and lights stay
    /// where they are in the world. Throws sightline::Error for an invalid setting.
    void setSceneImportSettings(const SceneImport& settings);
    /// What opening the current file decided for the user to know (the up axis guessed for a bare
    /// level), or empty.
    QString openNote() const { return openNote_; }

    // ---- selection ----
    ObjectRef selection() const { return selection_; }
    void select(ObjectRef object);
    QString objectName(ObjectRef object) const;

signals:
    void changed(unsigned changes);
    void selectionChanged(sightline::ui::ObjectRef selection);
    void fileChanged();
    void modifiedChanged(bool modified);

private:
    void reset(Project project, Scene sceneFile, std::filesystem::path file,
               std::map<std::string, Scene> occluderMeshes = {});
    const Scene& occluderMesh(const OccluderSpec& spec) const;
    void invalidate(unsigned changes);

    Project project_;
    Scene sceneFileOriginal_;   ///< as loaded and turned (SceneImport), before scene_transforms
    std::vector<glm::mat4> fileTransforms_;   ///< each instance's transform in the file, before the turn
    QString openNote_;
    /// Turns sceneFileOriginal_ by the project's settings from fileTransforms_, then the rest.
    void reimportLevel();
    Scene sceneFile_;
    std::filesystem::path file_;
    QUndoStack undo_;
    ObjectRef selection_;
    mutable std::map<std::string, Scene> occluderMeshes_;
    mutable std::optional<Scene> occluderScene_;
    mutable std::vector<std::size_t> occluderOfInstance_;
    mutable std::optional<Scene> scene_;
    mutable std::optional<Scene> rayScene_;
    mutable CoarseMeshCache coarseMeshes_;
    bool allowOutsidePaths_ = false;
    ObjectRef isolated_;
    std::vector<ObjectFlags> instanceFlags_;   ///< of the level's instances, read from the settings
    std::vector<Light> lights_;                ///< parsed from lightsJson(), validated
    nlohmann::json sceneFileLights_;           ///< the glTF's own lights, as "lights" entries
    Bounds levelBounds_;

    /// Pushes one undoable change of the whole "lights" array (validated first).
    void setLightsJson(const nlohmann::json& lights, const QString& text);
    void refreshLights();
    void refreshSceneFileLights();
};

/// Whether a path names a mesh file the editor opens as a scene.
bool isMeshFile(const std::filesystem::path& file);

/// The first free "<stem>-001.png", "<stem>-002.png", ... in `folder`: F12 never overwrites an
/// earlier image.
std::filesystem::path nextNumberedFile(const std::filesystem::path& folder, const std::string& stem,
                                       const std::string& extension = ".png");

} // namespace sightline::ui
