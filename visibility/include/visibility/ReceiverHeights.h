#pragma once
// A bumpy receiver given as a height field (Eisemann & Décoret §8: "it can be adapted to handle a
// bumpy one ... offset the fragment's world position, for example looking up a height map").
//
// Each receiver sample moves along the receiver's normal by its own height, so the receiver is a
// height field as seen from the source side, as the paper requires. Blocking keeps docs/design.md §2's
// meaning with the displaced position as the segment's receiver end: the ray S_i -> R_j is blocked
// when the segment from S_i to the displaced R_j crosses a triangle strictly between its ends.
// Every sampler that takes heights (RayCastOptions, BitmaskOptions) answers that same question.

#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Patch.h"

namespace sightline {

/// A bumpy receiver (Eisemann & Décoret §8): receiver sample j (bit index b * na + a) lies at
/// receiver.sample(j) + metres[j] * n, where n is the receiver's unit normal oriented toward the
/// source's side (toward the source centre). Empty = flat (the plain patch).
struct ReceiverHeights {
    std::vector<double> metres;
    bool empty() const { return metres.empty(); }
};

/// Unit receiver normal pointing to the source's side.
glm::dvec3 receiverNormalTowardSource(const Patch& source, const Patch& receiver);

/// The displaced position of receiver sample j (receiver.sample(j) when heights are empty).
glm::dvec3 displacedReceiverSample(const Patch& source, const Patch& receiver, const ReceiverHeights& heights, int j);

/// Throws sightline::Error (base/Error.h) with a one-line message a user can act on unless:
/// metres.size() == receiver.sampleCount() (or empty), every value finite, and every displaced
/// sample strictly on the receiver's side of the source plane (it must not reach the source).
/// Call it on a pair that validatePatchPair accepts.
void validateReceiverHeights(const Patch& source, const Patch& receiver, const ReceiverHeights& heights);

/// True when the heights move no sample (empty or all zero): the plain patch, sampled as such.
bool flatReceiver(const ReceiverHeights* heights);

} // namespace sightline
