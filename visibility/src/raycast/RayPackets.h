#pragma once
// Internal to the reference ray caster (RayCastSampler.cpp): how its rays go into packets and how
// a packet's lanes are tested against one triangle.

#include <cstdint>
#include <vector>

#include "visibility/ExactSegment.h"
#include "visibility/Patch.h"

namespace sightline::raycast {

/// Source sample indices in the order rays go into packets of 16: blocks of 4x4 samples where the
/// grid allows (more coherent than 16 along a row, and faster), else bit order.
std::vector<int> packetOrder(const Patch& source);

/// TriangleSeenFrom::crossedBy for `count` segments from the triangle's viewpoint with directions
/// (dx, dy, dz): hit[i] is 1 where segment i crosses it by the contract, else 0. Branch-free, so
/// that the compiler vectorises it (with AVX2 where the CPU has it): the same arithmetic, lane by
/// lane, hence the same answers as crossedBy.
void crossedLanes(const TriangleSeenFrom& triangle, const double* dx, const double* dy, const double* dz, int count,
                  std::int64_t* hit);

} // namespace sightline::raycast
