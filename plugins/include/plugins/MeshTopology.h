#pragma once
// A mesh's topology on OpenMesh's half-edge structure: whether it is closed, manifold and
// consistently wound, and which way it faces. The importers grant Mesh::watertight (the samplers'
// watertight culling, Eisemann & Décoret §7) by it.
//
// Vertices at exactly equal positions are welded first (OBJ, STL and glTF files often repeat a
// vertex per face or per normal). A triangle with two corners at one position is skipped (it
// covers nothing). OpenMesh refuses a face that would make an edge or a vertex non-manifold, or
// that runs an edge the same way as a face already there (inconsistent winding); such faces are
// counted, not dropped silently. The core's edge-count check (visibility/Scene.h closedAndOutward)
// answers the same question for the proofs inside the samplers; the tests hold the two to the
// same answers on every shared mesh and on broken ones.

#include <cstddef>

#include "visibility/Scene.h"

namespace sightline {

struct MeshTopology {
    std::size_t faces = 0;              ///< triangles OpenMesh accepted
    std::size_t degenerate = 0;         ///< skipped: two corners at one position
    std::size_t refused = 0;            ///< non-manifold or against the winding of their neighbours
    std::size_t boundaryEdges = 0;      ///< edges with a face on one side only (holes)
    std::size_t components = 0;         ///< connected parts
    double volume = 0.0;                ///< signed, of the accepted faces (positive: outward)

    bool manifold() const { return refused == 0; }
    bool closed() const { return faces > 0 && refused == 0 && boundaryEdges == 0; }
    bool closedAndOutward() const { return closed() && volume > 0.0; }
};

/// Indices out of range or a count that is not a multiple of 3 give an empty topology (not
/// closed): the importers refuse such meshes before they ask.
MeshTopology meshTopology(const Mesh& mesh);

} // namespace sightline
