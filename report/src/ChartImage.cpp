#include "report/ChartImage.h"

#include <QCoreApplication>
#include <QGraphicsLayout>
#include <QGraphicsScene>
#include <QImage>
#include <QPainter>
#include <QtCharts/QChart>

#include "report/PngFile.h"

namespace sightline {

void saveChartPng(QChart* chart, const QSize& size, const std::filesystem::path& png)
{
    // The chart item is rendered directly: no widget is ever shown, so it is given its geometry
    // and its layout settles before painting.
    QGraphicsScene scene;
    scene.addItem(chart);   // owns the chart
    const QRectF area(QPointF(0, 0), QSizeF(size));
    chart->setGeometry(area);
    QCoreApplication::processEvents();
    chart->layout()->activate();
    QImage image(size, QImage::Format_ARGB32);
    image.fill(Qt::white);
    QPainter painter(&image);
    painter.setRenderHint(QPainter::Antialiasing);
    scene.render(&painter, area, area);
    painter.end();
    savePng(image, png);   // atomic, like every other output
}

} // namespace sightline
