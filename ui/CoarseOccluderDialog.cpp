#include "CoarseOccluderDialog.h"

#include <algorithm>
#include <cmath>

#include <QComboBox>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLocale>
#include <QPushButton>
#include <QSpinBox>
#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtCharts/QXYSeries>

#include "CoarseSweepChart.h"
#include "base/Error.h"

namespace sightline::ui {

namespace {
enum Choice { FullMesh = 0, Closest = 1, Inner = 2 };
}

CoarseOccluderDialog::CoarseOccluderDialog(const QString& objectName, std::size_t triangles, bool closed,
                                           const std::optional<CoarseOccluder>& current, CoarseMeasureInput measure,
                                           QWidget* parent)
    : QDialog(parent), input_(std::move(measure)), triangleCount_(triangles)
{
    setWindowTitle(tr("Coarse Occluder"));
    auto* form = new QFormLayout(this);
    auto* what = new QLabel(tr("<b>%1</b>: %2 triangles. Its stand-in answers the rays between the patches; the view "
                               "still draws, lights and bakes the full mesh.")
                                .arg(objectName.toHtmlEscaped(), QLocale().toString(qulonglong(triangles))),
                            this);
    what->setWordWrap(true);
    form->addRow(what);

    addStandInRows(form, triangles, closed, current);
    addMeasureRows(form);
    addFitRows(form);
    if (triangles <= 8 || !input_.scene)
        setBusy(true);   // nothing to measure

    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, this);
    connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
    connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
    form->addRow(buttons);
    setMinimumWidth(460);
}

void CoarseOccluderDialog::addStandInRows(QFormLayout* form, std::size_t triangles, bool closed,
                                          const std::optional<CoarseOccluder>& current)
{
    kind_ = new QComboBox(this);
    kind_->setObjectName("coarseKind");
    kind_->addItem(tr("Full mesh (no stand-in)"));
    kind_->addItem(tr("Closest coarse mesh (fewest differences)"));
    kind_->addItem(tr("Inner occluder (never blocks a ray the mesh lets through)"));
    if (!closed) {
        // An inner stand-in is proved for closed meshes only (visibility/InnerOccluder.h).
        kind_->setItemData(Inner, 0, Qt::UserRole - 1);
        kind_->setItemData(Inner, tr("Needs a closed, outward mesh"), Qt::ToolTipRole);
    }
    form->addRow(tr("Stand-in"), kind_);

    triangles_ = new QSpinBox(this);
    triangles_->setObjectName("coarseTriangles");
    triangles_->setRange(4, 100'000'000);
    triangles_->setGroupSeparatorShown(true);
    triangles_->setValue(int(std::clamp<std::size_t>(triangles / 10, 4, 5000)));
    triangles_->setToolTip(tr("At most this many triangles; the decimater stops short rather than move the surface "
                              "more than 1% of the mesh's size"));
    form->addRow(tr("Triangles"), triangles_);

    resolution_ = new QSpinBox(this);
    resolution_->setObjectName("coarseResolution");
    resolution_->setRange(4, 256);
    resolution_->setValue(32);
    resolution_->setSuffix(tr(" voxels"));
    resolution_->setToolTip(tr("Voxels along the mesh's longest side: more hugs the surface closer"));
    form->addRow(tr("Resolution"), resolution_);

    explanation_ = new QLabel(this);
    explanation_->setWordWrap(true);
    explanation_->setEnabled(false);
    form->addRow(explanation_);

    if (current) {
        kind_->setCurrentIndex(current->kind == CoarseKind::Closest ? Closest : Inner);
        if (current->kind == CoarseKind::Closest)
            triangles_->setValue(int(std::min<std::size_t>(current->triangles, 100'000'000)));
        else
            resolution_->setValue(current->resolution);
    } else {
        kind_->setCurrentIndex(Closest);
    }
    connect(kind_, &QComboBox::currentIndexChanged, this, [this] { showKind(); });
    showKind();
}

void CoarseOccluderDialog::addMeasureRows(QFormLayout* form)
{
    measure_ = new QPushButton(tr("Measure"), this);
    measure_->setObjectName("coarseMeasure");
    measure_->setToolTip(tr("Sample the current pair exactly with the full mesh and with the closest stand-in at "
                            "several triangle counts: what each costs and saves"));
    measureStatus_ = new QLabel(tr("What each triangle count costs and saves on this pair"), this);
    measureStatus_->setWordWrap(true);
    form->addRow(measure_, measureStatus_);
    chartView_ = new QChartView(this);
    chartView_->setObjectName("coarseChart");
    chartView_->setRenderHint(QPainter::Antialiasing);
    chartView_->setMinimumSize(620, 360);
    chartView_->hide();
    form->addRow(chartView_);
    connect(measure_, &QPushButton::clicked, this, [this] { startMeasuring(); });
}

void CoarseOccluderDialog::addFitRows(QFormLayout* form)
{
    auto* fitRow = new QHBoxLayout;
    tolerance_ = new QDoubleSpinBox(this);
    tolerance_->setObjectName("coarseTolerance");
    tolerance_->setRange(0.0, 100.0);
    tolerance_->setDecimals(3);
    tolerance_->setSingleStep(0.05);
    tolerance_->setValue(0.1);
    tolerance_->setSuffix(tr(" % of the rays"));
    tolerance_->setToolTip(tr("The share of the pair's rays the stand-in may answer differently from the full mesh"));
    fit_ = new QPushButton(tr("Fewest Triangles"), this);
    fit_->setObjectName("coarseFit");
    fit_->setToolTip(tr("Find the fewest triangles whose stand-in stays within the share, each count checked by the "
                        "exact sampler on the current pair"));
    fitRow->addWidget(tolerance_);
    fitRow->addWidget(fit_);
    form->addRow(tr("Within"), fitRow);
    fitStatus_ = new QLabel(this);
    fitStatus_->setWordWrap(true);
    form->addRow(fitStatus_);
    connect(fit_, &QPushButton::clicked, this, [this] { startFitting(); });
}

void CoarseOccluderDialog::showKind()
{
    const int kind = kind_->currentIndex();
    triangles_->setEnabled(kind == Closest);
    resolution_->setEnabled(kind == Inner);
    explanation_->setText(kind == FullMesh ? tr("Every triangle of the object blocks rays, as in the file.")
                          : kind == Closest
                              ? tr("OpenMesh's decimater (quadric error), fitted back onto the surface: may block a few rays the mesh lets through and "
                                   "the reverse. View > Disagreement With Exact shows which.")
                              : tr("Faces around a region strictly inside the mesh: the view can only become more "
                                   "visible, never less (safe for culling)."));
}

CoarseOccluderDialog::~CoarseOccluderDialog() { stopMeasuring(); }

void CoarseOccluderDialog::stopMeasuring()
{
    cancel_ = true;
    if (worker_.joinable())
        worker_.join();
    cancel_ = false;
}

void CoarseOccluderDialog::setBusy(bool busy)
{
    measure_->setEnabled(!busy);
    fit_->setEnabled(!busy);
}

void CoarseOccluderDialog::startFitting()
{
    stopMeasuring();
    CoarseToleranceRequest request;
    request.tolerance = tolerance_->value() / 100.0;
    request.instance = input_.instance;
    request.cancel = &cancel_;
    setBusy(true);
    fitStatus_->setText(tr("Finding the fewest triangles within %1% of the rays...").arg(tolerance_->value()));
    worker_ = std::thread([this, request, input = input_] {
        QString error;
        std::optional<CoarseToleranceFit> fit;
        try {
            fit = fitCoarseToTolerance(*input.scene, input.source, input.receiver, input.heights.get(), request);
        } catch (const std::exception& e) {
            error = QString::fromStdString(e.what());
        }
        QMetaObject::invokeMethod(this, [this, fit, error] { showFit(fit, error); }, Qt::QueuedConnection);
    });
}

void CoarseOccluderDialog::showFit(const std::optional<CoarseToleranceFit>& fit, const QString& error)
{
    if (worker_.joinable())
        worker_.join();
    setBusy(false);
    fitResult_ = fit;
    if (!error.isEmpty())
        fitStatus_->setText(tr("Cannot search: %1").arg(error));
    else if (!fit->chosen)
        fitStatus_->setText(tr("Only the full mesh stays within %1% of the rays (%2 counts tried).")
                                .arg(tolerance_->value())
                                .arg(fit->tried.points.size()));
    else {
        kind_->setCurrentIndex(Closest);
        triangles_->setValue(int(std::min<std::size_t>(fit->chosen->asked, 100'000'000)));
        fitStatus_->setText(tr("%1 triangles: %2% of the rays differ (%3 counts tried).")
                                .arg(QLocale().toString(qulonglong(fit->chosen->asked)))
                                .arg(100.0 * double(fit->chosen->disagreeing()) / double(std::max<std::uint64_t>(fit->tried.rays, 1)), 0, 'f', 3)
                                .arg(fit->tried.points.size()));
    }
    emit fitted();
}

void CoarseOccluderDialog::startMeasuring()
{
    stopMeasuring();
    CoarseSweepRequest request;
    request.counts = defaultSweepCounts(triangleCount_);
    request.instance = input_.instance;
    request.repeat = 1;   // a chart to choose by; `sightline-cli coarse --sweep` times medians
    setBusy(true);
    measureStatus_->setText(tr("Measuring %1 triangle counts...").arg(request.counts.size()));
    // The worker posts each point to this dialog; posts to a closed dialog are dropped with it,
    // and closing waits for the sampling under way (cancel_ stops the next).
    request.progress = [this](const CoarseSweep& sweep) {
        QMetaObject::invokeMethod(this, [this, sweep] { showSweep(sweep, false, {}); }, Qt::QueuedConnection);
        return !cancel_.load();
    };
    worker_ = std::thread([this, request, input = input_] {
        QString error;
        CoarseSweep sweep;
        try {
            sweep = sweepCoarseOccluders(*input.scene, input.source, input.receiver, input.heights.get(), request);
        } catch (const std::exception& e) {
            error = QString::fromStdString(e.what());
        }
        QMetaObject::invokeMethod(this, [this, sweep, error] { showSweep(sweep, true, error); }, Qt::QueuedConnection);
    });
}

void CoarseOccluderDialog::showSweep(const CoarseSweep& sweep, bool finished, const QString& error)
{
    if (!error.isEmpty()) {
        measureStatus_->setText(tr("Cannot measure: %1").arg(error));
        setBusy(false);
        emit measured(true);
        return;
    }
    if (finished) {
        if (worker_.joinable())
            worker_.join();
        setBusy(false);
    }
    if (sweep.points.empty())
        return;
    sweep_ = sweep;
    QChart* chart = coarseChart(ui::coarseChartData(sweep), tr("The current pair: rays answered differently and sampling time"));
    for (QAbstractSeries* series : chart->series())
        if (auto* xy = qobject_cast<QXYSeries*>(series))
            connect(xy, &QXYSeries::clicked, this, [this](const QPointF& point) { pickPoint(point.x()); });
    QChart* old = chartView_->chart();
    chartView_->setChart(chart);
    delete old;
    chartView_->show();
    const CoarseSweepPoint& last = sweep.points.back();
    measureStatus_->setText(
        tr("%1 of %2 counts: at %3 triangles %4% of the rays differ, %5x the full mesh's speed.%6")
            .arg(sweep.points.size())
            .arg(defaultSweepCounts(triangleCount_).size())
            .arg(QLocale().toString(qulonglong(last.triangles)))
            .arg(100.0 * double(last.disagreeing()) / double(std::max<std::uint64_t>(sweep.rays, 1)), 0, 'f', 3)
            .arg(sweep.ms / std::max(last.ms, 1e-9), 0, 'f', 1)
            .arg(finished ? tr(" Click a point to take its count.") : QString()));
    emit measured(finished);
}

void CoarseOccluderDialog::pickPoint(double triangles)
{
    if (sweep_.points.empty())
        return;
    const auto nearest = std::min_element(sweep_.points.begin(), sweep_.points.end(), [&](const auto& a, const auto& b) {
        return std::abs(std::log(double(a.triangles) / triangles)) < std::abs(std::log(double(b.triangles) / triangles));
    });
    kind_->setCurrentIndex(Closest);
    triangles_->setValue(int(std::min<std::size_t>(nearest->asked, 100'000'000)));
}

std::optional<CoarseOccluder> CoarseOccluderDialog::choice() const
{
    const int kind = kind_->currentIndex();
    if (kind == FullMesh)
        return std::nullopt;
    CoarseOccluder spec;
    spec.kind = kind == Closest ? CoarseKind::Closest : CoarseKind::Inner;
    spec.triangles = std::size_t(triangles_->value());
    spec.resolution = resolution_->value();
    return spec;
}

} // namespace sightline::ui
