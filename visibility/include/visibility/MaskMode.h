#pragma once
// How a sampler finds the set of source samples inside a backprojection (Eisemann & Décoret §5).
// Shared by the CPU (CpuBitmaskSampler.h) and GL (GlBitmaskSampler.h) bitmask samplers.

namespace sightline {

enum class MaskMode {
    Exact,   ///< per source row, the exact interval of columns (default)
    Table,   ///< the paper's Hough bitmask table (HoughMaskTable.h), nearest texel, AND of the edges' masks
};

} // namespace sightline
