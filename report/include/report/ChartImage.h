#pragma once
// A Qt Charts chart saved as a PNG without a window: what the CLI's charts (bench, coarse) share.

#include <filesystem>

#include <QSize>

QT_BEGIN_NAMESPACE
class QChart;
QT_END_NAMESPACE

namespace sightline {

/// Takes `chart` (deleted here), lays it out at `size` pixels on white and writes it atomically.
/// Needs a QApplication (ensureApplication). Throws sightline::Error if the file cannot be written.
void saveChartPng(QChart* chart, const QSize& size, const std::filesystem::path& png);

} // namespace sightline
