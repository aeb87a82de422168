#include "project/CoarseOccluders.h"

#include <set>

#include "plugins/MeshSimplification.h"
#include "base/Error.h"
#include "visibility/InnerOccluder.h"

namespace sightline {

using nlohmann::json;

namespace {

constexpr const char* kKey = kCoarseOccludersKey;

/// A whole number in [low, high] as written (unsigned, signed or too large alike), else an error
/// naming `key`.
std::int64_t boundedInteger(const json& value, const std::string& key, std::int64_t low, std::int64_t high)
{
    const bool inRange = value.is_number_unsigned() ? value.get<std::uint64_t>() <= std::uint64_t(high) &&
                                                          value.get<std::uint64_t>() >= std::uint64_t(low)
                       : value.is_number_integer()  ? value.get<std::int64_t>() >= low && value.get<std::int64_t>() <= high
                                                    : false;
    if (!inRange)
        throw Error(std::string(kKey) + key + " must be a whole number in [" + std::to_string(low) + ", " +
                    std::to_string(high) + "], got " + value.dump());
    return value.get<std::int64_t>();
}

CoarseOccluder parseEntry(const json& object, std::size_t index)
{
    const std::string at = std::string("[").append(std::to_string(index)).append("]");   // "[" + s: GCC 12's -Wrestrict false alarm
    if (!object.is_object() || !object.contains("instance"))
        throw Error(std::string(kKey) + at + " must be an object with instance and kind");
    CoarseOccluder spec;
    spec.instance = std::size_t(boundedInteger(object.at("instance"), at + ".instance", 0, std::int64_t(1) << 40));
    const std::string kind = object.contains("kind") && object.at("kind").is_string() ? object.at("kind").get<std::string>() : "";
    if (kind == "closest")
        spec.kind = CoarseKind::Closest;
    else if (kind == "inner")
        spec.kind = CoarseKind::Inner;
    else
        throw Error(std::string(kKey) + at + ".kind must be \"closest\" or \"inner\"");
    if (object.contains("triangles"))
        spec.triangles = std::size_t(boundedInteger(object.at("triangles"), at + ".triangles", 4, 100'000'000));
    if (object.contains("resolution"))
        spec.resolution = int(boundedInteger(object.at("resolution"), at + ".resolution", 4, 256));
    spec.extra = object;
    for (const char* known : {"instance", "kind", "triangles", "resolution"})
        spec.extra.erase(known);
    return spec;
}

/// FNV-1a over the mesh's positions and indices: the cache's key for "the same mesh".
std::uint64_t contentHash(const Mesh& mesh)
{
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](const void* data, std::size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < bytes; ++i)
            h = (h ^ p[i]) * 1099511628211ull;
    };
    mix(mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
    mix(mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
    return h;
}

} // namespace

std::vector<CoarseOccluder> coarseOccluders(const Project& project)
{
    std::vector<CoarseOccluder> list;
    const auto it = project.extra.find(kKey);
    if (it == project.extra.end() || it->is_null())
        return list;
    if (!it->is_array())
        throw Error(project.name + ": '" + kKey + "' must be an array of {instance, kind}");
    std::set<std::size_t> seen;
    try {
        for (std::size_t i = 0; i < it->size(); ++i) {
            list.push_back(parseEntry((*it)[i], i));
            if (!seen.insert(list.back().instance).second)
                throw Error(std::string(kKey) + "[" + std::to_string(i) + "].instance " +
                            std::to_string(list.back().instance) + " is listed twice (one stand-in per object)");
        }
    } catch (const Error& e) {
        throw Error(project.name + ": " + e.what());
    }
    return list;
}

json coarseOccludersJson(const std::vector<CoarseOccluder>& list)
{
    json array = json::array();
    for (const CoarseOccluder& spec : list) {
        json entry = spec.extra;
        entry["instance"] = spec.instance;
        entry["kind"] = spec.kind == CoarseKind::Closest ? "closest" : "inner";
        if (spec.kind == CoarseKind::Closest)
            entry["triangles"] = spec.triangles;
        else
            entry["resolution"] = spec.resolution;
        array.push_back(std::move(entry));
    }
    return array;
}

std::string describeCoarse(const CoarseOccluder& spec)
{
    return spec.kind == CoarseKind::Closest ? "closest, " + std::to_string(spec.triangles) + " triangles"
                                            : "inner, " + std::to_string(spec.resolution) + " voxels";
}

Mesh coarseOccluderMesh(const Mesh& mesh, const CoarseOccluder& spec)
{
    if (spec.kind == CoarseKind::Closest) {
        if (mesh.triangleCount() <= spec.triangles)
            return mesh;
        Mesh coarse = simplifiedMesh(mesh, spec.triangles);
        coarse.name = mesh.name + " (coarse)";
        return coarse;
    }
    if (!closedAndOutward(mesh))
        throw Error("'" + mesh.name + "' is not closed and outward: an inner stand-in needs a closed mesh (use closest)");
    Mesh inner = innerOccluderMesh(mesh, spec.resolution);
    if (inner.triangleCount() == 0)
        throw Error("'" + mesh.name + "' is too thin for an inner stand-in at " + std::to_string(spec.resolution) +
                    " voxels (a larger resolution, or closest)");
    inner.name = mesh.name + " (inner)";
    return inner;
}

bool standInApplies(const Mesh& mesh, const CoarseOccluder& spec)
{
    return spec.kind == CoarseKind::Closest ? mesh.triangleCount() > spec.triangles
                                            : mesh.triangleCount() > 12 && closedAndOutward(mesh);
}

ReplacedMeshes replaceDenseMeshes(Scene& scene, const CoarseOccluder& spec)
{
    ReplacedMeshes count;
    for (Mesh& mesh : scene.meshes) {
        if (!standInApplies(mesh, spec)) {
            count.skipped += spec.kind == CoarseKind::Inner && mesh.triangleCount() > 12;
            continue;
        }
        mesh = spec.kind == CoarseKind::Closest ? simplifiedMesh(mesh, spec.triangles) : innerOccluderMesh(mesh, spec.resolution);
        ++count.replaced;
    }
    return count;
}

const Mesh& CoarseMeshCache::standIn(const Mesh& mesh, const CoarseOccluder& spec)
{
    const auto key = std::tuple{contentHash(mesh), int(spec.kind),
                                spec.kind == CoarseKind::Closest ? spec.triangles : std::size_t(spec.resolution)};
    auto it = meshes_.find(key);
    if (it == meshes_.end())
        it = meshes_.emplace(key, coarseOccluderMesh(mesh, spec)).first;
    return it->second;
}

void applyCoarseOccluders(const std::vector<CoarseOccluder>& list, Scene& level, CoarseMeshCache* cache)
{
    CoarseMeshCache local;
    CoarseMeshCache& standIns = cache ? *cache : local;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const CoarseOccluder& spec = list[i];
        const std::string key = std::string(kKey) + "[" + std::to_string(i) + "]";
        if (spec.instance >= level.instances.size())
            throw Error(key + ".instance " + std::to_string(spec.instance) + " does not exist (the scene has " +
                        std::to_string(level.instances.size()) + " objects)");
        const std::uint32_t original = level.instances[spec.instance].mesh;
        try {
            // A copy: addMesh may move the meshes, and the original stays for other instances.
            const Mesh standIn = standIns.standIn(level.meshes.at(original), spec);
            level.instances[spec.instance].mesh = level.addMesh(standIn);
        } catch (const Error& e) {
            throw Error(key + ": " + e.what());
        }
    }
}

Scene buildRayScene(const Project& project, std::vector<std::string>* warnings)
{
    ProjectMeshes meshes = loadProjectMeshes(project, warnings);
    applyCoarseOccluders(coarseOccluders(project), meshes.level);   // before the occluders join it
    return assembleScene(project, meshes);
}

} // namespace sightline
