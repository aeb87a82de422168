#pragma once
// The light sphere of Sattler et al. 2004 §3.4: the 6 vertices of an octahedron, refined by midpoint
// subdivision projected onto the unit sphere, k = 2 + 4^(s+1) directions at level s (6, 18, 66, 258,
// 1026). The levels are nested: the first k_s directions of every finer level are level s's, so
// the visibility bits of a coarser level are reused when refining (progressive, §3.4).
//
// Weights (ours, not the paper's): each direction j stands for its cell of the sphere, the points
// nearer to it than to the other directions of its level (a spherical Voronoi cell). For each cell
// we keep its solid angle Omega_j and its first moment m_j = integral over the cell of l dl, so
// that for a normal n whose hemisphere contains the whole cell,
//     integral over cell of (n . l) dl = n . m_j        (exactly: the integrand is linear in l).
// The cosine-weighted AO is then sum_j V_j w_j / sum_j w_j over the directions facing n, with
// w_j = n . m_j (cells the point's horizon cuts: the lobe over their upper part, aoWeight). The paper's plain counting (M_ij = n . l_j, every cell alike) is kept as
// AoWeighting::PlainCount: its cells differ in size by up to ~2x near the octahedron's vertices,
// which biases the sum.

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <glm/vec3.hpp>

namespace sightline {

inline constexpr std::array<int, 5> kAoDirectionCounts = {6, 18, 66, 258, 1026};

/// The subdivision level of `k` (0 for 6 ... 4 for 1026). Throws sightline::Error
/// "--k 100: must be one of 6, 18, 66, 258, 1026" style (prefix "k") otherwise.
int aoLevelOf(int k);

enum class AoWeighting {
    SolidAngle,   ///< cell first moments (default)
    PlainCount,   ///< the paper's M_ij = n . l_j, cells counted alike
};

struct AoDirectionSet {
    int k = 0;
    std::vector<glm::vec3> directions;   ///< unit vectors; the first k_s are level s's
    std::vector<float> solidAngle;       ///< Omega_j of direction j's cell at this level (sums to 4 pi)
    std::vector<glm::vec3> moment;       ///< m_j = integral over the cell of l dl (|m_j| ~ Omega_j)
    std::vector<float> cellRadius;       ///< sqrt(Omega_j / pi): the cell as a disk, for horizon cells
    /// The index of -l_j. The octahedron and its midpoint subdivision are centrally symmetric, so
    /// every direction's antipode is in the same level: casters answer d and -d in one pass
    /// (one projection, one depth map).
    std::vector<int> antipode;
};

/// The direction set for `k` (one of kAoDirectionCounts), computed once and cached (thread-safe).
const AoDirectionSet& aoDirections(int k);

/// Integral of max(0, c + g x) over a disk of radius r (x along the gradient), the cosine lobe
/// over a cell of solid angle pi r^2 that straddles the horizon; c is n . l_j, g = |n x l_j|.
float aoHorizonLobe(float c, float g, float r);

/// The weight of direction j for a point with unit normal n (0 for a direction not facing n).
/// Solid-angle weights: n . m_j for a cell wholly above the point's horizon (exact), and for a
/// cell the horizon cuts, the cosine lobe over its upper part, the cell taken as a disk
/// (aoHorizonLobe).
inline float aoWeight(const AoDirectionSet& set, int j, const glm::vec3& n, AoWeighting weighting)
{
    const glm::vec3& l = set.directions[std::size_t(j)];
    const float c = n.x * l.x + n.y * l.y + n.z * l.z;
    if (c <= 0.0f)
        return 0.0f;   // only directions facing the point are tested (§3.2)
    if (weighting == AoWeighting::PlainCount)
        return c;
    const float r = set.cellRadius[std::size_t(j)];
    const float g = std::sqrt(std::max(0.0f, 1.0f - c * c));
    if (c >= g * r) {
        const glm::vec3& m = set.moment[std::size_t(j)];
        const float w = n.x * m.x + n.y * m.y + n.z * m.z;
        return w > 0.0f ? w : 0.0f;
    }
    return aoHorizonLobe(c, g, r);
}

} // namespace sightline
