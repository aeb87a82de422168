#include "plugins/MeshTopology.h"

#include <mutex>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Core/Utils/PropertyManager.hh>

#include <glm/geometric.hpp>

namespace sightline {

namespace {

using HalfEdgeMesh = OpenMesh::TriMesh_ArrayKernelT<>;

std::size_t countComponents(HalfEdgeMesh& mesh)
{
    auto seen = OpenMesh::makeTemporaryProperty<OpenMesh::FaceHandle, bool>(mesh);
    for (const auto f : mesh.faces())
        seen[f] = false;
    std::size_t components = 0;
    std::vector<OpenMesh::FaceHandle> stack;
    for (const auto start : mesh.faces()) {
        if (seen[start])
            continue;
        ++components;
        seen[start] = true;
        stack.push_back(start);
        while (!stack.empty()) {
            const auto f = stack.back();
            stack.pop_back();
            for (const auto g : mesh.ff_range(f))
                if (!seen[g]) {
                    seen[g] = true;
                    stack.push_back(g);
                }
        }
    }
    return components;
}

} // namespace

MeshTopology meshTopology(const Mesh& mesh)
{
    MeshTopology topology;
    const std::vector<glm::vec3>& p = mesh.positions;
    if (mesh.indices.empty() || mesh.indices.size() % 3 != 0)
        return topology;
    for (const std::uint32_t i : mesh.indices)
        if (i >= p.size())
            return topology;

    // A refused face is counted here; OpenMesh would also print it ("complex edge") on stderr,
    // which a command's one-line errors must not be mixed with.
    static std::once_flag quiet;
    std::call_once(quiet, [] { omerr().disable(); });

    std::vector<std::uint32_t> representative;
    const std::vector<std::uint32_t> weld = weldPositions(p.data(), p.size(), &representative);
    HalfEdgeMesh halfEdges;
    std::vector<HalfEdgeMesh::VertexHandle> vertex;
    vertex.reserve(representative.size());
    for (const std::uint32_t r : representative)
        vertex.push_back(halfEdges.add_vertex(HalfEdgeMesh::Point(p[r].x, p[r].y, p[r].z)));
    // Volume from a local origin, in double: a closed box 100 km out keeps its sign.
    const glm::dvec3 origin(p[representative.front()]);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const std::uint32_t a = weld[mesh.indices[3 * t]], b = weld[mesh.indices[3 * t + 1]], c = weld[mesh.indices[3 * t + 2]];
        if (a == b || b == c || c == a) {
            ++topology.degenerate;
            continue;
        }
        const auto face = halfEdges.add_face(vertex[a], vertex[b], vertex[c]);
        if (!face.is_valid()) {
            ++topology.refused;
            continue;
        }
        ++topology.faces;
        const glm::dvec3 pa = glm::dvec3(p[representative[a]]) - origin, pb = glm::dvec3(p[representative[b]]) - origin,
                         pc = glm::dvec3(p[representative[c]]) - origin;
        topology.volume += glm::dot(pa, glm::cross(pb, pc)) / 6.0;
    }
    for (const auto e : halfEdges.edges())
        topology.boundaryEdges += halfEdges.is_boundary(e) ? 1 : 0;
    topology.components = countComponents(halfEdges);
    return topology;
}

} // namespace sightline
