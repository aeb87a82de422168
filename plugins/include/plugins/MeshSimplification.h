#pragma once
// Coarse occluders ("model no more than a scene needs", Eisemann & Décoret §10): a mesh simplified
// by OpenMesh's decimater (halfedge collapses ordered by quadric error, Garland & Heckbert 1997;
// collapses that would flip a face's normal are refused, so the surface does not fold over; no
// collapse moves the surface farther than a tolerance, which bounds the band of rays whose answer
// can change), then one least-squares step that fits the coarse vertices back onto the original
// surface along their normals. A halfedge collapse keeps one of its own vertices, so each coarse
// face on a convex part is a chord inside the original (it blocks less) and on a concave part one
// outside (it blocks more); the fit takes that bias out, which halves the rays answered
// differently at the same triangle count (docs/cli.md, `coarse --sweep`). The result is the
// closest coarse shape, not a conservative one: it may block rays the original lets through and
// the reverse; `sightline-cli coarse` counts both against the exact answer. The conservative kind
// (never blocks a ray the original lets through) is visibility/InnerOccluder.h.

#include <cstddef>

#include "visibility/Scene.h"

namespace sightline {

/// `mesh` with at most `targetTriangles` triangles where the decimater can get there without
/// moving the surface farther than `toleranceOfSize` times the mesh's bounding diagonal (it stops
/// short of the count rather than flatten the shape; a hole's rim is held where it is). Faces
/// OpenMesh refuses as non-manifold are dropped. Positions are welded within a millionth of the
/// size; the vertices are then fitted to the original surface (the rim's stay); the name is kept;
/// the watertight flag is recomputed.
Mesh simplifiedMesh(const Mesh& mesh, std::size_t targetTriangles, double toleranceOfSize = 0.01);

} // namespace sightline
