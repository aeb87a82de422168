#pragma once
// The level's surfaces as a light-map atlas for the editor's previews (AoPreview.h, LitPreview.h):
// which triangles get texels, where each triangle corner lands in the atlas, and an atlas image
// filled from one value per texel point. Plain C++ (no Qt).

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "lighting/ao/AoGeometry.h"
#include "lighting/ao/AoTexels.h"
#include "visibility/Scene.h"

namespace sightline::ui {

/// The surfaces that get texels: the world triangles of the instances asked for (all when none
/// is named), as occluders of their own for aoTexelPoints (three vertices a triangle), with each
/// one's world-triangle index.
struct TexelSurfaces {
    AoOccluders surfaces;
    std::vector<std::uint32_t> worldTriangle;
};
TexelSurfaces texelSurfaces(const WorldTriangles& triangles, const std::vector<std::uint32_t>& instances);

/// Each corner's uv in the atlas, from its position in its triangle's tile frame (AoTexels.h),
/// so the mapping does not depend on the corner order of a mirrored instance; -1 for triangles
/// without texels.
std::vector<glm::vec2> cornerUvs(const WorldTriangles& triangles, const TexelSurfaces& sampled, const AoTexelLayout& layout);

/// The atlas image (width x height, row 0 at the top) of one colour per texel point; texels of no
/// point, and non-finite colours, are `blank`. The one-texel gutter around each tile takes its
/// nearest texel: filtering at a triangle's edge would otherwise mix in the blank (bright or dark
/// lines along edges).
std::vector<glm::vec3> atlasImage(const AoTexelLayout& layout, const std::vector<glm::vec3>& colour, glm::vec3 blank);

/// No texel: the pixel takes the blank colour.
inline constexpr std::uint32_t kBlankPixel = UINT32_MAX;
/// Per pixel of the atlas (width x height, row 0 at the top) the texel point whose colour
/// atlasImage puts there, gutters included; kBlankPixel where it puts the blank. For a preview
/// that fills the same layout many times: gatherAtlas is then one read a pixel.
std::vector<std::uint32_t> atlasSources(const AoTexelLayout& layout);
/// atlasImage's picture from atlasSources' table (entries may also index a shorter list of
/// values: kBlankPixel or any index past `values` is blank).
std::vector<glm::vec3> gatherAtlas(const std::vector<std::uint32_t>& sources, const std::vector<glm::vec3>& values, glm::vec3 blank);
/// The same into `map` (its memory reused where large enough).
void gatherAtlas(const std::vector<std::uint32_t>& sources, const std::vector<glm::vec3>& values, glm::vec3 blank,
                 std::vector<glm::vec3>& map);

/// Lowers the calling thread's scheduling priority (Linux gives each thread its own nice value),
/// so that a preview's worker yields to the GUI thread and the live rays.
void lowerThisThreadsPriority();

} // namespace sightline::ui
