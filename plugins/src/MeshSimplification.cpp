#include "plugins/MeshSimplification.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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

glm::dvec3 toGlm(const HalfEdgeMesh::Point& p) { return {p[0], p[1], p[2]}; }

/// The point of triangle abc closest to p (Ericson, Real-Time Collision Detection §5.1.5), as
/// barycentric weights.
glm::dvec3 closestWeights(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0)
        return {1, 0, 0};
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3)
        return {0, 1, 0};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        return {1 - v, v, 0};
    }
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6)
        return {0, 0, 1};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        return {1 - w, 0, w};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {0, 1 - w, w};
    }
    const double denom = 1.0 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    return {1 - v - w, v, w};
}

/// One least-squares step that fits the coarse vertices back onto the original surface: every
/// original vertex finds its closest point on the coarse mesh and pulls that face's corners along
/// their normals by its signed distance, in proportion to its barycentric weights. A halfedge
/// collapse keeps one of its own vertices, so on a convex part each coarse face is a chord below
/// the original surface (a coarse mesh blocks less than the original there) and the reverse in
/// concave parts; the step removes that bias. Locked (rim) vertices stay.
void refitToSurface(HalfEdgeMesh& coarse, const std::vector<glm::dvec3>& original)
{
    const std::size_t faces = coarse.n_faces();
    if (faces == 0 || original.empty())
        return;
    std::vector<std::array<int, 3>> corner(faces);
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    double edge = 0.0;
    for (const auto f : coarse.faces()) {
        int k = 0;
        for (const auto v : coarse.fv_range(f)) {
            corner[std::size_t(f.idx())][std::size_t(k++)] = v.idx();
            lo = glm::min(lo, toGlm(coarse.point(v)));
            hi = glm::max(hi, toGlm(coarse.point(v)));
        }
        const auto& c = corner[std::size_t(f.idx())];
        edge += glm::length(toGlm(coarse.point(HalfEdgeMesh::VertexHandle(c[0]))) - toGlm(coarse.point(HalfEdgeMesh::VertexHandle(c[1]))));
    }
    // Faces binned by their boxes on a grid of about two mean edges.
    const double cell = std::max(2.0 * edge / double(faces), 1e-9 * std::max(1.0, glm::length(hi - lo)));
    const glm::ivec3 n = glm::clamp(glm::ivec3(glm::ceil((hi - lo) / cell)) + 1, glm::ivec3(1), glm::ivec3(512));
    const auto cellOf = [&](const glm::dvec3& p) { return glm::clamp(glm::ivec3(glm::floor((p - lo) / cell)), glm::ivec3(0), n - 1); };
    std::vector<std::vector<std::uint32_t>> bins(std::size_t(n.x) * n.y * n.z);
    const auto bin = [&](glm::ivec3 c) -> std::vector<std::uint32_t>& { return bins[(std::size_t(c.z) * n.y + c.y) * n.x + c.x]; };
    const auto point = [&](int v) { return toGlm(coarse.point(HalfEdgeMesh::VertexHandle(v))); };
    for (std::size_t f = 0; f < faces; ++f) {
        const glm::dvec3 a = point(corner[f][0]), b = point(corner[f][1]), c = point(corner[f][2]);
        const glm::ivec3 from = cellOf(glm::min(a, glm::min(b, c))), to = cellOf(glm::max(a, glm::max(b, c)));
        for (int z = from.z; z <= to.z; ++z)
            for (int y = from.y; y <= to.y; ++y)
                for (int x = from.x; x <= to.x; ++x)
                    bin({x, y, z}).push_back(std::uint32_t(f));
    }
    coarse.request_vertex_normals();
    coarse.update_normals();
    std::vector<double> pull(coarse.n_vertices(), 0.0), weight(coarse.n_vertices(), 0.0);
    const int reach = std::max({n.x, n.y, n.z});
    for (const glm::dvec3& p : original) {
        const glm::ivec3 at = cellOf(p);
        double best = std::numeric_limits<double>::infinity();
        std::size_t bestFace = 0;
        glm::dvec3 bestWeights(0.0);
        // Rings of cells until the next ring lies farther than the best face found.
        for (int r = 0; r <= reach && !(best <= double(r - 1) * cell); ++r)
            for (int z = at.z - r; z <= at.z + r; ++z)
                for (int y = at.y - r; y <= at.y + r; ++y)
                    for (int x = at.x - r; x <= at.x + r; ++x) {
                        if (std::max({std::abs(x - at.x), std::abs(y - at.y), std::abs(z - at.z)}) != r ||
                            glm::any(glm::lessThan(glm::ivec3(x, y, z), glm::ivec3(0))) ||
                            glm::any(glm::greaterThanEqual(glm::ivec3(x, y, z), n)))
                            continue;
                        for (const std::uint32_t f : bin({x, y, z})) {
                            const glm::dvec3 a = point(corner[f][0]), b = point(corner[f][1]), c = point(corner[f][2]);
                            const glm::dvec3 w = closestWeights(p, a, b, c);
                            const double d = glm::length(p - (w.x * a + w.y * b + w.z * c));
                            if (d < best) {
                                best = d;
                                bestFace = f;
                                bestWeights = w;
                            }
                        }
                    }
        if (!std::isfinite(best))
            continue;
        const auto fh = HalfEdgeMesh::FaceHandle(int(bestFace));
        const glm::dvec3 normal = toGlm(coarse.normal(fh));
        const glm::dvec3 a = point(corner[bestFace][0]), b = point(corner[bestFace][1]), c = point(corner[bestFace][2]);
        const double signedDistance = glm::dot(p - (bestWeights.x * a + bestWeights.y * b + bestWeights.z * c), normal);
        for (int k = 0; k < 3; ++k) {
            pull[std::size_t(corner[bestFace][std::size_t(k)])] += bestWeights[k] * signedDistance;
            weight[std::size_t(corner[bestFace][std::size_t(k)])] += bestWeights[k];
        }
    }
    for (const auto v : coarse.vertices()) {
        const std::size_t i = std::size_t(v.idx());
        if (weight[i] <= 0.0 || coarse.status(v).locked())
            continue;
        const auto normal = coarse.normal(v);
        coarse.set_point(v, coarse.point(v) + normal * (pull[i] / weight[i]));
    }
}

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
    std::vector<glm::dvec3> original;
    original.reserve(representative.size());
    for (const std::uint32_t r : representative)
        original.push_back(glm::dvec3(mesh.positions[r]));
    halfEdges.update_face_normals();
    refitToSurface(halfEdges, original);

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
