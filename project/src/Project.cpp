#include "project/Project.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <sstream>

#include "plugins/JsonText.h"
#include "plugins/SceneFormats.h"
#include "project/CoarseOccluders.h"
#include "project/SceneImport.h"
#include "base/AtomicFile.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "base/PathRule.h"

namespace sightline {

using nlohmann::json;

namespace {

/// Reading helpers: each throws sightline::Error("<what>: <key> <problem>").
struct Reader {
    const std::string& what;
    std::map<std::array<float, 16>, json>* transformsAsWritten = nullptr;   ///< filled as read

    [[noreturn]] void fail(const std::string& key, const std::string& problem) const
    {
        throw Error(what + ": '" + key + "' " + problem);
    }

    double number(const json& value, const std::string& key) const
    {
        if (!value.is_number())
            fail(key, "must be a number");
        const double x = value.get<double>();
        if (!std::isfinite(x))
            fail(key, "must be finite");
        return x;
    }

    glm::dvec3 vec3(const json& object, const std::string& key, const std::string& path) const
    {
        if (!object.contains(key))
            fail(path + key, "is missing");
        const json& value = object.at(key);
        if (!value.is_array() || value.size() != 3)
            fail(path + key, "must be an array of 3 numbers");
        return {number(value[0], path + key + "[0]"), number(value[1], path + key + "[1]"),
                number(value[2], path + key + "[2]")};
    }

    Patch patch(const json& document, const std::string& key, json& extra) const
    {
        if (!document.contains(key))
            fail(key, "is missing");
        const json& object = document.at(key);
        if (!object.is_object())
            fail(key, "must be an object with corner, u, v (and samples)");
        Patch p;
        p.corner = vec3(object, "corner", key + ".");
        p.u = vec3(object, "u", key + ".");
        p.v = vec3(object, "v", key + ".");
        if (object.contains("samples")) {
            const json& s = object.at("samples");
            if (!s.is_array() || s.size() != 2 || !s[0].is_number_integer() || !s[1].is_number_integer())
                fail(key + ".samples", "must be two integers [na, nb]");
            const long long limit = key == "source" ? kMaxSourceSamples : kMaxReceiverSide;
            // Range-check in the JSON's own type: a count above 2^63 is unsigned there and would
            // wrap negative as long long. The message quotes the numbers as written.
            auto inRange = [&](const json& n) {
                return n.is_number_unsigned() ? n.get<std::uint64_t>() <= std::uint64_t(limit) &&
                                                    n.get<std::uint64_t>() >= 1
                                              : n.get<long long>() >= 1 && n.get<long long>() <= limit;
            };
            if (!inRange(s[0]) || !inRange(s[1]))
                fail(key + ".samples", "must be in [1, " + std::to_string(limit) + "], got [" + s[0].dump() + ", " +
                                           s[1].dump() + "]");
            const auto na = s[0].get<long long>(), nb = s[1].get<long long>();
            p.na = int(na);
            p.nb = int(nb);
        }
        extra = object;
        for (const char* known : {"corner", "u", "v", "samples"})
            extra.erase(known);
        return p;
    }

    OccluderSpec occluder(const json& object, std::size_t index) const
    {
        const std::string key = "occluders[" + std::to_string(index) + "]";
        if (!object.is_object())
            fail(key, "must be an object with mesh and transform");
        OccluderSpec spec;
        if (object.contains("name")) {
            if (!object.at("name").is_string())
                fail(key + ".name", "must be a string");
            spec.name = object.at("name").get<std::string>();
        }
        if (!object.contains("mesh") || !object.at("mesh").is_string() || object.at("mesh").get<std::string>().empty())
            fail(key + ".mesh", "must be \"box\", \"plane\" or a mesh file path");
        spec.mesh = object.at("mesh").get<std::string>();
        if (object.contains("transform"))
            spec.transform = transform(object.at("transform"), key + ".transform");
        spec.extra = object;
        for (const char* known : {"name", "mesh", "transform"})
            spec.extra.erase(known);
        return spec;
    }

    glm::mat4 transform(const json& t, const std::string& key) const
    {
        if (!t.is_array() || t.size() != 16)
            fail(key, "must be 16 numbers (column-major 4x4)");
        glm::mat4 m(1.0f);
        std::array<float, 16> values{};
        for (int i = 0; i < 16; ++i)
            m[i / 4][i % 4] = values[std::size_t(i)] = float(number(t[std::size_t(i)], key));
        // Points are transformed with w = 1 and the result's w ignored: a projective last row
        // would be dropped without a word, placing another shape than the file says.
        if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
            fail(key, "must be affine: elements 3, 7, 11 and 15 (its last row) must be 0, 0, 0, 1");
        if (transformsAsWritten)
            transformsAsWritten->emplace(values, t);
        return m;
    }

    std::map<std::size_t, glm::mat4> sceneTransforms(const json& list, std::map<std::size_t, json>& extra) const
    {
        if (!list.is_array())
            fail("scene_transforms", "must be an array of {instance, transform}");
        std::map<std::size_t, glm::mat4> result;
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string key = "scene_transforms[" + std::to_string(i) + "]";
            const json& object = list[i];
            if (!object.is_object() || !object.contains("instance") || !object.at("instance").is_number_integer() ||
                object.at("instance").get<std::int64_t>() < 0)   // built in code, 0 is a signed integer
                fail(key + ".instance", "must be a non-negative integer");
            if (!object.contains("transform"))
                fail(key + ".transform", "is missing");
            const auto instance = object.at("instance").get<std::size_t>();
            result[instance] = transform(object.at("transform"), key + ".transform");
            json unknown = object;
            unknown.erase("instance");
            unknown.erase("transform");
            if (!unknown.empty())
                extra[instance] = std::move(unknown);
        }
        return result;
    }
};

json vec3Json(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

/// A float as the shortest decimal that reads back as it (0.1f as 0.1, not 0.10000000149).
double shortestDecimal(float x)
{
    // Both ways locale-independent: the editor runs under the user's LC_NUMERIC, where strtod
    // would read "1.25" as 1 in a comma-decimal locale.
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, x).ptr;
    double value = 0.0;
    std::from_chars(text, end, value);
    return value;
}

/// A transform as the file wrote it where it is unedited, else its floats as shortest decimals.
json matrixJson(const glm::mat4& m, const std::map<std::array<float, 16>, json>& asWritten)
{
    std::array<float, 16> values{};
    for (int i = 0; i < 16; ++i)
        values[std::size_t(i)] = m[i / 4][i % 4];
    if (const auto found = asWritten.find(values); found != asWritten.end())
        return found->second;
    json t = json::array();
    for (const float x : values)
        t.push_back(shortestDecimal(x));
    return t;
}

json patchJson(const Patch& p, const json& extra)
{
    json object = extra;
    object["corner"] = vec3Json(p.corner);
    object["u"] = vec3Json(p.u);
    object["v"] = vec3Json(p.v);
    object["samples"] = json::array({p.na, p.nb});
    return object;
}

Mesh makeMesh(std::string name, std::vector<glm::vec3> positions, std::vector<std::uint32_t> indices, bool watertight)
{
    Mesh mesh;
    mesh.name = std::move(name);
    mesh.positions = std::move(positions);
    mesh.indices = std::move(indices);
    mesh.watertight = watertight;
    return mesh;
}

} // namespace

std::filesystem::path Project::resolve(const std::string& path, const std::string& key) const
{
    return resolveWrittenPath(path, folder, allowOutsidePaths, name, key);
}

Project parseProject(const json& document, const std::filesystem::path& folder, const std::string& what)
{
    if (!document.is_object())
        throw Error(what + ": a project must be a JSON object");
    Project project;
    const Reader read{what, &project.transformsAsWritten};
    project.folder = folder;
    project.name = what;
    if (!document.contains("version"))
        read.fail("version", "is missing (this file is not a Sightline project)");
    if (!document.at("version").is_number_integer())
        read.fail("version", "must be an integer");
    const auto version = document.at("version").get<long long>();
    if (version > kProjectVersion)
        read.fail("version", "is " + std::to_string(version) + "; this Sightline reads up to " +
                                 std::to_string(kProjectVersion) + " (update Sightline)");
    if (version < 1)
        read.fail("version", "must be at least 1");

    if (document.contains("scene") && !document.at("scene").is_null()) {
        if (!document.at("scene").is_string())
            read.fail("scene", "must be a file path");
        project.scene = document.at("scene").get<std::string>();
    }
    project.source = read.patch(document, "source", project.sourceExtra);
    project.receiver = read.patch(document, "receiver", project.receiverExtra);
    if (document.contains("occluders")) {
        const json& list = document.at("occluders");
        if (!list.is_array())
            read.fail("occluders", "must be an array");
        for (std::size_t i = 0; i < list.size(); ++i)
            project.occluders.push_back(read.occluder(list[i], i));
    }
    if (document.contains("scene_transforms"))
        project.sceneTransforms = read.sceneTransforms(document.at("scene_transforms"), project.sceneTransformExtra);
    project.extra = document;
    for (const char* known : {"version", "scene", "source", "receiver", "occluders", "scene_transforms"})
        project.extra.erase(known);
    (void)sceneImport(project);        // "scene_up" and "scene_scale" (kept in extra) checked now
    (void)coarseOccluders(project);    // and "coarse_occluders"
    return project;
}

Project loadProject(const std::filesystem::path& file, const ProjectLoadOptions& options)
{
    // A FIFO would block forever, a folder fail deep in the stream library: checked first; then
    // depth-checked before parsing, and every parser failure one line naming the file (JsonText.h).
    const std::string text = readInputFile(file, "project");
    const json document = parseJsonText(text, file.string());
    const std::filesystem::path folder = std::filesystem::absolute(file).parent_path();
    Project project = parseProject(document, folder, file.string());
    project.allowOutsidePaths = options.allowOutsidePaths;
    project.textureAlbedos = options.textureAlbedos;
    return project;
}

json toJson(const Project& project)
{
    json document = project.extra;
    document["version"] = kProjectVersion;
    if (!project.scene.empty())
        document["scene"] = project.scene;
    document["source"] = patchJson(project.source, project.sourceExtra);
    document["receiver"] = patchJson(project.receiver, project.receiverExtra);
    json occluders = json::array();
    for (const OccluderSpec& spec : project.occluders) {
        json object = spec.extra;
        object["name"] = spec.name;
        object["mesh"] = spec.mesh;
        object["transform"] = matrixJson(spec.transform, project.transformsAsWritten);
        occluders.push_back(std::move(object));
    }
    document["occluders"] = std::move(occluders);
    if (!project.sceneTransforms.empty()) {
        json moved = json::array();
        for (const auto& [instance, transform] : project.sceneTransforms) {
            const auto extra = project.sceneTransformExtra.find(instance);
            json entry = extra != project.sceneTransformExtra.end() ? extra->second : json::object();
            entry["instance"] = instance;
            entry["transform"] = matrixJson(transform, project.transformsAsWritten);
            moved.push_back(std::move(entry));
        }
        document["scene_transforms"] = std::move(moved);
    }
    return document;
}

void saveProject(const Project& project, const std::filesystem::path& file)
{
    std::string text;
    try {
        text = toJson(project).dump(2) + "\n";
    } catch (const json::type_error&) {
        // A path or name that is not UTF-8 cannot be stored in the JSON the contract asks for;
        // refuse the save rather than write a file that reads back differently.
        throw Error(file.string() + ": cannot save: a path or name in the project is not valid UTF-8");
    }
    writeFileAtomically(file, text);
}

bool isBuiltinMesh(const std::string& name) { return name == "box" || name == "plane"; }

Mesh builtinMesh(const std::string& name)
{
    if (name == "box") {
        std::vector<glm::vec3> p;
        for (int i = 0; i < 8; ++i)
            p.emplace_back((i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f);
        // Outward, counter-clockwise seen from outside (right-handed).
        return makeMesh("box", std::move(p),
                        {0, 2, 3, 0, 3, 1,  4, 5, 7, 4, 7, 6,  0, 1, 5, 0, 5, 4,
                         2, 6, 7, 2, 7, 3,  0, 4, 6, 0, 6, 2,  1, 3, 7, 1, 7, 5},
                        true);
    }
    if (name == "plane")
        return makeMesh("plane", {{-0.5f, 0, -0.5f}, {0.5f, 0, -0.5f}, {0.5f, 0, 0.5f}, {-0.5f, 0, 0.5f}},
                        {0, 2, 1, 0, 3, 2}, false);
    throw Error("unknown built-in mesh '" + name + "' (built-ins: box, plane)");
}

void applySceneTransforms(const Project& project, Scene& sceneFile)
{
    for (const auto& [instance, transform] : project.sceneTransforms) {
        if (instance >= sceneFile.instances.size())
            throw Error("scene_transforms: instance " + std::to_string(instance) + " does not exist (the scene has " +
                        std::to_string(sceneFile.instances.size()) + " objects)");
        sceneFile.instances[instance].transform = transform;
    }
}

namespace {
/// Where an occluder's mesh path was written, for errors.
std::string occluderKey(const OccluderSpec& spec)
{
    return spec.name.empty() ? std::string("occluder mesh") : "occluder '" + spec.name + "' mesh";
}
} // namespace

Scene loadOccluderMesh(const Project& project, const OccluderSpec& spec, std::vector<std::string>* warnings)
{
    Scene mesh;
    if (isBuiltinMesh(spec.mesh))
        mesh.addMeshInstance(builtinMesh(spec.mesh));
    else
        mesh = loadScene(project.resolve(spec.mesh, occluderKey(spec)), warnings, {.textureAlbedos = project.textureAlbedos});
    return mesh;
}

void appendOccluder(Scene& scene, const Scene& mesh, const OccluderSpec& spec)
{
    Scene part = mesh;
    for (Instance& instance : part.instances) {
        instance.transform = spec.transform * instance.transform;
        if (!spec.name.empty())
            instance.name = spec.name;
    }
    scene.append(part);
}

ProjectMeshes loadProjectMeshes(const Project& project, std::vector<std::string>* warnings)
{
    ProjectMeshes meshes;
    meshes.level = loadLevel(project, warnings);   // turned and scaled first (SceneImport.h)
    applySceneTransforms(project, meshes.level);
    for (const OccluderSpec& spec : project.occluders)
        meshes.occluders.push_back(loadOccluderMesh(project, spec, warnings));
    return meshes;
}

Scene assembleScene(const Project& project, const ProjectMeshes& meshes)
{
    if (meshes.occluders.size() != project.occluders.size())
        throw Error("assembleScene: the project's occluders changed since their meshes were loaded");
    Scene scene = meshes.level;
    for (std::size_t k = 0; k < project.occluders.size(); ++k)
        appendOccluder(scene, meshes.occluders[k], project.occluders[k]);
    validate(scene, project.scene.empty() ? "project" : project.scene);
    return scene;
}

Scene buildScene(const Project& project, std::vector<std::string>* warnings)
{
    return assembleScene(project, loadProjectMeshes(project, warnings));
}

namespace {

/// Rewrites a path written relative to `from` so that it means the same file from `to`
/// (absolute when `absolute`, or when the relative form would climb out of `to`: such a path is
/// refused on load, base/PathRule.h, while an absolute one is taken as written).
std::string rebase(const std::string& path, const std::filesystem::path& from, const std::filesystem::path& to, bool absolute)
{
    if (path.empty())
        return path;
    std::error_code ec;
    if (!absolute && std::filesystem::equivalent(from, to, ec))
        return path;   // saved in place: what the user wrote stays as written
    const std::filesystem::path p(path);
    const std::filesystem::path full = p.is_absolute() ? p : (from / p).lexically_normal();
    if (absolute)
        return full.string();
    const std::filesystem::path relative = full.lexically_relative(to);
    const bool leaves = !relative.empty() && *relative.begin() == "..";
    return relative.empty() || leaves ? full.string() : relative.generic_string();
}

} // namespace

Project rebasedProject(Project project, const std::filesystem::path& folder, bool absolute)
{
    project.scene = rebase(project.scene, project.folder, folder, absolute);
    for (OccluderSpec& spec : project.occluders)
        if (!isBuiltinMesh(spec.mesh))
            spec.mesh = rebase(spec.mesh, project.folder, folder, absolute);
    // Paths in the lighting keys the editor keeps as unknown (project/LightingSetup.h).
    auto rebaseKey = [&](const char* object, const char* key) {
        const auto it = project.extra.find(object);
        if (it != project.extra.end() && it->is_object() && it->contains(key) && it->at(key).is_string())
            (*it)[key] = rebase(it->at(key).get<std::string>(), project.folder, folder, absolute);
    };
    rebaseKey("light", "texture");
    rebaseKey("receiver_heights", "image");
    rebaseKey("receiver_heights", "npy");
    project.folder = folder;
    return project;
}

} // namespace sightline
