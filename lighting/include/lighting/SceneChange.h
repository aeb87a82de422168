#pragma once
// What changed between two versions of a scene, for views that keep what they computed
// (LightingCache::sceneChanged): the boxes around the geometry one version has and the other lacks,
// and which shading points stayed where they were.

#include <cstddef>
#include <span>
#include <vector>

#include "lighting/DirectLight.h"
#include "visibility/Scene.h"

namespace sightline {

/// Boxes around the triangles of either version that the other lacks (each triangle as its three
/// vertices bit for bit, counted with multiplicity; which instance holds it does not matter), one
/// per instance that holds some: an occluder moved across a room gives where it was and where it
/// is, not the room between. None when both hold the same triangles.
std::vector<Bounds> changedRegions(const WorldTriangles& before, const WorldTriangles& after);

/// Per point of `after`, the index of a point of `before` with the same position and normal bit
/// for bit (each matched once), or SIZE_MAX.
std::vector<std::size_t> matchPoints(std::span<const ShadingPoint> before, std::span<const ShadingPoint> after);

} // namespace sightline
