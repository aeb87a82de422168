#pragma once
// Lighting from the visibility matrix (Sattler et al. 2004 §3.3, §5), without tracing again:
//     c_i = sum_j V_ij w_ij L_j / sum_j w_ij      over directions j facing point i,
// with w_ij the direction weight (AoDirections.h: the cell's cosine lobe by default, the paper's
// n_i . l_j with AoWeighting::PlainCount) and L_j the radiance from direction j's cell. Under a
// uniform white sky (L_j = 1) c_i is the ambient occlusion: the cosine-weighted visible fraction
// of the hemisphere, in [0, 1]; a point on an open plane gets exactly 1.
//
// Unusable points (AoPointStatus::NoFace, ZeroNormal) get NaN: reported, not shaded.

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/ao/AoDirections.h"
#include "lighting/ao/AoGeometry.h"
#include "lighting/ao/VisibilityMatrix.h"

namespace sightline {

/// Per-point AO from directions [0, k) of the matrix (k: a complete level).
std::vector<float> ambientOcclusion(const VisibilityMatrix& matrix, const AoPoints& points, int k,
                                    AoWeighting weighting = AoWeighting::SolidAngle);

/// Relighting for an editor: built once per matrix level, then shade() maps per-direction
/// radiance (an environment, rotated and exposed: AoEnvironment::directionRadiance) to per-point
/// colours. The set-up keeps, for each point, its visible directions and their normalised weights
/// (6 bytes per visible bit: about 22 MB for the bunny at k = 258), so a change of environment,
/// rotation or exposure costs one multiply-add per visible bit and never reads the matrix again.
class AoRelighter {
public:
    AoRelighter(const VisibilityMatrix& matrix, const AoPoints& points, int k, AoWeighting weighting = AoWeighting::SolidAngle);
    int k() const { return k_; }
    /// `radiance` holds k colours (direction j's cell). NaN colours for unusable points.
    std::vector<glm::vec3> shade(const std::vector<glm::vec3>& radiance, int threads = 0) const;
    /// The memory the set-up keeps (6 bytes per visible bit, 4 per point).
    std::size_t bytes() const { return start_.size() * 4 + direction_.size() * 2 + weight_.size() * 4; }

private:
    const AoPoints& points_;
    int k_;
    std::vector<std::uint32_t> start_;    ///< per point: first entry (points + 1 values)
    std::vector<std::uint16_t> direction_;
    std::vector<float> weight_;           ///< w_ij / sum_j w_ij
};

} // namespace sightline
