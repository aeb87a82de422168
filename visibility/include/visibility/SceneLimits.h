#pragma once
// Limits on what a scene file may expand to. Instancing formats (glTF: a node per placement of a
// shared mesh) describe far more geometry than their bytes: a file of a few kilobytes can place a
// large mesh a million times. Importers count what a file expands to before expanding it, and refuse
// past these limits with an error instead of running out of memory. They are far above any level
// Sightline is meant for (a game level is thousands of instances and a few million triangles), and
// low enough that the expanded scene's world-space triangles fit in a few gigabytes.

#include <cstdint>

namespace sightline {

/// The most mesh instances one scene file may place.
inline constexpr std::uint64_t kMaxSceneInstances = 1'000'000;

/// The most triangles one scene file may place, counting each instance's mesh in full.
inline constexpr std::uint64_t kMaxSceneTriangles = 50'000'000;

/// The most vertices one scene file's meshes may hold (each converted once, however often placed):
/// shared vertex data is copied per primitive, so a small file could otherwise make gigabytes.
inline constexpr std::uint64_t kMaxSceneVertices = 50'000'000;

/// The most elements a glTF accessor without a bufferView (zeros, perhaps sparse values, none of
/// them stored in the file) may declare: its memory is not bounded by the file's size otherwise.
inline constexpr std::uint64_t kMaxUnbackedAccessorElements = std::uint64_t(1) << 22;

} // namespace sightline
