#pragma once
// Rays along the silhouettes of what blocks a (cell, object) pair: where slivers of visibility
// open, and where area samples rarely fall. The triangles a pair's rays met first, the most met
// first, are its blockers; a ray from a point of the cell passes just outside a blocker edge (at a
// quarter, half and three quarters of it, 1e-5 of its length or 20 um, whichever is more, off the
// triangle in its plane: inside any opening wider than that) and goes on to the object's far side.
// One whose first hit is the object is a witness. The dense reference runs them for the pairs its
// area rays did not see (PvsReference.h).

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"
#include "visibility/pvs/FirstHitCaster.h"

namespace sightline::pvs {

/// Blockers per pair, and the cell points the rays start from.
inline constexpr int kEdgeBlockers = 12;
inline constexpr int kEdgeCellPoints = 8;

/// The `count` triangles met first most often (ties: the lower index first).
std::vector<std::int64_t> mostMet(const std::unordered_map<std::int64_t, int>& met, int count);

/// Whether a ray from one of `from` past an edge of one of `blockers` (indices into
/// `triangleVertices`, three corners each) first meets an instance of `object` (objectOf maps
/// instances to objects), going no farther than `objectBox`'s far corner. `rays` counts the casts.
bool edgeWitness(const std::vector<glm::vec3>& triangleVertices, const FirstHitCaster& caster,
                 const std::vector<std::int32_t>& objectOf, std::int32_t object, const Bounds& objectBox,
                 const std::vector<glm::vec3>& from, const std::vector<std::int64_t>& blockers, std::uint64_t& rays);

} // namespace sightline::pvs
