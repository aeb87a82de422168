#include "report/SeriesChart.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <QPen>
#include <QtCharts/QChart>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QValueAxis>

#include "report/ChartImage.h"
#include "report/OffscreenApplication.h"
#include "base/Error.h"

namespace sightline {

namespace {

// Tableau's ten, as the other charts use them: distinct in colour and in grey.
const QColor kColours[] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {255, 127, 14}, {148, 103, 189},
                           {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};

QAbstractAxis* makeAxis(const ChartAxis& axis, double lo, double hi)
{
    if (axis.log) {
        auto* a = new QLogValueAxis;
        a->setTitleText(axis.title);
        a->setLabelFormat("%g");
        // Powers of ten label a range of less than a decade or two once at most: use powers of two.
        a->setBase(hi / lo < 30.0 ? 2.0 : 10.0);
        a->setMinorTickCount(a->base() == 10.0 ? 8 : 0);
        a->setRange(lo / 1.3, hi * 1.3);
        return a;
    }
    auto* a = new QValueAxis;
    a->setTitleText(axis.title);
    const double pad = hi > lo ? 0.05 * (hi - lo) : std::max(1.0, std::abs(hi) * 0.1);
    // Figures that cannot be negative (times, errors, ratios) keep the axis at 0 and above.
    a->setRange(lo >= 0.0 ? std::max(0.0, lo - pad) : lo - pad, hi + pad);
    a->applyNiceNumbers();
    return a;
}

} // namespace

void checkSeriesChart(const SeriesChartSpec& spec)
{
    std::size_t points = 0;
    for (const ChartSeries& s : spec.series) {
        for (std::size_t k = 0; k < s.points.size(); ++k) {
            const auto [x, y] = s.points[k];
            const std::string where = "series \"" + s.name.toStdString() + "\", point " + std::to_string(k);
            if (!std::isfinite(x) || !std::isfinite(y))
                throw Error(where + ": not a finite number");
            if ((spec.x.log && x <= 0.0) || (spec.y.log && y <= 0.0))
                throw Error(where + ": a logarithmic axis needs values above 0");
        }
        points += s.points.size();
    }
    if (points == 0)
        throw Error("the chart has no points");
}

void writeSeriesChart(const SeriesChartSpec& spec, int width, int height, const std::filesystem::path& png)
{
    checkSeriesChart(spec);
    const auto app = ensureApplication();
    double xLo = std::numeric_limits<double>::max(), xHi = -xLo, yLo = xLo, yHi = -xLo;
    for (const ChartSeries& s : spec.series)
        for (const auto& [x, y] : s.points) {
            xLo = std::min(xLo, x), xHi = std::max(xHi, x);
            yLo = std::min(yLo, y), yHi = std::max(yHi, y);
        }
    auto* chart = new QChart;
    chart->setTitle(spec.title);
    QAbstractAxis* x = makeAxis(spec.x, xLo, xHi);
    QAbstractAxis* y = makeAxis(spec.y, yLo, yHi);
    chart->addAxis(x, Qt::AlignBottom);
    chart->addAxis(y, Qt::AlignLeft);
    std::size_t k = 0;
    for (const ChartSeries& s : spec.series) {
        auto* line = new QLineSeries;
        line->setName(s.name);
        QPen pen(kColours[k++ % std::size(kColours)]);
        pen.setWidthF(2.0);
        line->setPen(pen);
        line->setPointsVisible(true);
        line->setMarkerSize(7.0);
        for (const auto& [px, py] : s.points)
            line->append(px, py);
        chart->addSeries(line);
        line->attachAxis(x);
        line->attachAxis(y);
    }
    chart->legend()->setAlignment(Qt::AlignBottom);
    saveChartPng(chart, QSize(width, height), png);
}

} // namespace sightline
