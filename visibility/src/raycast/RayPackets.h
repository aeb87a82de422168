#pragma once
// Internal to the ray casters (RayCastSampler.cpp, ProvenRayCaster.cpp): how their rays go into
// packets and how a packet's lanes are tested against one triangle.

#include <cstdint>
#include <vector>

#include "visibility/ExactSegment.h"
#include "visibility/Patch.h"
#include "visibility/ReceiverHeights.h"

namespace sightline::raycast {

/// The segments' ends in double (docs/design.md §2): every source sample, and each receiver sample
/// moved along the receiver's normal by its height on a bumpy receiver (§8; all-zero heights are
/// the flat patch). Throws sightline::Error for heights that do not fit the receiver.
struct SampleEnds {
    SampleEnds(const Patch& source, const Patch& receiver, const ReceiverHeights* heights);
    glm::dvec3 receiverEnd(int j) const
    {
        return bumpy ? receiver.sample(j) + heights->metres[std::size_t(j)] * normal : receiver.sample(j);
    }

    const Patch& receiver;
    const ReceiverHeights* heights;
    bool bumpy = false;
    glm::dvec3 normal{0.0};               ///< the receiver's, towards the source (bumpy only)
    std::vector<glm::dvec3> source;       ///< source.sample(i)
};

/// Source sample indices in the order rays go into packets of 16: blocks of 4x4 samples where the
/// grid allows (more coherent than 16 along a row, and faster), else bit order.
std::vector<int> packetOrder(const Patch& source);

/// Receiver samples grouped in blocks of 4x4 neighbouring grid samples (only those of `subset`,
/// when given), in the grid's order: packets that start at the source run to one block. Throws
/// sightline::Error for a subset entry outside the grid.
std::vector<std::vector<int>> receiverBlocks(const Patch& receiver, const std::vector<int>* subset);

/// TriangleSeenFrom::crossedBy for `count` segments from the triangle's viewpoint with directions
/// (dx, dy, dz): hit[i] is 1 where segment i crosses it by the contract, else 0. Branch-free, so
/// that the compiler vectorises it (with AVX2 where the CPU has it): the same arithmetic, lane by
/// lane, hence the same answers as crossedBy (RayPackets.cpp is built without contracting
/// products into fused multiply-adds, which the AVX2 copy could otherwise do and crossedBy not).
void crossedLanes(const TriangleSeenFrom& triangle, const double* dx, const double* dy, const double* dz, int count,
                  std::int64_t* hit);

} // namespace sightline::raycast
