#pragma once
// Barczak 2006's low-resolution pass with edge refinement, for a light being dragged: its field
// is computed exactly at every `stride`-th texel of each light-map tile (the coarse points), and
// the texels between four coarse points are interpolated from them where the four agree, and
// computed exactly where they do not (a shadow edge, a light's reach ending). Tiles too small for
// a block (most of a furnished level's texels lie on triangles a texel or two across: a chair's
// rungs, a plant's leaves) are lowered in resolution in space instead: their texels in one cube two
// texels across and facing the same way share one coarse point, which the others copy. The pass is a
// preview: LightingCache keeps the light stale after it and refreshes it exactly once it stops
// moving, so the view still ends exact.

#include <array>
#include <cstdint>
#include <vector>

#include <span>

#include "lighting/DirectLight.h"
#include "lighting/ao/AoTexels.h"

namespace sightline {

struct LowResolutionPlan {
    /// Points computed exactly by every pass: the blocks' corners, and every point no block covers
    /// (tiles narrower than a block, texels a degenerate neighbour leaves without four corners).
    std::vector<std::uint32_t> coarse;
    struct Fine {
        std::uint32_t point = 0;
        std::array<float, 4> weights{};   ///< bilinear, over the block's corners
    };
    struct Block {
        std::array<std::uint32_t, 4> corners{};   ///< points, all in `coarse`
        std::uint32_t first = 0, count = 0;       ///< its points in `fine`
    };
    std::vector<Block> blocks;
    std::vector<Fine> fine;
    std::size_t points = 0;   ///< of the whole set; every point is in `coarse` or in one block
};

/// Corners disagree when their values differ by more than this share of the largest, or when one
/// is zero and another is not: the block is computed exactly.
inline constexpr float kRefineRelative = 0.2f;

/// The plan over the texels of `layout`: `pointOfTexel` maps a texel (AoPoints order) to its
/// shading point, SIZE_MAX where the texel has none. `stride` >= 2 texels between coarse points.
/// With `points` (the shading points, indexed as pointOfTexel's values), the texels of tiles too
/// small for a block (no wider or no taller than one texel, or no more than `stride` each way) are
/// grouped by cube of side stride / layout.density and by the axis their normal leans to most
/// (six ways): the first of a group is coarse, the rest copy it (a block of four equal corners).
/// Without, each of them is coarse.
LowResolutionPlan lowResolutionPlan(const AoTexelLayout& layout, const std::vector<std::size_t>& pointOfTexel, int stride,
                                    std::span<const ShadingPoint> points = {});

/// Whether a block with these corner values is computed exactly (kRefineRelative).
bool cornersDisagree(const std::array<float, 4>& values);

} // namespace sightline
