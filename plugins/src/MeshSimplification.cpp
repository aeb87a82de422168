#include "plugins/MeshSimplification.h"

#include <algorithm>
#include <mutex>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "plugins/MeshTopology.h"

namespace sightline {

namespace {

/// Double positions: the quadrics of a mesh far from the origin keep their precision.
struct DoubleTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
using HalfEdgeMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

} // namespace

Mesh simplifiedMesh(const Mesh& mesh, std::size_t targetTriangles, double toleranceOfSize)
{
    static std::once_flag quiet;
    std::call_once(quiet, [] { omerr().disable(); });   // refused faces are expected, not news

    // Welded within a millionth of the mesh's size: generated and exported meshes often leave a
    // seam whose two sides differ in the last float bit, and an open seam unzips under collapses.
    const Bounds box = [&] {
        Bounds b;
        for (const glm::vec3& p : mesh.positions)
            b.extend(p);
        return b;
    }();
    const double snap = 1e-6 * std::max(1e-9, double(glm::length(box.max - box.min)));
    std::vector<glm::vec3> snapped;
    snapped.reserve(mesh.positions.size());
    for (const glm::vec3& p : mesh.positions)
        snapped.push_back(glm::vec3(glm::round(glm::dvec3(p) / snap) * snap));
    std::vector<std::uint32_t> representative;
    const std::vector<std::uint32_t> weld = weldPositions(snapped.data(), snapped.size(), &representative);
    HalfEdgeMesh halfEdges;
    std::vector<HalfEdgeMesh::VertexHandle> vertex;
    for (const std::uint32_t r : representative) {
        const glm::vec3& p = mesh.positions[r];
        vertex.push_back(halfEdges.add_vertex(HalfEdgeMesh::Point(p.x, p.y, p.z)));
    }
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t a = weld[mesh.indices[t]], b = weld[mesh.indices[t + 1]], c = weld[mesh.indices[t + 2]];
        if (a != b && b != c && c != a)
            halfEdges.add_face(vertex[a], vertex[b], vertex[c]);
    }
    halfEdges.request_face_normals();
    halfEdges.update_face_normals();
    halfEdges.request_vertex_status();
    halfEdges.request_edge_status();
    halfEdges.request_face_status();
    // A hole's rim stays where it is: the quadrics do not hold a boundary, which would recede.
    for (const auto v : halfEdges.vertices())
        if (halfEdges.is_boundary(v))
            halfEdges.status(v).set_locked(true);

    OpenMesh::Decimater::DecimaterT<HalfEdgeMesh> decimater(halfEdges);
    OpenMesh::Decimater::ModQuadricT<HalfEdgeMesh>::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<HalfEdgeMesh>::Handle normalFlipping;
    decimater.add(quadric);
    decimater.add(normalFlipping);
    // No collapse may move the surface farther than the tolerance (the quadric is a squared
    // distance): past it the decimater stops short of the count rather than flatten the mesh.
    const double tolerance = toleranceOfSize * glm::length(glm::dvec3(box.max - box.min));
    decimater.module(quadric).set_max_err(tolerance * tolerance, false);
    decimater.initialize();
    decimater.decimate_to_faces(0, targetTriangles);
    halfEdges.garbage_collection();

    Mesh coarse;
    coarse.name = mesh.name;
    for (const auto v : halfEdges.vertices()) {
        const auto& p = halfEdges.point(v);
        coarse.positions.emplace_back(float(p[0]), float(p[1]), float(p[2]));
    }
    for (const auto f : halfEdges.faces())
        for (const auto v : halfEdges.fv_range(f))
            coarse.indices.push_back(std::uint32_t(v.idx()));
    coarse.watertight = meshTopology(coarse).closedAndOutward();
    return coarse;
}

} // namespace sightline
