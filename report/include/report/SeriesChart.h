#pragma once
// A line chart of named series over one x axis, linear or logarithmic: the benchmark scripts'
// charts (lights_sweep.py: time and speed-up against the light count, time against the light cut's
// error), drawn by `sightline-cli chart` from a JSON description (docs/cli.md).

#include <filesystem>
#include <utility>
#include <vector>

#include <QString>

namespace sightline {

struct ChartAxis {
    QString title;
    bool log = false;
};

struct ChartSeries {
    QString name;
    std::vector<std::pair<double, double>> points;   ///< drawn in order
};

struct SeriesChartSpec {
    QString title;
    ChartAxis x, y;
    std::vector<ChartSeries> series;
};

/// Throws sightline::Error naming the series and point for a value that is not finite, or not
/// positive on a logarithmic axis, and for a chart without points.
void checkSeriesChart(const SeriesChartSpec& spec);

/// The chart as a PNG of `width` x `height` pixels, written atomically. Throws sightline::Error.
void writeSeriesChart(const SeriesChartSpec& spec, int width, int height, const std::filesystem::path& png);

} // namespace sightline
