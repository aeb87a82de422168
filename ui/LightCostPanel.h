#pragma once
// The lit view's cost panel: per light what its last refresh cost (samples, lit terms, shadow
// rays, time), how many frames ago it was refreshed exactly and whether the view shows it fresh,
// stale or from the low-resolution pass; a line above sums them and names the share of the
// costliest few. Sorted by any column (time, costliest first, by default); a click selects the
// light.

#include <QWidget>

#include <vector>

#include "lighting/LightingCache.h"

class QLabel;
class QTableWidget;

namespace sightline::ui {

class LightCostPanel : public QWidget {
    Q_OBJECT
public:
    explicit LightCostPanel(QWidget* parent = nullptr);

    /// Shows `costs` (one per light, in the project's order) under `names`.
    void showCosts(const std::vector<LightingCache::LightCost>& costs, const std::vector<QString>& names);
    /// Empties the table and says why (e.g. the lit view is off).
    void clear(const QString& why);

    QTableWidget* table() const { return table_; }
    QLabel* summary() const { return summary_; }
    enum Column { NameColumn, SamplesColumn, TermsColumn, RaysColumn, TimeColumn, AgeColumn, StateColumn, ColumnCount };

signals:
    void lightChosen(int index);

private:
    QLabel* summary_ = nullptr;
    QTableWidget* table_ = nullptr;
};

/// The summary line: lights, rays and time in all, and the share of the time the costliest
/// `top` lights take.
QString lightCostSummary(const std::vector<LightingCache::LightCost>& costs, std::size_t top = 5);

} // namespace sightline::ui
