#include "LightCostPanel.h"

#include <QHeaderView>
#include <QLabel>
#include <QTableWidget>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <functional>

namespace sightline::ui {

namespace {

QTableWidgetItem* number(double value)
{
    auto* item = new QTableWidgetItem;
    item->setData(Qt::DisplayRole, value);   // sorts as a number
    item->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
    item->setFlags(item->flags() & ~Qt::ItemIsEditable);
    return item;
}

QString state(const LightingCache::LightCost& cost)
{
    if (cost.rough && cost.stale)
        return QObject::tr("low resolution");
    return cost.stale ? QObject::tr("stale") : QObject::tr("fresh");
}

} // namespace

QString lightCostSummary(const std::vector<LightingCache::LightCost>& costs, std::size_t top)
{
    if (costs.empty())
        return QObject::tr("No lights in the lit view.");
    double ms = 0.0;
    std::uint64_t rays = 0;
    std::size_t stale = 0;
    std::vector<double> times;
    for (const LightingCache::LightCost& c : costs) {
        ms += c.ms;
        rays += c.rays;
        stale += c.stale ? 1 : 0;
        times.push_back(c.ms);
    }
    top = std::min(top, times.size());
    std::partial_sort(times.begin(), times.begin() + std::ptrdiff_t(top), times.end(), std::greater<>());
    double topMs = 0.0;
    for (std::size_t k = 0; k < top; ++k)
        topMs += times[k];
    return QObject::tr("%1 lights, %2 stale: %3 million shadow rays and %4 s to refresh them all; the %5 costliest take %6%")
        .arg(costs.size())
        .arg(stale)
        .arg(double(rays) * 1e-6, 0, 'f', 2)
        .arg(ms / 1000.0, 0, 'f', 2)
        .arg(top)
        .arg(ms > 0.0 ? 100.0 * topMs / ms : 0.0, 0, 'f', 0);
}

LightCostPanel::LightCostPanel(QWidget* parent) : QWidget(parent)
{
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(4, 4, 4, 4);
    summary_ = new QLabel(this);
    summary_->setWordWrap(true);
    layout->addWidget(summary_);
    table_ = new QTableWidget(0, ColumnCount, this);
    table_->setHorizontalHeaderLabels({tr("Light"), tr("Samples"), tr("Terms"), tr("Rays"), tr("ms"), tr("Age"), tr("State")});
    table_->horizontalHeaderItem(TermsColumn)->setToolTip(tr("(texel, sample) pairs the light reaches before shadowing"));
    table_->horizontalHeaderItem(RaysColumn)->setToolTip(tr("Shadow rays its last refresh cast; the rest of its terms were "
                                                             "decided whole by tile proofs (fully lit or shadowed)"));
    table_->horizontalHeaderItem(AgeColumn)->setToolTip(tr("Lit frames since it was last refreshed exactly"));
    table_->verticalHeader()->hide();
    table_->setSelectionBehavior(QAbstractItemView::SelectRows);
    table_->setSelectionMode(QAbstractItemView::SingleSelection);
    table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    table_->horizontalHeaderItem(SamplesColumn)->setToolTip(tr("Point lights it is sampled into (an area light's grid)"));
    table_->horizontalHeaderItem(TimeColumn)->setToolTip(tr("Milliseconds its last refresh took"));
    table_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
    table_->setSortingEnabled(true);
    table_->sortByColumn(TimeColumn, Qt::DescendingOrder);
    layout->addWidget(table_);
    connect(table_, &QTableWidget::cellClicked, this, [this](int row, int) {
        if (const QTableWidgetItem* item = table_->item(row, NameColumn))
            emit lightChosen(item->data(Qt::UserRole).toInt());
    });
    clear(tr("Turn on the lit view (View > Lit View, I) to see what each light costs."));
}

void LightCostPanel::clear(const QString& why)
{
    table_->setRowCount(0);
    summary_->setText(why);
}

void LightCostPanel::showCosts(const std::vector<LightingCache::LightCost>& costs, const std::vector<QString>& names)
{
    summary_->setText(lightCostSummary(costs));
    table_->setSortingEnabled(false);   // rows keep their place while they are filled
    table_->setRowCount(int(costs.size()));
    for (std::size_t l = 0; l < costs.size(); ++l) {
        const LightingCache::LightCost& c = costs[l];
        const int row = int(l);
        auto* name = new QTableWidgetItem(l < names.size() ? names[l] : QString::number(l));
        name->setData(Qt::UserRole, int(l));
        table_->setItem(row, NameColumn, name);
        table_->setItem(row, SamplesColumn, number(c.samples));
        table_->setItem(row, TermsColumn, number(double(c.terms)));
        table_->setItem(row, RaysColumn, number(double(c.rays)));
        table_->setItem(row, TimeColumn, number(std::round(c.ms * 10.0) / 10.0));
        table_->setItem(row, AgeColumn, number(double(c.age)));
        table_->setItem(row, StateColumn, new QTableWidgetItem(state(c)));
    }
    table_->setSortingEnabled(true);
}

} // namespace sightline::ui
