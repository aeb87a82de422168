#pragma once
// O'Rorke's light visibility sets (GPU Gems ch. 15) per light, over a scene's instances:
//   V  the instances visible from the camera (given: the caller renders or casts them),
//   L  the instances the light reaches: some point of them has a free segment to some point of
//      the light, within its range and cone (an area light: on its emitting side),
//   I  = V ∩ L, what must be lit,
//   S  the instances that cast a shadow onto I: some segment from the light to a point of an
//      instance of I crosses them.
// "Some point" is sampled: each triangle's centroid and a barycentric grid of points spaced
// `spacing` apart (at most kMaxPointsPerTriangle), tested against every emitter of the light (an
// area light's samples), every segment decided by the contract's exact test. A light's L is
// therefore what those samples see: a sliver reached only between them is missed, never invented.

#include <cstdint>
#include <optional>
#include <vector>

#include "lighting/DirectLight.h"
#include "lighting/Light.h"
#include "visibility/Scene.h"
#include "visibility/pvs/PvsData.h"

namespace sightline {

struct LightSets {
    std::vector<std::uint32_t> V, L, I, S;   ///< sorted instance indices
    bool operator==(const LightSets&) const = default;
};

struct LightSetOptions {
    double spacing = 0.5;                    ///< metres between a triangle's sampled points
    int threads = 0;
    /// Per light (in the lights' order, or empty for none), whether its L is restricted, and to
    /// which instances (sorted): a baked PVS's row for the cell the light stands in (O'Rorke's L
    /// served by the bake), so that only those instances are sampled.
    std::vector<bool> restricted;
    std::vector<std::vector<std::uint32_t>> candidates;
};

inline constexpr int kMaxPointsPerTriangle = 4096;

/// What a baked PVS's rows bound a light's L by: the instances visible from the cells it stands
/// in (a point or spot light's position, an area light's corners and samples), for
/// LightSetOptions::candidates; nullopt when some of those points lie in no cell, and for a
/// directional light, which stands nowhere. Whatever the light reaches is visible from its
/// cells, so a conservative bake only spares work.
std::optional<std::vector<std::uint32_t>> pvsReach(const std::vector<Bounds>& cells, const pvs::VisibilityRows& rows,
                                                   const std::vector<pvs::PvsObject>& objects, const Light& light);

/// The sets of each light, in the lights' order. `visible` is V (any order, duplicates allowed).
/// `scene` must be the one `lighting` was built from.
std::vector<LightSets> lightSets(const LightingScene& lighting, const Scene& scene, const std::vector<Light>& lights,
                                 const std::vector<std::uint32_t>& visible, const LightSetOptions& options = {});

} // namespace sightline
