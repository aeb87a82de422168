#pragma once
// What is under the cursor: scene triangles (to place patches on surfaces and select objects) and
// the patches themselves. Brute force over the world triangles: on one core a small fraction of
// a click's budget for the demo, and it needs no BVH kept in step with edits.

#include <cstdint>
#include <functional>
#include <optional>

#include "editor/Camera.h"
#include "visibility/Patch.h"
#include "visibility/Scene.h"

namespace sightline::ui {

struct SurfaceHit {
    double distance = 0.0;        ///< along the ray
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0.0};       ///< unit, facing the ray's origin
    std::size_t triangle = 0;     ///< index into the WorldTriangles
};

/// Nearest triangle the ray hits (both faces), if any; with `visible`, only hits it accepts (the
/// section cut: a click goes through what is not drawn).
std::optional<SurfaceHit> pickSurface(const WorldTriangles& triangles, const Ray& ray,
                                      const std::function<bool(std::size_t triangle, const glm::dvec3& point)>& visible = {});

/// The closed (watertight) instance whose inside holds `point`, if any: rays from the point in two
/// skew directions first meet one of its outward faces from behind. Open meshes have no inside
/// and are never named.
std::optional<std::size_t> enclosingInstance(const Scene& scene, const WorldTriangles& triangles, const glm::dvec3& point);

/// Distance along the ray to the patch's parallelogram, if hit.
std::optional<double> pickPatch(const Patch& patch, const Ray& ray);

/// Where a ray crosses a patch: the patch coordinates (s, t) in [0, 1]^2 (point c + s u + t v)
/// and the sample whose cell holds them. Sample (a, b) sits at the centre of its cell
/// [a/na, (a+1)/na) x [b/nb, (b+1)/nb) (docs/design.md §2), which is also the texel the overlay
/// draws there.
struct PatchSampleHit {
    double distance = 0.0;
    double s = 0.0, t = 0.0;
    int a = 0, b = 0;
};
std::optional<PatchSampleHit> pickPatchSample(const Patch& patch, const Ray& ray);

/// A width x height patch lying on the surface at `hit`, lifted `offset` metres off it along the
/// normal, facing away from the surface. Edges follow the surface: u horizontal where the surface
/// is a wall, along X on floors and ceilings; the grid keeps `na` x `nb`.
Patch patchOnSurface(const SurfaceHit& hit, double width, double height, int na, int nb, double offset = 0.02);

} // namespace sightline::ui
