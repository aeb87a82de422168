#pragma once
// Images of per-sample maps for people: an importance map in the viridis colour map with its
// legend (CLI `importance --out`, the editor's overlay legend), and a receiver's light image (CLI
// `shadow --out`).
//
// Orientation: sample (a, b) of a patch is drawn with a to the right and b up (the patch seen
// from the side its normal points to, u right and v up), so the image's top row is b = nb - 1.

#include <string>

#include <QImage>
#include <QPainter>
#include <QRect>
#include <QString>

#include "lighting/SoftShadow.h"
#include "visibility/ImportanceMap.h"

namespace sightline {

/// Where things are in a map image (tests read pixels at these places).
struct MapImageLayout {
    int scale = 1;       ///< screen pixels per sample
    QRect map;           ///< the samples
    QRect legendBar;     ///< the colour bar: value 1 at the top row, 0 at the bottom row
    QSize size;          ///< the whole image
};
MapImageLayout mapImageLayout(int na, int nb);

/// The map in viridis, a title above and a legend (colour bar with 0%, 25%, ... 100% ticks and
/// `caption`) to the right. Needs a QGuiApplication (ensureApplication).
QImage renderMapImage(const ImportanceMap& map, const QString& title, const QString& caption);

/// Draws the colour bar with ticks and caption into `rect` (shared with the editor's legend).
void paintLegend(QPainter& painter, const QRect& bar, const QString& caption);
/// The same with the bar in `colour(t)` for t from 0 (bottom) to 1 (top): e.g. a light's grey ramp.
void paintLegend(QPainter& painter, const QRect& bar, const QString& caption, QRgb (*colour)(float));

/// The light image: one pixel per receiver sample, scaled by `scale` (nearest). With
/// `intensity` the shadow intensity 1 - L (grey, mean over channels) instead of the light.
QImage renderLightImage(const LightImage& light, int scale = 1, bool intensity = false);

} // namespace sightline
