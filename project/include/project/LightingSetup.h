#pragma once
// Lighting inputs a project may carry for soft shadows (Eisemann & Décoret §8), as optional keys
// kept on save like any other:
//
//   "light": {"texture": "neon.png", "levels": 8}
//       the source patch is a colour-textured area light: each source sample takes the texel
//       under it (texture v up, like the patch's v), quantised to `levels` steps per channel;
//       without the key the light is white.
//   "receiver_heights": {"image": "bumps.png", "metres": 0.25}   or   {"npy": "heights.npy"}
//       the receiver is a height field: each receiver sample is raised toward the source by the
//       image's grey level (bilinear, 0..1) times `metres`, or by the float32 array of shape
//       (nb, na) in metres; without the key the receiver is flat.
//
// Paths are relative to the project's folder, like "scene".

#include <string>

#include "lighting/AreaLight.h"
#include "project/Project.h"
#include "visibility/ReceiverHeights.h"

namespace sightline {

/// The project's light for `source` (whose sample grid may differ from the project's). Throws
/// sightline::Error naming the key or file.
AreaLight projectLight(const Project& project, const Patch& source, const std::string& what);

/// The project's receiver heights for `receiver`'s sample grid (empty for a flat receiver).
/// Throws sightline::Error naming the key or file.
ReceiverHeights projectReceiverHeights(const Project& project, const Patch& receiver, const std::string& what);

/// The project's pair checked (validatePatchPair) and its receiver's heights, read and checked
/// against it (validateReceiverHeights): what a command samples the project's own pair with.
/// Throws sightline::Error.
ReceiverHeights validatedPairHeights(const Project& project);

} // namespace sightline
