#include "EditorDocument.h"
#include "editor/DefaultPatches.h"

#include "editor/Picking.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "EditCommands.h"
#include "editor/LightObjects.h"
#include "plugins/SceneFormats.h"
#include "project/ProjectLights.h"
#include "project/SceneImport.h"
#include "base/AtomicFile.h"
#include "base/Error.h"

namespace sightline::ui {

namespace fs = std::filesystem;

namespace {

constexpr const char* kEditorKey = "editor";   // the project key the CLI ignores (kept as unknown)

} // namespace

fs::path nextNumberedFile(const fs::path& folder, const std::string& stem, const std::string& extension)
{
    for (int n = 1;; ++n) {
        char number[16];
        std::snprintf(number, sizeof number, "-%03d", n);
        const fs::path candidate = folder / (stem + number + extension);
        std::error_code ec;
        if (!fs::exists(fs::symlink_status(candidate, ec)))
            return candidate;
    }
}

bool isMeshFile(const fs::path& file) { return SceneFormatRegistry::builtin().importerFor(file) != nullptr; }

EditorDocument::EditorDocument(QObject* parent) : QObject(parent)
{
    connect(&undo_, &QUndoStack::cleanChanged, this, [this](bool clean) { emit modifiedChanged(!clean); });
    newDocument();
}

EditorDocument::~EditorDocument() = default;

QString EditorDocument::displayName() const
{
    return file_.empty() ? tr("Untitled") : QString::fromStdString(file_.filename().string());
}

void EditorDocument::reset(Project project, Scene sceneFile, fs::path file, std::map<std::string, Scene> occluderMeshes)
{
    undo_.clear();
    openNote_.clear();
    project_ = std::move(project);
    sceneFileOriginal_ = std::move(sceneFile);
    fileTransforms_.clear();
    const glm::mat4 unturn(glm::inverse(sceneImport(project_).transform()));
    for (const Instance& instance : sceneFileOriginal_.instances)
        fileTransforms_.push_back(unturn * instance.transform);
    sceneFile_ = sceneFileOriginal_;
    applySceneTransforms(project_, sceneFile_);
    occluderMeshes_ = std::move(occluderMeshes);
    file_ = std::move(file);
    selection_ = {};
    isolated_ = {};
    instanceFlags_.assign(sceneFile_.instances.size(), {});
    levelBounds_ = sceneFile_.bounds();
    refreshSceneFileLights();
    refreshLights();
    const nlohmann::json editor = editorSettings();
    for (std::size_t i = 0; i < instanceFlags_.size(); ++i)
        instanceFlags_[i] = settingsFlags(editor, {ObjectKind::SceneObject, i});
    invalidate(DocumentReset | PatchesChanged | OccludersChanged | SceneFileChanged);
    emit selectionChanged(selection_);
    emit fileChanged();
}

void EditorDocument::refreshSceneFileLights()
{
    sceneFileLights_ = nlohmann::json::array();
    if (!project_.extra.contains("lights") && !project_.scene.empty()) {
        // Checked by open(); a level without a glTF's lights has none.
        try {
            for (const Light& light : sceneFileLights(project_))
                sceneFileLights_.push_back(lightJson(light));
        } catch (const Error&) {
        }
    }
}

SceneImport EditorDocument::sceneImportSettings() const { return sceneImport(project_); }

std::string EditorDocument::guessedFileUp() const { return guessSceneUp(sceneFileOriginal_, fileTransforms_); }

void EditorDocument::setSceneImportSettings(const SceneImport& settings)
{
    Project check = project_;
    setSceneImport(check, settings);
    (void)sceneImport(check);   // throws, naming the key, before anything changes
    const auto value = [](const Project& p, const char* key) {
        const auto it = p.extra.find(key);
        return it != p.extra.end() ? *it : nlohmann::json();
    };
    undo_.beginMacro(tr("import settings"));
    for (const char* key : {kSceneUpKey, kSceneScaleKey})
        if (value(project_, key) != value(check, key))
            undo_.push(new SetProjectKeyCommand(*this, key, value(project_, key), value(check, key), tr("import settings")));
    undo_.endMacro();
}

void EditorDocument::reimportLevel()
{
    const glm::mat4 turn(sceneImport(project_).transform());
    for (std::size_t i = 0; i < sceneFileOriginal_.instances.size() && i < fileTransforms_.size(); ++i)
        sceneFileOriginal_.instances[i].transform = turn * fileTransforms_[i];
    sceneFile_ = sceneFileOriginal_;
    applySceneTransforms(project_, sceneFile_);
    levelBounds_ = sceneFile_.bounds();
    refreshSceneFileLights();
    refreshLights();
    invalidate(SceneFileChanged | LightsChanged);
}

void EditorDocument::setAllowOutsidePaths(bool allow)
{
    allowOutsidePaths_ = allow;
    project_.allowOutsidePaths = allow;
}

void EditorDocument::newDocument()
{
    Project project;
    project.folder = fs::current_path();
    project.allowOutsidePaths = allowOutsidePaths_;
    project.textureAlbedos = true;   // the lit view's bounce
    std::tie(project.source, project.receiver) = defaultPatches(Bounds{});
    reset(std::move(project), Scene{}, {});
}

void EditorDocument::open(const fs::path& file)
{
    if (isMeshFile(file)) {
        Scene scene = loadScene(file, nullptr, {.textureAlbedos = true});   // the lit view's bounce
        Project project;
        project.folder = fs::absolute(file).parent_path();
        project.scene = file.filename().string();
        project.allowOutsidePaths = allowOutsidePaths_;
        project.textureAlbedos = true;
        // A bare level says nothing of its up axis: guessed from its floors, used and said.
        const SceneImport guessed{guessSceneUp(scene), 1.0};
        applySceneImport(guessed, scene);
        setSceneImport(project, guessed);
        const QString note = guessed.up == "+y" ? QString()
                                                : tr("%1 looks %2-up (most of its floor-like area faces that way): turned so that "
                                                     "it stands upright; File > Import Settings changes it")
                                                      .arg(QString::fromStdString(file.filename().string()),
                                                           QString::fromStdString(guessed.up));
        std::tie(project.source, project.receiver) = defaultPatchesInOpenSpace(scene);
        reset(std::move(project), std::move(scene), {});
        openNote_ = note;
        return;
    }
    Project project = loadProject(file, {.allowOutsidePaths = allowOutsidePaths_, .textureAlbedos = true});   // the lit view's bounce
    Scene scene = loadLevel(project);   // turned and scaled by the project's import settings
    (void)lightsToUse(project);   // bad lights refuse the file as a whole, naming the key
    // Checks the occluders, moved objects and coarse stand-ins now, so a broken file is refused as
    // a whole; the occluder meshes loaded and the stand-ins made for the check are kept.
    Scene check = scene;
    applySceneTransforms(project, check);
    {
        Scene level = check;
        applyCoarseOccluders(sightline::coarseOccluders(project), level, &coarseMeshes_);
    }
    std::map<std::string, Scene> meshes;
    for (const OccluderSpec& spec : project.occluders) {
        auto it = meshes.find(spec.mesh);
        if (it == meshes.end())
            it = meshes.emplace(spec.mesh, loadOccluderMesh(project, spec)).first;
        appendOccluder(check, it->second, spec);
    }
    validate(check, file.filename().string());
    reset(std::move(project), std::move(scene), fs::absolute(file), std::move(meshes));
}

void EditorDocument::save(const fs::path& file)
{
    const fs::path target = fs::absolute(file);
    const Project project = rebasedProject(project_, target.parent_path(), false);
    saveProject(project, target);
    project_ = project;
    file_ = target;
    undo_.setClean();
    emit fileChanged();
}

void EditorDocument::saveRecovery(const fs::path& file) const
{
    saveProject(rebasedProject(project_, fs::absolute(file).parent_path(), true), file);
}

void EditorDocument::setEditorSettings(const nlohmann::json& settings) { project_.extra[kEditorKey] = settings; }

nlohmann::json EditorDocument::editorSettings() const
{
    const auto it = project_.extra.find(kEditorKey);
    return it == project_.extra.end() ? nlohmann::json::object() : *it;
}

ObjectState EditorDocument::state(ObjectRef object) const
{
    switch (object.kind) {
    case ObjectKind::Source: return project_.source;
    case ObjectKind::Receiver: return project_.receiver;
    case ObjectKind::Occluder: return project_.occluders.at(object.index).transform;
    case ObjectKind::SceneObject: return sceneFile_.instances.at(object.index).transform;
    case ObjectKind::Light: return lightTransform(lights_.at(object.index), levelBounds_);
    case ObjectKind::None: break;
    }
    throw Error("no object selected");
}

void EditorDocument::editState(ObjectRef object, const ObjectState& before, const ObjectState& after, const QString& text)
{
    undo_.push(new SetStateCommand(*this, object, before, after, text));
}

void EditorDocument::setState(ObjectRef object, const ObjectState& after, const QString& text)
{
    editState(object, state(object), after, text);
}

void EditorDocument::applyState(ObjectRef object, const ObjectState& state)
{
    switch (object.kind) {
    case ObjectKind::Source:
        project_.source = std::get<Patch>(state);
        invalidate(PatchesChanged);
        break;
    case ObjectKind::Receiver:
        project_.receiver = std::get<Patch>(state);
        invalidate(PatchesChanged);
        break;
    case ObjectKind::Occluder:
        project_.occluders.at(object.index).transform = std::get<glm::mat4>(state);
        invalidate(OccludersChanged);
        break;
    case ObjectKind::SceneObject:
        project_.sceneTransforms[object.index] = std::get<glm::mat4>(state);
        sceneFile_.instances.at(object.index).transform = std::get<glm::mat4>(state);
        invalidate(SceneFileChanged);
        break;
    case ObjectKind::Light: {
        nlohmann::json lights = lightsJson();
        lights.at(object.index) = placedLightJson(lights.at(object.index), lights_.at(object.index).type, std::get<glm::mat4>(state));
        try {
            lights_ = parseLights(lights, "lights");
        } catch (const Error&) {
            break;   // a place that would break the light (a flattened area light) is not taken
        }
        project_.extra["lights"] = std::move(lights);
        invalidate(LightsChanged);
        break;
    }
    case ObjectKind::None: break;
    }
}

void EditorDocument::applyProjectKey(const std::string& key, const nlohmann::json& value)
{
    if (value.is_null())
        project_.extra.erase(key);
    else
        project_.extra[key] = value;
    if (key == kSceneUpKey || key == kSceneScaleKey) {
        reimportLevel();
        return;
    }
    if (key == kCoarseOccludersKey) {
        invalidate(CoarseOccludersChanged);
        return;
    }
    if (key == "lights") {
        refreshLights();
        if (selection_.kind == ObjectKind::Light && selection_.index >= lights_.size())
            select({});   // undone or deleted: nothing left to show in the panel or the gizmo
        invalidate(LightsChanged);
        return;
    }
    invalidate(ProjectKeysChanged);
}

nlohmann::json EditorDocument::lightsJson() const
{
    const auto it = project_.extra.find("lights");
    return it != project_.extra.end() ? *it : sceneFileLights_;
}

void EditorDocument::refreshLights()
{
    try {
        lights_ = parseLights(lightsJson(), displayName().toStdString());
    } catch (const Error&) {
        lights_.clear();   // open() and every edit check first: only a hand-made document gets here
    }
}

void EditorDocument::setLightsJson(const nlohmann::json& lights, const QString& text)
{
    (void)parseLights(lights, "lights");   // throws, naming the key, before anything changes
    const auto it = project_.extra.find("lights");
    undo_.push(new SetProjectKeyCommand(*this, "lights", it != project_.extra.end() ? *it : nlohmann::json(), lights, text));
}

void EditorDocument::addLight(const nlohmann::json& light)
{
    nlohmann::json lights = lightsJson();
    lights.push_back(light);
    const std::string name = light.contains("name") && light["name"].is_string() ? light["name"].get<std::string>() : "light";
    setLightsJson(lights, tr("Add %1").arg(QString::fromStdString(name)));
    select({ObjectKind::Light, lights_.size() - 1});
}

void EditorDocument::editLight(std::size_t index, const nlohmann::json& light, const QString& text)
{
    nlohmann::json lights = lightsJson();
    if (index >= lights.size() || lights[index] == light)
        return;
    lights[index] = light;
    setLightsJson(lights, text);
}

void EditorDocument::addOccluder(const OccluderSpec& spec)
{
    occluderMesh(spec);   // throws here, before the command, for a mesh file that does not load
    undo_.push(new OccluderListCommand(*this, project_.occluders.size(), spec, false,
                                       tr("Add %1").arg(QString::fromStdString(spec.name))));
}

void EditorDocument::removeSelected()
{
    if (selection_.kind == ObjectKind::Light) {
        nlohmann::json lights = lightsJson();
        const QString name = objectName(selection_);
        lights.erase(lights.begin() + std::ptrdiff_t(selection_.index));
        select({});
        setLightsJson(lights, tr("Delete %1").arg(name));
        return;
    }
    if (selection_.kind != ObjectKind::Occluder)
        return;
    const std::size_t index = selection_.index;
    undo_.push(new OccluderListCommand(*this, index, project_.occluders.at(index), true,
                                       tr("Delete %1").arg(objectName(selection_))));
}

void EditorDocument::duplicateSelected()
{
    if (selection_.kind == ObjectKind::Light) {
        const Light& light = lights_.at(selection_.index);
        nlohmann::json copy = lightsJson().at(selection_.index);
        copy["name"] = sightline::displayName(lights_, selection_.index) + " copy";
        // Beside the original: half a metre along its transform's first axis.
        glm::mat4 t = lightTransform(light, levelBounds_);
        t[3] += 0.5f * glm::vec4(glm::normalize(glm::vec3(t[0])), 0.0f);
        addLight(placedLightJson(copy, light.type, t));
        return;
    }
    if (selection_.kind != ObjectKind::Occluder)
        return;
    OccluderSpec copy = project_.occluders.at(selection_.index);
    copy.name += " copy";
    setOccluderFlags(copy, {});   // a copy starts shown and free to move
    // Offset by half the object's first axis, so the copy is visible beside the original.
    copy.transform[3] += 0.5f * copy.transform[0];
    addOccluder(copy);
}

void EditorDocument::insertOccluder(std::size_t index, const OccluderSpec& spec)
{
    project_.occluders.insert(project_.occluders.begin() + std::ptrdiff_t(std::min(index, project_.occluders.size())), spec);
    unsigned changes = OccludersChanged;
    if (isolated_.kind == ObjectKind::Occluder) {   // its index may now name another occluder
        isolated_ = {};
        changes |= FlagsChanged;
    }
    invalidate(changes);
}

void EditorDocument::renameOccluder(std::size_t index, const std::string& name)
{
    const std::string before = project_.occluders.at(index).name;
    if (before != name)
        undo_.push(new RenameOccluderCommand(*this, index, before, name));
}

void EditorDocument::applyOccluderName(std::size_t index, const std::string& name)
{
    project_.occluders.at(index).name = name;
    invalidate(NamesChanged);
}

void EditorDocument::eraseOccluder(std::size_t index)
{
    project_.occluders.erase(project_.occluders.begin() + std::ptrdiff_t(index));
    unsigned changes = OccludersChanged;
    if (isolated_.kind == ObjectKind::Occluder) {   // its index may now name another occluder
        isolated_ = {};
        changes |= FlagsChanged;
    }
    invalidate(changes);
}

ObjectFlags EditorDocument::flags(ObjectRef object) const
{
    switch (object.kind) {
    case ObjectKind::Occluder: return object.index < project_.occluders.size() ? occluderFlags(project_.occluders[object.index]) : ObjectFlags{};
    case ObjectKind::SceneObject: return object.index < instanceFlags_.size() ? instanceFlags_[object.index] : ObjectFlags{};
    case ObjectKind::Source:
    case ObjectKind::Receiver: return settingsFlags(editorSettings(), object);
    case ObjectKind::Light:   // lights are neither hidden nor locked: the lit view shows them all
    case ObjectKind::None: break;
    }
    return {};
}

void EditorDocument::setFlags(ObjectRef object, ObjectFlags after, const QString& text)
{
    const ObjectFlags before = flags(object);
    if (object && object.kind != ObjectKind::Light && before != after)
        undo_.push(new SetFlagsCommand(*this, object, before, after, text));
}

void EditorDocument::applyFlags(ObjectRef object, ObjectFlags flags)
{
    if (object.kind == ObjectKind::Occluder) {
        setOccluderFlags(project_.occluders.at(object.index), flags);
    } else {
        nlohmann::json editor = editorSettings();
        setSettingsFlags(editor, object, flags);
        setEditorSettings(editor);
        if (object.kind == ObjectKind::SceneObject)
            instanceFlags_.at(object.index) = flags;
    }
    invalidate(FlagsChanged);
}

void EditorDocument::showAll()
{
    std::vector<ObjectRef> hidden;
    for (ObjectKind kind : {ObjectKind::Source, ObjectKind::Receiver})
        if (flags({kind, 0}).hidden)
            hidden.push_back({kind, 0});
    for (std::size_t i = 0; i < project_.occluders.size(); ++i)
        if (flags({ObjectKind::Occluder, i}).hidden)
            hidden.push_back({ObjectKind::Occluder, i});
    for (std::size_t i = 0; i < instanceFlags_.size(); ++i)
        if (instanceFlags_[i].hidden)
            hidden.push_back({ObjectKind::SceneObject, i});
    setIsolated({});
    if (hidden.empty())
        return;
    undo_.beginMacro(tr("Show all"));
    for (ObjectRef object : hidden) {
        ObjectFlags shown = flags(object);
        shown.hidden = false;
        undo_.push(new SetFlagsCommand(*this, object, flags(object), shown, {}));
    }
    undo_.endMacro();
}

void EditorDocument::setIsolated(ObjectRef object)
{
    if (object == isolated_)
        return;
    isolated_ = object;
    invalidate(FlagsChanged);
}

bool EditorDocument::isShown(ObjectRef object) const
{
    if (flags(object).hidden)
        return false;
    return !isolated_ || object == isolated_ || object.isPatch();
}

std::vector<std::uint8_t> EditorDocument::hiddenMask(ObjectKind kind) const
{
    const std::size_t count = kind == ObjectKind::SceneObject ? sceneFile_.instances.size()
                              : kind == ObjectKind::Occluder  ? project_.occluders.size()
                                                              : 0;
    std::vector<std::uint8_t> mask(count);
    for (std::size_t i = 0; i < count; ++i)
        mask[i] = isShown({kind, i}) ? 0 : 1;
    return mask;
}

void EditorDocument::select(ObjectRef object)
{
    if (object == selection_)
        return;
    selection_ = object;
    emit selectionChanged(selection_);
}

QString EditorDocument::objectName(ObjectRef object) const
{
    switch (object.kind) {
    case ObjectKind::Source: return tr("Source patch");
    case ObjectKind::Receiver: return tr("Receiver patch");
    case ObjectKind::Occluder: {
        const OccluderSpec& spec = project_.occluders.at(object.index);
        return QString::fromStdString(spec.name.empty() ? spec.mesh : spec.name);
    }
    case ObjectKind::SceneObject: {
        const Instance& instance = sceneFile_.instances.at(object.index);
        return instance.name.empty() ? tr("Object %1").arg(object.index) : QString::fromStdString(instance.name);
    }
    case ObjectKind::Light:
        return object.index < lights_.size() ? QString::fromStdString(sightline::displayName(lights_, object.index)) : QString();
    case ObjectKind::None: break;
    }
    return {};
}

const Scene& EditorDocument::occluderMesh(const OccluderSpec& spec) const
{
    auto it = occluderMeshes_.find(spec.mesh);
    if (it == occluderMeshes_.end())
        it = occluderMeshes_.emplace(spec.mesh, loadOccluderMesh(project_, spec)).first;
    return it->second;
}

const Scene& EditorDocument::occluderScene() const
{
    if (!occluderScene_) {
        Scene scene;
        occluderOfInstance_.clear();
        for (std::size_t i = 0; i < project_.occluders.size(); ++i) {
            const std::size_t before = scene.instances.size();
            appendOccluder(scene, occluderMesh(project_.occluders[i]), project_.occluders[i]);
            occluderOfInstance_.insert(occluderOfInstance_.end(), scene.instances.size() - before, i);
        }
        occluderScene_ = std::move(scene);
    }
    return *occluderScene_;
}

const std::vector<std::size_t>& EditorDocument::occluderOfInstance() const
{
    occluderScene();
    return occluderOfInstance_;
}

ProjectMeshes EditorDocument::projectMeshes() const
{
    ProjectMeshes meshes;
    meshes.level = sceneFile_;
    for (const OccluderSpec& spec : project_.occluders)
        meshes.occluders.push_back(occluderMesh(spec));
    return meshes;
}

const Scene& EditorDocument::scene() const
{
    if (!scene_) {
        Scene scene = sceneFile_;
        scene.append(occluderScene());
        scene_ = std::move(scene);
    }
    return *scene_;
}

const Scene& EditorDocument::rayScene() const
{
    const std::vector<CoarseOccluder> standIns = coarseOccluders();
    if (standIns.empty())
        return scene();
    if (!rayScene_) {
        Scene scene = sceneFile_;
        applyCoarseOccluders(standIns, scene, &coarseMeshes_);   // checked at open and at each edit
        scene.append(occluderScene());
        rayScene_ = std::move(scene);
    }
    return *rayScene_;
}

std::vector<CoarseOccluder> EditorDocument::coarseOccluders() const { return sightline::coarseOccluders(project_); }

std::size_t EditorDocument::standInTriangles(std::size_t instance, const CoarseOccluder& spec) const
{
    const Instance& object = sceneFile_.instances.at(instance);
    return coarseMeshes_.standIn(sceneFile_.meshes.at(object.mesh), spec).triangleCount();
}

void EditorDocument::setCoarseOccluder(std::size_t instance, const std::optional<CoarseOccluder>& spec)
{
    if (instance >= sceneFile_.instances.size())
        throw Error("no level object " + std::to_string(instance) + " (the level has " +
                    std::to_string(sceneFile_.instances.size()) + " objects)");
    std::vector<CoarseOccluder> list = coarseOccluders();
    std::erase_if(list, [&](const CoarseOccluder& c) { return c.instance == instance; });
    if (spec) {
        CoarseOccluder entry = *spec;
        entry.instance = instance;
        try {
            (void)standInTriangles(instance, entry);   // made now: refused before anything changes
        } catch (const Error& e) {
            throw Error(objectName({ObjectKind::SceneObject, instance}).toStdString() + ": " + e.what());
        }
        list.push_back(std::move(entry));
        std::sort(list.begin(), list.end(), [](const CoarseOccluder& a, const CoarseOccluder& b) { return a.instance < b.instance; });
    }
    const auto it = project_.extra.find(kCoarseOccludersKey);
    const nlohmann::json before = it != project_.extra.end() ? *it : nlohmann::json();
    const nlohmann::json after = list.empty() ? nlohmann::json() : coarseOccludersJson(list);
    if (before == after)
        return;
    const QString name = objectName({ObjectKind::SceneObject, instance});
    undo_.push(new SetProjectKeyCommand(*this, kCoarseOccludersKey, before, after,
                                        spec ? tr("Coarse occluder for %1").arg(name) : tr("Full mesh for %1").arg(name)));
}

void EditorDocument::invalidate(unsigned changes)
{
    if (changes & (OccludersChanged | SceneFileChanged | DocumentReset | CoarseOccludersChanged))
        rayScene_.reset();
    if (changes & (OccludersChanged | DocumentReset))
        occluderScene_.reset();
    if (changes & (OccludersChanged | SceneFileChanged | DocumentReset))
        scene_.reset();
    emit changed(changes);
}

} // namespace sightline::ui
