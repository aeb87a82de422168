#pragma once
// The bench chart: time per evaluation (x) against error versus the reference (y), both on log
// axes, one series per method, drawn with Qt Charts and saved as PNG. Runs headless (Qt's
// offscreen platform when there is no display).

#include <filesystem>
#include <vector>

#include "bench/Bench.h"

namespace sightline::bench {

enum class ChartKind {
    RayErrors,     ///< y: fraction of rays wrong against the reference, per direction
    ShadowError,   ///< y: the light fraction's mean absolute error against the dense reference
};

/// Errors of zero (the reference itself, exact runs) are drawn on the axis floor, labelled so.
/// Throws sightline::Error if the image cannot be written.
void writeChart(const std::vector<Row>& rows, const std::filesystem::path& png, ChartKind kind = ChartKind::RayErrors);

} // namespace sightline::bench
