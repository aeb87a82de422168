#pragma once
// Structural checks of a glTF document's JSON, done before tinygltf reads it. tinygltf converts
// every index and count to int or size_t as it goes: 3.5, 1e308 or 4294967295 as `nodes[].mesh`
// becomes "no mesh" (or -1), and the instance silently vanishes. Here each such field must be a
// non-negative integer naming an existing element, and the node graph must be what glTF 2.0
// requires (disjoint strict trees, scene roots that are root nodes), so the scene builder can rely
// on it. Every failure throws sightline::Error naming `what` (the file) and the element.

#include <string>

#include <nlohmann/json.hpp>

namespace sightline::gltf {

/// Index fields (scene, scenes[].nodes, nodes[].mesh/children/camera/skin, meshes' accessors and
/// materials, accessors[].bufferView and sparse views, bufferViews[].buffer, images[].bufferView,
/// skins) must name existing elements; counts, offsets, lengths, strides and enums must be
/// non-negative integers; the top-level lists must be arrays of objects.
void checkIndices(const nlohmann::json& doc, const std::string& what);

/// No node is a child twice (of one parent or of two), no node is its own ancestor, and each scene's
/// roots are distinct nodes that are nobody's child. Run after checkIndices.
void checkNodeForest(const nlohmann::json& doc, const std::string& what);

} // namespace sightline::gltf
