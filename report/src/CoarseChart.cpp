#include "report/CoarseChart.h"

#include <algorithm>

#include <QPen>
#include <QtCharts/QChart>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QScatterSeries>
#include <QtCharts/QValueAxis>

#include "report/ChartImage.h"
#include "report/OffscreenApplication.h"

namespace sightline {

namespace {

const QColor kDisagreeing(214, 39, 40);   // the disagreement view's false-blocked red
const QColor kTime(31, 119, 180);

template <class Series>
Series* addSeries(QChart* chart, const QString& name, const QColor& colour, QAbstractAxis* x, QAbstractAxis* y)
{
    auto* series = new Series;
    series->setName(name);
    series->setColor(colour);
    chart->addSeries(series);
    series->attachAxis(x);
    series->attachAxis(y);
    return series;
}

} // namespace

QChart* coarseChart(const CoarseChartData& data, const QString& title)
{
    auto* chart = new QChart;
    chart->setTitle(title);
    auto* x = new QLogValueAxis;
    x->setTitleText(QStringLiteral("triangles in the level"));
    x->setLabelFormat("%g");
    auto* differ = new QValueAxis;
    differ->setTitleText(QStringLiteral("rays answered differently (% of all)"));
    differ->setLabelFormat("%.2f");
    auto* time = new QValueAxis;
    time->setTitleText(QStringLiteral("exact sampling (ms)"));
    time->setLabelFormat("%.1f");
    chart->addAxis(x, Qt::AlignBottom);
    chart->addAxis(differ, Qt::AlignLeft);
    chart->addAxis(time, Qt::AlignRight);

    auto* differLine = addSeries<QLineSeries>(chart, QStringLiteral("rays answered differently"), kDisagreeing, x, differ);
    auto* timeLine = addSeries<QLineSeries>(chart, QStringLiteral("sampling time"), kTime, x, time);
    auto* original = addSeries<QScatterSeries>(chart, QStringLiteral("the full meshes"), Qt::black, x, time);
    original->setMarkerSize(11.0);
    for (QLineSeries* line : {differLine, timeLine}) {
        line->setPointsVisible(true);
        line->setMarkerSize(7.0);
        QPen pen = line->pen();
        pen.setWidthF(2.0);
        line->setPen(pen);
    }

    // Left to right: the coarsest level first, the full meshes last (at no difference).
    std::vector<CoarseChartPoint> points = data.coarse;
    std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.triangles < b.triangles; });
    const double full = double(std::max<std::size_t>(data.full.triangles, 1));
    double xMin = full, maxDiffer = 0.0, maxMs = data.full.ms;
    for (const CoarseChartPoint& p : points) {
        const double t = double(std::max<std::size_t>(p.triangles, 1));
        differLine->append(t, p.differing);
        timeLine->append(t, p.ms);
        xMin = std::min(xMin, t), maxDiffer = std::max(maxDiffer, p.differing), maxMs = std::max(maxMs, p.ms);
    }
    differLine->append(full, 0.0);
    timeLine->append(full, data.full.ms);
    original->append(full, data.full.ms);
    x->setRange(xMin / 1.5, full * 1.5);
    differ->setRange(0.0, std::max(maxDiffer * 1.15, 0.1));
    time->setRange(0.0, std::max(maxMs * 1.15, 0.1));
    differ->applyNiceNumbers();
    time->applyNiceNumbers();
    chart->legend()->setAlignment(Qt::AlignBottom);
    return chart;
}

void writeCoarseChart(const CoarseChartData& data, const QString& title, const std::filesystem::path& png)
{
    const auto app = ensureApplication();
    saveChartPng(coarseChart(data, title), QSize(1100, 700), png);
}

} // namespace sightline
