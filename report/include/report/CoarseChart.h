#pragma once
// The coarse-occluder chart: for each triangle count of a sweep (project's CoarseSweep.h), the rays
// the coarse level answers differently from the original (left axis, % of all rays) and its exact
// sampling time (right axis, ms), against the level's triangles (log axis); the original drawn as
// its own point, at no difference. Drawn with Qt Charts, the same chart in the editor's Coarse
// Occluder dialog and in `sightline-cli coarse --sweep --chart`.

#include <cstddef>
#include <filesystem>
#include <vector>

#include <QString>

QT_BEGIN_NAMESPACE
class QChart;
QT_END_NAMESPACE

namespace sightline {

struct CoarseChartPoint {
    std::size_t triangles = 0;   ///< the level's
    double ms = 0.0;             ///< its exact sampling
    double differing = 0.0;      ///< rays answered differently from the full meshes, % of all
};

struct CoarseChartData {
    CoarseChartPoint full;                 ///< the full meshes (differing 0)
    std::vector<CoarseChartPoint> coarse;  ///< any order
};

/// A new chart (the caller owns it, or a QChartView it is set on).
QChart* coarseChart(const CoarseChartData& data, const QString& title);

/// The chart as a PNG of 1100 x 700 pixels, written atomically. Throws sightline::Error.
void writeCoarseChart(const CoarseChartData& data, const QString& title, const std::filesystem::path& png);

} // namespace sightline
