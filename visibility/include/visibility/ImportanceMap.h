#pragma once
// Importance maps (Eisemann & Décoret 2007, §9): which parts of a patch see the most of the other.
//
// From one hidden-samples map (HiddenSampleMap.h) come two maps:
//   - over the receiver: for receiver sample j, the fraction of source samples it sees,
//     1 - |B_j| / S (the soft-shadow light fraction of §8 for a white light);
//   - over the source: for source sample i, the fraction of receiver samples that see it (the
//     inverted view of §6: "which part of the receiver a source point sees").
// Values are in [0, 1], one float per sample, sample (a, b) at index b * na + a (docs/design.md §2),
// which is also the row-major (nb, na) layout of the .npy export.
//
// Accumulation over time (§9, "allows to investigate the impact of moving objects"): while
// objects move, each new map is folded into a running mean, a running maximum and an "ever
// visible" flag per sample.

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "visibility/HiddenSampleMap.h"

namespace sightline {

struct ImportanceMap {
    int na = 0;
    int nb = 0;
    std::vector<float> values;   ///< na * nb fractions in [0, 1], index b * na + a

    ImportanceMap() = default;
    ImportanceMap(int na_, int nb_, float fill = 0.0f)
        : na(na_), nb(nb_), values(std::size_t(na_) * std::size_t(nb_), fill) {}

    int sampleCount() const { return na * nb; }
    float at(int a, int b) const { return values[std::size_t(b) * std::size_t(na) + std::size_t(a)]; }
    /// Mean over all samples (0 for an empty map).
    double mean() const;
    bool sameGrid(const ImportanceMap& other) const { return na == other.na && nb == other.nb; }
};

/// Per receiver sample, the fraction of source samples it sees.
ImportanceMap receiverImportance(const HiddenSampleMap& map);

/// Per source sample (grid sourceNa x sourceNb, sourceNa * sourceNb == map.sourceCount()), the
/// fraction of receiver samples that see it.
ImportanceMap sourceImportance(const HiddenSampleMap& map, int sourceNa, int sourceNb);

/// Which patch an importance map is over.
enum class ImportanceSide { Receiver, Source };

/// The accumulated statistics of an importance map over frames.
enum class ImportanceStatistic {
    Mean,          ///< running mean of the per-frame fractions
    Maximum,       ///< the largest fraction any frame gave
    EverVisible,   ///< 1 where any frame saw anything, else 0
};
/// "mean", "max", "ever" (what the CLI and project files use); throws sightline::Error otherwise.
ImportanceStatistic parseImportanceStatistic(std::string_view name);
const char* toString(ImportanceStatistic statistic);

/// Folds per-frame importance maps into the statistics above. Every frame must have the grid of
/// the first one after a reset (a grid change is a new accumulation: the caller resets).
class ImportanceAccumulator {
public:
    /// Adds one frame. Throws std::invalid_argument when the grid differs from the frames so far.
    void add(const ImportanceMap& frame);
    /// Forgets every frame.
    void reset();

    int frames() const { return frames_; }
    bool empty() const { return frames_ == 0; }
    int na() const { return na_; }
    int nb() const { return nb_; }

    /// The statistic as a map (an empty map when no frame was added).
    ImportanceMap result(ImportanceStatistic statistic) const;

private:
    int frames_ = 0;
    int na_ = 0, nb_ = 0;
    std::vector<double> sum_;   // double: a long accumulation of floats would drift
    std::vector<float> maximum_;
    std::vector<std::uint8_t> ever_;
};

} // namespace sightline
