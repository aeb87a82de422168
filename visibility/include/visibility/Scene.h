#pragma once
// The scene model: just what visibility needs, and the surfaces' albedos for indirect light.
//
// A Scene holds meshes once and places them through instances (mesh index + world transform), so a
// plant placed 200 times is stored once. Units are metres, right-handed, Y up (docs/design.md §2).
// Samplers do not walk this structure: they take the flat world-space view from worldTriangles().

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace sightline {

/// Axis-aligned box. An empty box has min > max (the default), and grows with extend().
struct Bounds {
    glm::vec3 min{std::numeric_limits<float>::infinity()};
    glm::vec3 max{-std::numeric_limits<float>::infinity()};

    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    void extend(const glm::vec3& p);
    void extend(const Bounds& b);
};

/// Mesh::albedo of a triangle whose file does not say: the lighting run's own albedo applies.
inline constexpr glm::vec3 kUnknownAlbedo{-1.0f};

/// Indexed triangle mesh in its own object space. `indices.size()` is a multiple of 3.
/// `normals` is either empty or one per position (for display only; visibility ignores it).
struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<std::uint32_t> indices;
    /// The mesh is closed and consistently oriented (outward faces). Only an optimisation may rely
    /// on it (watertight front-face culling, Eisemann & Décoret §7), never the answer. A flag
    /// wrongly set on an open mesh loses real blockers, so importers set it only where
    /// closedAndOutward() holds.
    bool watertight = false;
    /// Empty, or each triangle's diffuse reflectance per channel, in [0, 1]: its material's base
    /// colour where the file gives one, kUnknownAlbedo where it does not (a texture not decoded).
    /// Indirect light alone reads it (lighting/Indirect.h); visibility ignores it.
    std::vector<glm::vec3> albedo;

    std::size_t triangleCount() const { return indices.size() / 3; }
};

/// One placement of a mesh in the world.
struct Instance {
    std::string name;
    std::uint32_t mesh = 0;             ///< index into Scene::meshes
    glm::mat4 transform{1.0f};          ///< object -> world, column-major (GLM)
};

struct Scene {
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;

    /// Adds a mesh and returns its index.
    std::uint32_t addMesh(Mesh mesh);
    /// Adds a mesh with one instance of it under the mesh's name; returns the instance index.
    std::size_t addMeshInstance(Mesh mesh, const glm::mat4& transform = glm::mat4(1.0f));
    /// Appends all meshes and instances of `other` (mesh indices are remapped).
    void append(const Scene& other);

    /// Triangles in the world, counting every instance.
    std::size_t triangleCount() const;
    /// Triangles stored once per mesh.
    std::size_t uniqueTriangleCount() const;
    /// World-space bounds of all instances (empty box for an empty scene).
    Bounds bounds() const;
    /// World-space bounds of one placed mesh.
    Bounds instanceBounds(const Instance& instance) const;
};

/// Flat world-space triangle soup: triangle t is (vertices[3t], vertices[3t+1], vertices[3t+2]).
/// `instanceOf[t]` names the instance it came from (for watertight flags and picking). Winding is
/// the mesh's, corrected for mirroring transforms, so outward faces stay outward.
struct WorldTriangles {
    std::vector<glm::vec3> vertices;
    std::vector<std::uint32_t> instanceOf;

    std::size_t size() const { return instanceOf.size(); }
};

WorldTriangles worldTriangles(const Scene& scene);

/// Ids that weld `count` positions: positions of equal value share an id (ids count up in the
/// positions' sorted order). `representative`, when given, receives for each id the index of a
/// position that holds it.
std::vector<std::uint32_t> weldPositions(const glm::vec3* positions, std::size_t count,
                                         std::vector<std::uint32_t>* representative = nullptr);

/// Whether `mesh` may carry Mesh::watertight: its surface is closed and consistently wound with
/// outward faces. Vertices at exactly equal positions are welded first (OBJ, STL and glTF files
/// often repeat a vertex per face or per normal); then every directed edge must occur once and
/// its reverse once, i.e. each undirected edge is shared by exactly two triangles that traverse it
/// in opposite directions; and the signed volume (the sum of dot(a, cross(b, c)) / 6) must be
/// positive, which a closed mesh wound inward fails.
///
/// Degenerate triangles: one with two corners at the same position is skipped (it covers nothing,
/// and its two real edges are each other's reverse, so it neither opens nor closes the surface);
/// a zero-area triangle with three distinct corners (a sliver closing a T-junction) counts like
/// any other, its edges matched or not. A mesh of several closed parts passes when each part is
/// closed and their volumes sum positive. False for an empty mesh, an index count that is not a
/// multiple of 3, or an index out of range.
bool closedAndOutward(const Mesh& mesh);

/// Throws sightline::Error naming the first problem: an index out of range, an index count that is
/// not a multiple of 3, a non-finite position, a normal count that differs from the position count,
/// an albedo count that is neither 0 nor the triangle count or an albedo outside [0, 1] (other
/// than kUnknownAlbedo),
/// an instance naming a missing mesh, a non-finite transform, or (scenes) a placed vertex farther
/// than kMaxCoordinateMetres (ExactSegment.h, docs/design.md §2) from the origin on some axis. `what`
/// prefixes the message (usually the file name).
void validate(const Mesh& mesh, const std::string& what);
void validate(const Scene& scene, const std::string& what);

/// Throws sightline::Error when a world vertex is not finite or lies beyond kMaxCoordinateMetres
/// on some axis: every sampler refuses such input rather than answer wrongly (Embree asserts on
/// coordinates near 1e19, and float arithmetic on them is meaningless).
void validateCoordinates(const WorldTriangles& triangles, const std::string& what);

} // namespace sightline
