#include "visibility/Scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <tuple>

#include <glm/common.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "base/Error.h"
#include "visibility/ExactSegment.h"

namespace sightline {

void Bounds::extend(const glm::vec3& p)
{
    min = glm::min(min, p);
    max = glm::max(max, p);
}

void Bounds::extend(const Bounds& b)
{
    if (b.empty())
        return;
    extend(b.min);
    extend(b.max);
}

std::uint32_t Scene::addMesh(Mesh mesh)
{
    meshes.push_back(std::move(mesh));
    return static_cast<std::uint32_t>(meshes.size() - 1);
}

std::size_t Scene::addMeshInstance(Mesh mesh, const glm::mat4& transform)
{
    std::string name = mesh.name;
    const std::uint32_t index = addMesh(std::move(mesh));
    instances.push_back(Instance{std::move(name), index, transform});
    return instances.size() - 1;
}

void Scene::append(const Scene& other)
{
    const auto offset = static_cast<std::uint32_t>(meshes.size());
    meshes.insert(meshes.end(), other.meshes.begin(), other.meshes.end());
    for (Instance instance : other.instances) {
        instance.mesh += offset;
        instances.push_back(std::move(instance));
    }
}

std::size_t Scene::triangleCount() const
{
    std::size_t count = 0;
    for (const Instance& instance : instances)
        count += meshes.at(instance.mesh).triangleCount();
    return count;
}

std::size_t Scene::uniqueTriangleCount() const
{
    std::size_t count = 0;
    for (const Mesh& mesh : meshes)
        count += mesh.triangleCount();
    return count;
}

Bounds Scene::bounds() const
{
    Bounds box;
    for (const Instance& instance : instances)
        box.extend(instanceBounds(instance));
    return box;
}

Bounds Scene::instanceBounds(const Instance& instance) const
{
    Bounds box;
    for (const glm::vec3& p : meshes.at(instance.mesh).positions)
        box.extend(glm::vec3(instance.transform * glm::vec4(p, 1.0f)));
    return box;
}

WorldTriangles worldTriangles(const Scene& scene)
{
    WorldTriangles out;
    const std::size_t count = scene.triangleCount();
    out.vertices.reserve(3 * count);
    out.instanceOf.reserve(count);
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const Mesh& mesh = scene.meshes.at(instance.mesh);
        // A mirroring transform turns counter-clockwise into clockwise: swap two vertices so that
        // front faces stay front faces (watertight culling relies on outward orientation).
        const bool mirrored = glm::determinant(glm::mat3(instance.transform)) < 0.0f;
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
            for (std::size_t k : {std::size_t(0), std::size_t(mirrored ? 2 : 1), std::size_t(mirrored ? 1 : 2)})
                out.vertices.emplace_back(instance.transform * glm::vec4(mesh.positions[mesh.indices[3 * t + k]], 1.0f));
        out.instanceOf.insert(out.instanceOf.end(), mesh.triangleCount(), static_cast<std::uint32_t>(i));
    }
    return out;
}

std::vector<std::uint32_t> weldPositions(const glm::vec3* p, std::size_t count, std::vector<std::uint32_t>* representative)
{
    std::vector<std::uint32_t> order(count);
    std::iota(order.begin(), order.end(), 0u);
    const auto less = [&](std::uint32_t a, std::uint32_t b) {
        return std::tie(p[a].x, p[a].y, p[a].z) < std::tie(p[b].x, p[b].y, p[b].z);
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<std::uint32_t> weld(count);
    std::uint32_t id = 0;
    for (std::size_t k = 0; k < count; ++k) {
        if (k > 0 && less(order[k - 1], order[k]))
            ++id;
        weld[order[k]] = id;
        if (representative && representative->size() == id)
            representative->push_back(order[k]);
    }
    return weld;
}

bool closedAndOutward(const Mesh& mesh)
{
    const std::vector<glm::vec3>& p = mesh.positions;
    if (mesh.indices.empty() || mesh.indices.size() % 3 != 0)
        return false;
    for (std::uint32_t i : mesh.indices)
        if (i >= p.size())
            return false;

    const std::vector<std::uint32_t> weld = weldPositions(p.data(), p.size());

    // Relative to one of its vertices, so that a mesh far from the origin keeps its volume's digits.
    const glm::dvec3 origin(p[mesh.indices[0]]);
    double volume6 = 0.0;
    std::vector<std::uint64_t> edges;
    edges.reserve(mesh.indices.size());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const std::uint32_t* v = &mesh.indices[3 * t];
        const std::uint64_t a = weld[v[0]], b = weld[v[1]], c = weld[v[2]];
        if (a == b || b == c || c == a)
            continue;
        edges.insert(edges.end(), {a << 32 | b, b << 32 | c, c << 32 | a});
        volume6 += glm::dot(glm::dvec3(p[v[0]]) - origin,
                            glm::cross(glm::dvec3(p[v[1]]) - origin, glm::dvec3(p[v[2]]) - origin));
    }
    if (edges.empty())
        return false;
    std::sort(edges.begin(), edges.end());
    if (std::adjacent_find(edges.begin(), edges.end()) != edges.end())
        return false;   // an edge traversed twice the same way: a flipped face, or more than two faces on it
    for (std::uint64_t e : edges)
        if (!std::binary_search(edges.begin(), edges.end(), e << 32 | e >> 32))
            return false;   // a boundary edge: the mesh is open there
    return volume6 > 0.0;
}

namespace {
bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool outOfRange(const glm::vec3& v)
{
    return std::abs(v.x) > kMaxCoordinateMetres || std::abs(v.y) > kMaxCoordinateMetres || std::abs(v.z) > kMaxCoordinateMetres;
}
std::string coordinates(const glm::vec3& v)
{
    char text[96];
    std::snprintf(text, sizeof text, "%.6g, %.6g, %.6g", double(v.x), double(v.y), double(v.z));
    return text;
}
} // namespace

void validate(const Mesh& mesh, const std::string& what)
{
    const std::string where = what + ": mesh '" + mesh.name + "'";
    if (mesh.indices.size() % 3 != 0)
        throw Error(where + " has " + std::to_string(mesh.indices.size()) +
                    " indices, not a multiple of 3");
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
        throw Error(where + " has " + std::to_string(mesh.normals.size()) + " normals for " +
                    std::to_string(mesh.positions.size()) + " positions");
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        if (!finite(mesh.positions[i]))
            throw Error(where + ": vertex " + std::to_string(i) + " is not finite (NaN or infinity)");
    if (!mesh.albedo.empty() && mesh.albedo.size() != mesh.triangleCount())
        throw Error(where + " has " + std::to_string(mesh.albedo.size()) + " albedos for " +
                    std::to_string(mesh.triangleCount()) + " triangles");
    for (std::size_t t = 0; t < mesh.albedo.size(); ++t)
        for (int c = 0; c < 3; ++c)
            if (!(mesh.albedo[t][c] >= 0.0f && mesh.albedo[t][c] <= 1.0f) && mesh.albedo[t] != kUnknownAlbedo)
                throw Error(where + ": triangle " + std::to_string(t) + "'s albedo must lie in [0, 1] per channel");
    for (std::size_t i = 0; i < mesh.indices.size(); ++i)
        if (mesh.indices[i] >= mesh.positions.size())
            throw Error(where + ": index " + std::to_string(i) + " = " + std::to_string(mesh.indices[i]) +
                        " is out of range (" + std::to_string(mesh.positions.size()) + " vertices)");
}

void validate(const Scene& scene, const std::string& what)
{
    for (const Mesh& mesh : scene.meshes)
        validate(mesh, what);
    for (const Instance& instance : scene.instances) {
        if (instance.mesh >= scene.meshes.size())
            throw Error(what + ": instance '" + instance.name + "' names mesh " +
                        std::to_string(instance.mesh) + " of " + std::to_string(scene.meshes.size()));
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(instance.transform[c][r]))
                    throw Error(what + ": instance '" + instance.name + "' has a non-finite transform");
        const Mesh& mesh = scene.meshes[instance.mesh];
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            const glm::vec3 p(instance.transform * glm::vec4(mesh.positions[i], 1.0f));
            if (!finite(p) || outOfRange(p))
                throw Error(what + ": instance '" + instance.name + "' places vertex " + std::to_string(i) + " at (" +
                            coordinates(p) + "); Sightline accepts coordinates up to " + std::to_string(int(kMaxCoordinateMetres)) +
                            " m from the origin");
        }
    }
}

void validateCoordinates(const WorldTriangles& triangles, const std::string& what)
{
    for (std::size_t i = 0; i < triangles.vertices.size(); ++i) {
        const glm::vec3& p = triangles.vertices[i];
        if (!finite(p) || outOfRange(p))
            throw Error(what + ": triangle " + std::to_string(i / 3) + " has a vertex at (" + coordinates(p) +
                        "); Sightline accepts coordinates up to " + std::to_string(int(kMaxCoordinateMetres)) +
                        " m from the origin");
    }
}

} // namespace sightline
