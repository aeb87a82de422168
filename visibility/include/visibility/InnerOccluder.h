#pragma once
// The conservative coarse occluder of a closed mesh: a few hundred faces around a region strictly
// inside it (the CPU sampler's inner proxy, src/bitmask/InnerProxy.h, which proves the claim). A
// segment between two points outside the mesh that meets these faces crosses the mesh itself, so
// in place of the mesh they block no ray the mesh lets through: safe for a PVS and for culling
// (the answer can only become more visible). The closest coarse kind is plugins/MeshSimplification.h.

#include "visibility/Scene.h"

namespace sightline {

/// Its faces for `mesh` (object space), from `resolution` voxels along the longest side of its
/// bounds; empty when no voxel clears the surface (a thin shell). Throws sightline::Error unless
/// the mesh is closed and outward (closedAndOutward): the proof needs a closed surface.
Mesh innerOccluderMesh(const Mesh& mesh, int resolution = 32);

} // namespace sightline
