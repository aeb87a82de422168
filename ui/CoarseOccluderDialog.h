#pragma once
// Edit > Coarse Occluder: which stand-in answers a level object's rays ("model no more than a
// scene needs"; project/CoarseOccluders.h). The full mesh, the closest coarse mesh at a triangle
// count, or the conservative inner occluder of a closed mesh. The object is still drawn, lit and
// baked from its full mesh. Measure charts, for the current pair, what each triangle count costs
// and saves (project/CoarseSweep.h on a worker thread, report/CoarseChart.h); a click on a point
// takes its count. Fewest Triangles finds, on the worker, the fewest triangles whose stand-in
// answers at most the given share of the pair's rays differently (fitCoarseToTolerance).

#include <atomic>
#include <cstddef>
#include <memory>
#include <optional>
#include <thread>

#include <QDialog>

#include "project/CoarseOccluders.h"
#include "project/CoarseSweep.h"

class QChartView;
class QComboBox;
class QDoubleSpinBox;
class QFormLayout;
class QLabel;
class QPushButton;
class QSpinBox;

namespace sightline::ui {

/// What Measure samples: the level with its full meshes, the object, the pair.
struct CoarseMeasureInput {
    std::shared_ptr<const Scene> scene;
    std::size_t instance = 0;
    Patch source, receiver;
    std::shared_ptr<const ReceiverHeights> heights;   ///< may be null
};

class CoarseOccluderDialog : public QDialog {
    Q_OBJECT
public:
    /// `triangles`: the object's own; `closed`: whether an inner stand-in applies; `current`: its
    /// stand-in now, if any (the dialog starts there).
    CoarseOccluderDialog(const QString& objectName, std::size_t triangles, bool closed,
                         const std::optional<CoarseOccluder>& current, CoarseMeasureInput measure,
                         QWidget* parent = nullptr);
    ~CoarseOccluderDialog() override;

    /// The choice: a stand-in (its instance unset), or none for the full mesh.
    std::optional<CoarseOccluder> choice() const;

    QComboBox* kindField() const { return kind_; }
    QSpinBox* trianglesField() const { return triangles_; }
    QSpinBox* resolutionField() const { return resolution_; }
    QPushButton* measureButton() const { return measure_; }
    QDoubleSpinBox* toleranceField() const { return tolerance_; }
    QPushButton* fitButton() const { return fit_; }
    /// The last Fewest Triangles search (none before one ends).
    const std::optional<CoarseToleranceFit>& toleranceFit() const { return fitResult_; }
    QChartView* chartView() const { return chartView_; }
    /// The sweep measured so far (empty before Measure).
    const CoarseSweep& sweep() const { return sweep_; }
    /// Takes the count of the sweep's point nearest `triangles` (what a click on the chart does).
    void pickPoint(double triangles);

signals:
    /// A point of the sweep arrived (`finished`: the last).
    void measured(bool finished);
    /// A Fewest Triangles search ended.
    void fitted();

private:
    /// The Stand-in, Triangles and Resolution rows, starting at `current` (or the closest mesh).
    void addStandInRows(QFormLayout* form, std::size_t triangles, bool closed, const std::optional<CoarseOccluder>& current);
    /// The Measure button, its status and the sweep's chart (hidden until a sweep).
    void addMeasureRows(QFormLayout* form);
    /// The Within row (the tolerance and Fewest Triangles) and the search's status.
    void addFitRows(QFormLayout* form);
    void showKind();
    void startMeasuring();
    void showSweep(const CoarseSweep& sweep, bool finished, const QString& error);
    void stopMeasuring();
    void startFitting();
    void showFit(const std::optional<CoarseToleranceFit>& fit, const QString& error);
    void setBusy(bool busy);

    QComboBox* kind_ = nullptr;
    QSpinBox* triangles_ = nullptr;
    QSpinBox* resolution_ = nullptr;
    QLabel* explanation_ = nullptr;
    QPushButton* measure_ = nullptr;
    QLabel* measureStatus_ = nullptr;
    QDoubleSpinBox* tolerance_ = nullptr;
    QPushButton* fit_ = nullptr;
    QLabel* fitStatus_ = nullptr;
    std::optional<CoarseToleranceFit> fitResult_;
    QChartView* chartView_ = nullptr;
    CoarseMeasureInput input_;
    std::size_t triangleCount_ = 0;
    CoarseSweep sweep_;
    std::thread worker_;
    std::atomic<bool> cancel_{false};
};

} // namespace sightline::ui
