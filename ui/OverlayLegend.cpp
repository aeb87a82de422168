#include "OverlayLegend.h"

#include <algorithm>
#include <cmath>

#include <QEvent>
#include <QFontMetrics>
#include <QPainter>
#include <QWindow>

#include "report/MapImage.h"

namespace sightline::ui {

namespace {
constexpr int kMargin = 10;        // inside the panel
constexpr int kBarWidth = 24;
constexpr int kLabels = 82;        // ticks, labels and the rotated caption right of the bar (paintLegend)
constexpr int kCorner = 8;         // from the viewport's corner
constexpr int kMinBarHeight = 160;
const QColor kPanel(34, 36, 40);

QFont captionFont()
{
    QFont font;
    font.setPixelSize(12);   // what paintLegend draws with
    return font;
}

QRect barIn(const QRect& panel) { return {panel.left() + kMargin, panel.top() + kMargin, kBarWidth, panel.height() - 2 * kMargin}; }
} // namespace

QSize legendPanelSize(const QString& caption, int maxHeight)
{
    // The caption runs along the bar: the bar is as long as the caption, within limits.
    const int captionLength = QFontMetrics(captionFont()).horizontalAdvance(caption) + 16;
    const int bar = std::max(kMinBarHeight, captionLength);
    return {kMargin + kBarWidth + kLabels + kMargin, std::max(std::min(bar + 2 * kMargin, maxHeight), 60)};
}

void paintLegendPanel(QPainter& painter, const QRect& panel, const QString& caption, LegendScale scale)
{
    painter.save();
    painter.fillRect(panel, kPanel);
    painter.setPen(QColor(80, 84, 92));
    painter.drawRect(panel.adjusted(0, 0, -1, -1));
    painter.setBackground(kPanel);   // paintLegend picks light ink on a dark background
    painter.setFont(captionFont());
    if (scale == LegendScale::Light)
        paintLegend(painter, barIn(panel), caption, [](float t) {
            const int v = int(std::lround(std::clamp(t, 0.0f, 1.0f) * 255.0f));
            return qRgb(v, v, v);
        });
    else
        paintLegend(painter, barIn(panel), caption);
    painter.restore();
}

OverlayLegend::OverlayLegend(QWidget* host, Corner corner) : QWidget(host), host_(host), corner_(corner)
{
    setObjectName(corner == Corner::TopRight ? "overlayLegend" : "keyLegend");
    setAttribute(Qt::WA_NativeWindow);   // above the native 3D view (see the header)
    setAttribute(Qt::WA_TransparentForMouseEvents);
    host_->installEventFilter(this);
    hide();
}

void OverlayLegend::setCaption(const QString& caption, LegendScale scale)
{
    entries_.clear();
    caption_ = caption;
    scale_ = scale;
    setToolTip(caption);
    place();
    update();
}

void OverlayLegend::setEntries(const QString& title, std::vector<LegendEntry> entries)
{
    caption_ = title;
    entries_ = std::move(entries);
    setToolTip(title);
    place();
    update();
}

QRect OverlayLegend::colourBar() const { return barIn(rect()); }

namespace {
constexpr int kSwatch = 12, kLine = 18;
}

QSize OverlayLegend::keySize() const
{
    const QFontMetrics metrics(captionFont());
    int width = metrics.horizontalAdvance(caption_);
    for (const LegendEntry& entry : entries_)
        width = std::max(width, kSwatch + 6 + metrics.horizontalAdvance(entry.text));
    return {width + 2 * kMargin, 2 * kMargin + kLine * int(entries_.size() + 1)};
}

void OverlayLegend::paintKey(QPainter& painter) const
{
    const QRect panel = rect();
    painter.fillRect(panel, kPanel);
    painter.setPen(QColor(80, 84, 92));
    painter.drawRect(panel.adjusted(0, 0, -1, -1));
    painter.setFont(captionFont());
    painter.setPen(QColor(235, 235, 235));
    painter.drawText(QRect(kMargin, kMargin, panel.width() - 2 * kMargin, kLine), Qt::AlignLeft | Qt::AlignVCenter, caption_);
    for (std::size_t k = 0; k < entries_.size(); ++k) {
        const int top = kMargin + kLine * int(k + 1);
        painter.fillRect(QRect(kMargin, top + (kLine - kSwatch) / 2, kSwatch, kSwatch), entries_[k].colour);
        painter.setPen(QColor(220, 220, 220));
        painter.drawText(QRect(kMargin + kSwatch + 6, top, panel.width() - 2 * kMargin - kSwatch - 6, kLine),
                         Qt::AlignLeft | Qt::AlignVCenter, entries_[k].text);
    }
}

void OverlayLegend::paintEvent(QPaintEvent*)
{
    QPainter painter(this);
    if (!entries_.empty())
        paintKey(painter);
    else
        paintLegendPanel(painter, rect(), caption_, scale_);
}

bool OverlayLegend::eventFilter(QObject* watched, QEvent* event)
{
    if (watched == host_ && (event->type() == QEvent::Resize || event->type() == QEvent::Show))
        place();
    return QWidget::eventFilter(watched, event);
}

void OverlayLegend::place()
{
    const QSize size = entries_.empty() ? legendPanelSize(caption_, host_->height() - 2 * kCorner) : keySize();
    setGeometry(corner_ == Corner::TopRight ? host_->width() - size.width() - kCorner : kCorner, kCorner, size.width(),
                size.height());
    raiseAboveView();
}

void OverlayLegend::raiseAboveView()
{
    // QWidget::raise() does nothing for the only child widget of the container, but the embedded
    // view is a sibling native window: raise the legend's own native window.
    if (QWindow* window = windowHandle())
        window->raise();
}

void OverlayLegend::showEvent(QShowEvent* event)
{
    QWidget::showEvent(event);
    raiseAboveView();
}

} // namespace sightline::ui
