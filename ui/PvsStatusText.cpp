#include "PvsStatusText.h"

#include <QCoreApplication>
#include <QStringList>

namespace sightline::ui {

namespace {

QString tr(const char* text, int n = -1) { return QCoreApplication::translate("PvsStatus", text, nullptr, n); }

/// "3-7, 12, 20-254" for the cells still coarse (at most `most` runs, then "...").
QString cellRuns(const std::vector<std::uint8_t>& refined, std::size_t count, int most = 4)
{
    QStringList runs;
    for (std::size_t c = 0; c < count;) {
        if (c < refined.size() && refined[c]) {
            ++c;
            continue;
        }
        std::size_t end = c;
        while (end + 1 < count && !(end + 1 < refined.size() && refined[end + 1]))
            ++end;
        if (runs.size() == most) {
            runs << QStringLiteral("...");
            break;
        }
        runs << (end == c ? QString::number(c) : QStringLiteral("%1-%2").arg(c).arg(end));
        c = end + 1;
    }
    return runs.join(QStringLiteral(", "));
}

/// The bake's progress, or the file the rows came from, with the reference's gaps and the cut-off.
QString progressText(const PvsView& view)
{
    const std::size_t cells = view.cells().size();
    QString progress;
    if (view.finished())
        progress = tr("baked");
    else if (view.coarseDone() < cells)
        progress = tr("coarse %1 of %2 cells").arg(view.coarseDone()).arg(cells);
    else
        progress = tr("refining: %1 of %2 cells refined, still coarse: %3")
                       .arg(view.refinedDone())
                       .arg(cells)
                       .arg(cellRuns(view.cellsRefined(), cells));
    if (!view.fromFile().empty())
        progress = tr("from %1").arg(QString::fromStdString(view.fromFile()));
    else if (view.finished())
        progress += view.gapsReady() ? tr(", %n gap(s) against the reference", int(view.gaps().size()))
                                     : tr(", checking against the reference...");
    if (view.cutoff() > 0.0)
        progress += tr(", cut-off %1 m").arg(view.cutoff());
    return progress;
}

} // namespace

QString pvsStatusText(const PvsView& view)
{
    if (!view.error().empty())
        return tr("PVS: %1").arg(QString::fromStdString(view.error()));
    if (view.cells().empty())
        return tr("PVS: finding view cells and objects...");
    QString progress = progressText(view);
    if (!view.overrideError().empty())
        return tr("PVS %1 · overrides ignored: %2").arg(progress, QString::fromStdString(view.overrideError()));
    const int selected = view.gapSelected();
    if (selected >= 0 && std::size_t(selected) < view.gaps().size()) {
        const pvs::Gap& gap = view.gaps()[std::size_t(selected)];
        progress += tr(" · gap %1 of %2: %3 reference ray(s) from cell %4 reach '%5' through an opening at (%6, %7, %8), clearance %9 m")
                        .arg(selected + 1)
                        .arg(view.gaps().size())
                        .arg(gap.opening.rays)
                        .arg(gap.cell)
                        .arg(gap.object < view.objects().size() ? QString::fromStdString(view.objects()[gap.object].name) : QString())
                        .arg(gap.opening.centre.x, 0, 'f', 2)
                        .arg(gap.opening.centre.y, 0, 'f', 2)
                        .arg(gap.opening.centre.z, 0, 'f', 2)
                        .arg(gap.opening.clearance, 0, 'f', 2);
    }
    const std::optional<std::size_t> cell = view.shownCell();
    if (!cell)
        return tr("PVS %1 · the camera is in no view cell").arg(progress);
    const bool coarse = !view.finished() && view.cellCoarse(*cell);
    return tr("PVS %1 · cell %2%3%4 sees %5 of %6 objects (culled ones tinted)")
        .arg(progress)
        .arg(*cell)
        .arg(view.frozen() ? tr(" (frozen)") : QString())
        .arg(coarse ? tr(" (coarse answer)") : QString())
        .arg(view.shown().cellCount() > *cell ? view.shown().visibleCount(*cell) : 0)
        .arg(view.objects().size());
}

} // namespace sightline::ui
