#pragma once
// Internal to the CPU bitmask sampler: the paper's own §5 method, the mask of a backprojected
// polygon as the AND of its edges' masks from a Hough table (HoughMaskTable.h). Inexact by design
// (nearest texel); `bench` charts it against the exact masks.

#include <cstdint>

#include "visibility/HoughMaskTable.h"

namespace sightline::bitmask {

/// ORs into `mask` the AND of the table masks of the backprojection's edges (ps, pt: source
/// coordinates), taken counter-clockwise so that the inside is on the left of every edge. A
/// polygon of zero area covers nothing.
void tableMask(const HoughMaskTable& table, const double* ps, const double* pt, int count, std::uint64_t* mask);

} // namespace sightline::bitmask
