#include "report/MapImage.h"

#include <algorithm>
#include <cmath>

#include <QPainter>

#include "base/ColourMap.h"

namespace sightline {

namespace {
constexpr int kMargin = 16;
constexpr int kTitleHeight = 28;
constexpr int kBarWidth = 24;
constexpr int kLegendWidth = 150;   // bar, ticks, labels and the rotated caption
constexpr int kMinMapSide = 512;    // small grids are enlarged to at least this (nearest)

QRgb viridisRgb(float t)
{
    const Rgb8 c = viridis8(t);
    return qRgb(c.r, c.g, c.b);
}
} // namespace

MapImageLayout mapImageLayout(int na, int nb)
{
    MapImageLayout layout;
    const int longest = std::max(std::max(na, nb), 1);
    layout.scale = std::max(1, (kMinMapSide + longest - 1) / longest);
    layout.map = QRect(kMargin, kMargin + kTitleHeight, na * layout.scale, nb * layout.scale);
    const int barHeight = std::max(layout.map.height(), 200);
    layout.legendBar = QRect(layout.map.right() + 1 + 2 * kMargin, layout.map.top(), kBarWidth, barHeight);
    layout.size = QSize(layout.legendBar.left() + kLegendWidth, layout.map.top() + std::max(barHeight, layout.map.height()) + kMargin);
    return layout;
}

void paintLegend(QPainter& painter, const QRect& bar, const QString& caption)
{
    paintLegend(painter, bar, caption, [](float t) { return viridisRgb(t); });
}

void paintLegend(QPainter& painter, const QRect& bar, const QString& caption, QRgb (*colour)(float))
{
    for (int y = 0; y < bar.height(); ++y) {
        const float t = bar.height() > 1 ? 1.0f - float(y) / float(bar.height() - 1) : 1.0f;
        painter.setPen(QColor(colour(t)));
        painter.drawLine(bar.left(), bar.top() + y, bar.right(), bar.top() + y);
    }
    const QColor ink = painter.background().color().lightness() < 128 ? Qt::white : Qt::black;
    painter.setPen(ink);
    QFont font = painter.font();
    font.setPixelSize(12);
    painter.setFont(font);
    for (int k = 0; k <= 4; ++k) {
        const int y = bar.top() + int(std::lround((1.0 - k / 4.0) * (bar.height() - 1)));
        painter.drawLine(bar.right() + 1, y, bar.right() + 5, y);
        painter.drawText(QRect(bar.right() + 8, y - 8, 48, 16), Qt::AlignLeft | Qt::AlignVCenter,
                         QString::number(k * 25) + "%");
    }
    painter.save();
    painter.translate(bar.right() + 70, bar.center().y());
    painter.rotate(90);
    painter.drawText(QRect(-bar.height() / 2, -10, bar.height(), 20), Qt::AlignCenter, caption);
    painter.restore();
}

QImage renderMapImage(const ImportanceMap& map, const QString& title, const QString& caption)
{
    const MapImageLayout layout = mapImageLayout(map.na, map.nb);
    QImage image(layout.size, QImage::Format_RGB32);
    image.fill(Qt::white);
    // The samples, b up.
    for (int b = 0; b < map.nb; ++b) {
        for (int a = 0; a < map.na; ++a) {
            const QRgb colour = viridisRgb(map.at(a, b));
            const int x0 = layout.map.left() + a * layout.scale;
            const int y0 = layout.map.top() + (map.nb - 1 - b) * layout.scale;
            for (int y = y0; y < y0 + layout.scale; ++y) {
                auto* line = reinterpret_cast<QRgb*>(image.scanLine(y));
                std::fill(line + x0, line + x0 + layout.scale, colour);
            }
        }
    }
    QPainter painter(&image);
    painter.setBackground(Qt::white);
    QFont font = painter.font();
    font.setPixelSize(14);
    painter.setFont(font);
    painter.setPen(Qt::black);
    painter.drawText(QRect(kMargin, 4, layout.size.width() - 2 * kMargin, kTitleHeight - 4),
                     Qt::AlignLeft | Qt::AlignVCenter, title);
    paintLegend(painter, layout.legendBar, caption);
    return image;
}

QImage renderLightImage(const LightImage& light, int scale, bool intensity)
{
    scale = std::max(scale, 1);
    QImage image(light.na * scale, light.nb * scale, QImage::Format_RGB32);
    auto channel = [](float x) { return int(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f)); };
    for (int y = 0; y < image.height(); ++y) {
        const int b = light.nb - 1 - y / scale;
        auto* line = reinterpret_cast<QRgb*>(image.scanLine(y));
        for (int x = 0; x < image.width(); ++x) {
            const glm::vec3 c = light.rgb[std::size_t(b * light.na + x / scale)];
            if (intensity) {
                const int grey = channel(1.0f - (c.r + c.g + c.b) / 3.0f);
                line[x] = qRgb(grey, grey, grey);
            } else {
                line[x] = qRgb(channel(c.r), channel(c.g), channel(c.b));
            }
        }
    }
    return image;
}

} // namespace sightline
