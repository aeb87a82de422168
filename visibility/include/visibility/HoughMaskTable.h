#pragma once
// The bitmask texture of Eisemann & Décoret §5: for every oriented line in the source's
// normalised frame, the set of source samples on its left.
//
// A line is stored by its Hough coordinates: the angle theta in [-pi, pi) of its left normal n
// and its signed distance r = dot(n, X - centre) from the source's centre, r in
// [-sqrt(2)/2, sqrt(2)/2] (the lines that cross the unit square). Texel (i, k) holds the samples
// X with dot(n, X - centre) > r for the texel-centre line. A convex backprojection is then the AND
// of its edges' masks. Lookups are nearest-texel as in the paper (theta wraps, r clamps), so
// answers are approximate where edges pass between texel-centre lines: this is the paper's
// "table mode", measured against the exact mode, not a substitute for it.

#include <cstdint>
#include <utility>
#include <vector>

#include "visibility/Patch.h"

namespace sightline {

class HoughMaskTable {
public:
    /// `width` angles by `height` distances, for the regular na x nb sample grid of `source`
    /// (positions in the normalised frame (s, t) in [0, 1]^2: ((a + 0.5) / na, (b + 0.5) / nb)).
    HoughMaskTable(int na, int nb, int width = 256, int height = 128);
    /// Throws sightline::Error unless 4 <= width <= 8192 and 2 <= height <= 8192 (the
    /// constructor's own check, for callers that validate before building, e.g. the GL sampler).
    static void checkResolution(int width, int height);
    /// Bytes the table takes for `sampleCount` source samples: one mask a texel.
    static std::uint64_t bytesFor(int sampleCount, int width, int height);
    /// Throws sightline::Error, saying the cost, when the table would take more than kMaxBytes:
    /// every resolution in range fits a small source, not every one fits 1024 samples. The
    /// constructor checks it before allocating; callers check it before loading a scene.
    static void checkBudget(int sampleCount, int width, int height);
    static constexpr std::uint64_t kMaxBytes = std::uint64_t(2) << 30;

    int width() const { return width_; }
    int height() const { return height_; }
    int wordsPerMask() const { return words_; }
    std::pair<int, int> grid() const { return {na_, nb_}; }

    /// The mask of the texel nearest to the oriented line from p to q (in (s, t)): samples on
    /// its left, i.e. cross(q - p, x - p) > 0.
    const std::uint64_t* lookup(double ps, double pt, double qs, double qt) const;
    /// Texel (i, k) directly.
    const std::uint64_t* texel(int i, int k) const { return &masks_[(std::size_t(k) * width_ + std::size_t(i)) * words_]; }
    /// The texel-centre line of texel (i, k): angle and distance.
    double theta(int i) const;
    double distance(int k) const;

private:
    int na_, nb_, width_, height_, words_;
    std::vector<std::uint64_t> masks_;
};

} // namespace sightline
