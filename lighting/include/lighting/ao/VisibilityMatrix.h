#pragma once
// The visibility matrix of Sattler et al. 2004 §3.2, one bit per sample point i and light
// direction j: set when the ray from point i's (offset) origin towards direction j leaves the
// scene unblocked. The paper stores n_i . l_j for visible entries; we store the bit and apply the
// weights when shading (AoShading.h), so one matrix serves every weighting, environment and
// rotation (§5) without tracing again.
//
// Layout: point-major, `words()` 64-bit words per point, direction j at bit j % 64 of word j / 64.
// Directions not facing the point (n_i . l_j <= 0) are never tested and stay 0.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sightline {

class VisibilityMatrix {
public:
    VisibilityMatrix() = default;
    /// All bits clear, room for `capacity` directions (the target k of a progressive run).
    VisibilityMatrix(std::size_t points, int capacity)
        : points_(points), capacity_(capacity), words_((capacity + 63) / 64), bits_(points * std::size_t(words_), 0)
    {
    }

    std::size_t points() const { return points_; }
    int capacity() const { return capacity_; }
    int words() const { return words_; }

    bool visible(std::size_t i, int j) const { return (row(i)[j >> 6] >> (j & 63)) & 1u; }
    void setVisible(std::size_t i, int j) { row(i)[j >> 6] |= std::uint64_t(1) << (j & 63); }

    const std::uint64_t* row(std::size_t i) const { return bits_.data() + i * std::size_t(words_); }
    std::uint64_t* row(std::size_t i) { return bits_.data() + i * std::size_t(words_); }

    /// Set bits among directions [0, k) of every point.
    std::uint64_t visibleCount(int k) const;

private:
    std::size_t points_ = 0;
    int capacity_ = 0;
    int words_ = 0;
    std::vector<std::uint64_t> bits_;
};

} // namespace sightline
