#pragma once
// The importance overlay's legend (viridis colour bar, 0-100% ticks, a caption saying what the
// values are and over how many frames): report/MapImage's paintLegend, the legend of the CLI's
// importance images, on a small dark panel. A widget in the viewport's top-right corner, and the
// same panel painted onto headless screenshots. Or a key of a few colours with a line each (the
// disagreement view's), in the top-left corner.
//
// The 3D view is a native window inside a window container, which paints over ordinary sibling
// and child widgets; the legend is a native widget itself, raised above the view, so that it is
// seen over it.

#include <vector>

#include <QColor>
#include <QWidget>

class QPainter;

namespace sightline::ui {

/// The panel's size for `caption` (the rotated caption sets the bar's height), at most
/// `maxHeight` tall.
QSize legendPanelSize(const QString& caption, int maxHeight);
/// What the bar shows: viridis (importance) or the light's linear grey ramp (0 dark, 1 full light;
/// a coloured light scales its own colour the same way).
enum class LegendScale { Viridis, Light };
/// Paints the panel into `panel` (background, colour bar, ticks, caption).
void paintLegendPanel(QPainter& painter, const QRect& panel, const QString& caption, LegendScale scale = LegendScale::Viridis);

/// One line of a key: a colour and what it means.
struct LegendEntry {
    QColor colour;
    QString text;
};

class OverlayLegend : public QWidget {
    Q_OBJECT
public:
    enum class Corner { TopRight, TopLeft };
    /// Lives in a corner of `host` (the viewport's container); hidden until shown.
    explicit OverlayLegend(QWidget* host, Corner corner = Corner::TopRight);

    void setCaption(const QString& caption, LegendScale scale = LegendScale::Viridis);
    /// A key instead of the colour bar: `title` above one swatch and line per entry.
    void setEntries(const QString& title, std::vector<LegendEntry> entries);
    const std::vector<LegendEntry>& entries() const { return entries_; }
    LegendScale scale() const { return scale_; }
    const QString& caption() const { return caption_; }
    /// Where the colour bar is, in widget coordinates (value 1 at its top row, 0 at its bottom).
    QRect colourBar() const;

protected:
    void paintEvent(QPaintEvent* event) override;
    void showEvent(QShowEvent* event) override;
    bool eventFilter(QObject* watched, QEvent* event) override;

private:
    void place();
    void raiseAboveView();

    QSize keySize() const;
    void paintKey(QPainter& painter) const;

    QWidget* host_;
    Corner corner_;
    std::vector<LegendEntry> entries_;   ///< a key (then caption_ is its title), else the bar
    QString caption_;
    LegendScale scale_ = LegendScale::Viridis;
};

} // namespace sightline::ui
