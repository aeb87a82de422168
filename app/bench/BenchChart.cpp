#include "bench/BenchChart.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>


#include <QApplication>
#include <QtCharts/QChart>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QScatterSeries>

#include "report/ChartImage.h"
#include "report/OffscreenApplication.h"
#include "base/Error.h"

namespace sightline::bench {


void writeChart(const std::vector<Row>& rows, const std::filesystem::path& png, ChartKind kind)
{
    const auto app = ensureApplication();
    const bool shadow = kind == ChartKind::ShadowError;
    const double kFloor = shadow ? 1e-5 : 1e-7;   // where zero error is drawn on the log axis

    auto* chart = new QChart;
    chart->setTitle(shadow ? "Soft shadows: time per evaluation against the light fraction's mean absolute error "
                             "versus a dense reference (one point per source sample count)"
                           : "Time per evaluation against error versus the raycast reference "
                             "(errors of 0 drawn at 1e-7)");
    auto* x = new QLogValueAxis;
    x->setTitleText("ms per evaluation (median)");
    x->setLabelFormat("%g");
    auto* y = new QLogValueAxis;
    y->setTitleText(shadow ? "mean absolute error of the light fraction" : "fraction of rays wrong");
    y->setLabelFormat("%g");
    chart->addAxis(x, Qt::AlignBottom);
    chart->addAxis(y, Qt::AlignLeft);

    // Per method, one colour and two series: circles for rays the method blocks but the
    // reference does not, squares for the reverse.
    static const QColor palette[] = {QColor(31, 119, 180), QColor(255, 127, 14), QColor(44, 160, 44),
                                     QColor(214, 39, 40),  QColor(148, 103, 189), QColor(140, 86, 75),
                                     QColor(227, 119, 194), QColor(127, 127, 127), QColor(188, 189, 34)};
    std::map<std::string, std::pair<QScatterSeries*, QScatterSeries*>> series;
    auto makeSeries = [&](const std::string& name, const QColor& colour, QScatterSeries::MarkerShape shape) {
        auto* s = new QScatterSeries;
        s->setName(QString::fromStdString(name));
        s->setMarkerShape(shape);
        s->setMarkerSize(shape == QScatterSeries::MarkerShapeCircle ? 10.0 : 8.0);
        s->setColor(colour);
        s->setBorderColor(colour.darker());
        chart->addSeries(s);
        s->attachAxis(x);
        s->attachAxis(y);
        return s;
    };
    double xMin = 1e300, xMax = 0.0, yMax = kFloor;
    for (const Row& r : rows) {
        auto& pair = series[r.method];
        if (shadow) {
            if (!pair.first)
                pair.first = makeSeries(r.method, palette[(series.size() - 1) % std::size(palette)],
                                        QScatterSeries::MarkerShapeCircle);
            const double ms = std::max(r.ms, 1e-3), error = std::max(r.denseMae, kFloor);
            pair.first->append(ms, error);
            xMin = std::min(xMin, ms), xMax = std::max(xMax, ms), yMax = std::max(yMax, error);
            continue;
        }
        if (!pair.first) {
            const QColor colour = palette[(series.size() - 1) % std::size(palette)];
            pair.first = makeSeries(r.method + ": blocked, reference free", colour, QScatterSeries::MarkerShapeCircle);
            pair.second = makeSeries(r.method + ": free, reference blocked", colour, QScatterSeries::MarkerShapeRectangle);
        }
        const double rays = double(std::max<std::uint64_t>(r.rays, 1));
        const double ms = std::max(r.ms, 1e-3);
        const double blocked = std::max(double(r.wronglyBlocked) / rays, kFloor);
        const double freed = std::max(double(r.wronglyFree) / rays, kFloor);
        pair.first->append(ms, blocked);
        pair.second->append(ms, freed);
        xMin = std::min(xMin, ms), xMax = std::max(xMax, ms), yMax = std::max({yMax, blocked, freed});
    }
    if (rows.empty())
        xMin = 1.0, xMax = 10.0;
    x->setRange(xMin / 2.0, xMax * 2.0);
    y->setRange(kFloor / 2.0, std::max(shadow ? 1e-1 : 1e-3, yMax * 2.0));

    chart->legend()->setAlignment(Qt::AlignRight);
    saveChartPng(chart, QSize(1100, 700), png);
}

} // namespace sightline::bench
