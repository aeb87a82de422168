#include "OverlayControls.h"

#include <QAction>
#include <QActionGroup>
#include <QComboBox>
#include <QEventLoop>
#include <QLabel>
#include <QMainWindow>
#include <QMenu>
#include <QMessageBox>
#include <QProgressDialog>
#include <QSignalBlocker>
#include <QStatusBar>
#include <QTimer>
#include <QToolBar>

#include <atomic>
#include <optional>
#include <thread>

#include "AnimationImportance.h"
#include "EditorDocument.h"
#include "OverlayLegend.h"
#include "editor/Picking.h"
#include "Viewport.h"
#include "ViewportController.h"

namespace sightline::ui {

namespace {

struct KindEntry {
    OverlayKind kind;
    const char* text;
    const char* name;
};
const KindEntry kKinds[] = {
    {OverlayKind::None, QT_TRANSLATE_NOOP("OverlayControls", "No Overlay"), "overlayNone"},
    {OverlayKind::ReceiverImportance, QT_TRANSLATE_NOOP("OverlayControls", "Receiver Importance"), "overlayReceiver"},
    {OverlayKind::SourceImportance, QT_TRANSLATE_NOOP("OverlayControls", "Source Importance"), "overlaySource"},
    {OverlayKind::LightOnReceiver, QT_TRANSLATE_NOOP("OverlayControls", "Light on Receiver"), "overlayLight"},
};

struct StatisticEntry {
    ImportanceStatistic statistic;
    const char* text;
    const char* name;
};
const StatisticEntry kStatistics[] = {
    {ImportanceStatistic::Mean, QT_TRANSLATE_NOOP("OverlayControls", "Mean"), "statisticMean"},
    {ImportanceStatistic::Maximum, QT_TRANSLATE_NOOP("OverlayControls", "Maximum"), "statisticMaximum"},
    {ImportanceStatistic::EverVisible, QT_TRANSLATE_NOOP("OverlayControls", "Ever Visible"), "statisticEver"},
};

int indexOf(OverlayKind kind)
{
    for (int i = 0; i < int(std::size(kKinds)); ++i)
        if (kKinds[i].kind == kind)
            return i;
    return 0;
}

int indexOf(ImportanceStatistic statistic)
{
    for (int i = 0; i < int(std::size(kStatistics)); ++i)
        if (kStatistics[i].statistic == statistic)
            return i;
    return 0;
}

} // namespace

OverlayControls::OverlayControls(QMainWindow& window, EditorDocument& document, Viewport& viewport,
                                 ViewportController& controller, QWidget* viewportHost, QMenu* view, QToolBar* toolbar)
    : QObject(&window), window_(window), document_(document), viewport_(viewport), controller_(controller)
{
    const QString kindTip =
        tr("Paint a map on a patch (Eisemann & Décoret §8-9): the fraction of the source each receiver sample sees, the "
           "fraction of the receiver that sees each source sample, or the source's light (white, or the project's "
           "\"light\" texture) on the receiver.\nThe project's receiver_heights apply (the patch is drawn flat).");
    view->addSeparator();
    QMenu* overlayMenu = view->addMenu(tr("&Overlay"));
    overlayMenu->setToolTipsVisible(true);
    kinds_ = new QActionGroup(this);
    kindCombo_ = new QComboBox(&window);
    kindCombo_->setObjectName("overlayCombo");
    kindCombo_->setToolTip(kindTip);
    for (const KindEntry& entry : kKinds) {
        QAction* a = overlayMenu->addAction(tr(entry.text));
        a->setObjectName(entry.name);
        a->setCheckable(true);
        a->setToolTip(kindTip);
        kinds_->addAction(a);
        connect(a, &QAction::triggered, this, [this, kind = entry.kind] { setKind(kind); });
        kindCombo_->addItem(tr(entry.text));
    }
    kinds_->actions().front()->setChecked(true);
    connect(kindCombo_, &QComboBox::currentIndexChanged, this, [this](int i) {
        if (i >= 0 && i < int(std::size(kKinds)))
            setKind(kKinds[i].kind);
    });

    QMenu* statisticMenu = view->addMenu(tr("Importance &Statistic"));
    statistics_ = new QActionGroup(this);
    statisticCombo_ = new QComboBox(&window);
    statisticCombo_->setObjectName("statisticCombo");
    statisticCombo_->setToolTip(tr("How accumulated frames combine: the mean fraction, the largest, or whether a sample "
                                   "ever saw anything"));
    for (const StatisticEntry& entry : kStatistics) {
        QAction* a = statisticMenu->addAction(tr(entry.text));
        a->setObjectName(entry.name);
        a->setCheckable(true);
        statistics_->addAction(a);
        connect(a, &QAction::triggered, this, [this, statistic = entry.statistic] { setStatistic(statistic); });
        statisticCombo_->addItem(tr(entry.text));
    }
    statistics_->actions().front()->setChecked(true);
    connect(statisticCombo_, &QComboBox::currentIndexChanged, this, [this](int i) {
        if (i >= 0 && i < int(std::size(kStatistics)))
            setStatistic(kStatistics[i].statistic);
    });

    accumulate_ = view->addAction(tr("Accumulate While &Editing"));
    accumulate_->setObjectName("accumulateWhileEditing");
    accumulate_->setCheckable(true);
    accumulate_->setToolTip(tr("Add every new result to the importance overlay (§9: the impact of moving objects)"));
    connect(accumulate_, &QAction::toggled, this, &OverlayControls::setAccumulating);
    reset_ = view->addAction(tr("Rese&t Accumulation"));
    reset_->setObjectName("resetAccumulation");
    reset_->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_R));
    connect(reset_, &QAction::triggered, this, &OverlayControls::resetAccumulation);
    animation_ = view->addAction(tr("Accumulate &Animation..."));
    animation_->setObjectName("accumulateAnimation");
    animation_->setToolTip(tr("Sample every frame of the project's \"animation\" and show the accumulated importance"));
    connect(animation_, &QAction::triggered, this, &OverlayControls::accumulateAnimation);
    path_ = view->addAction(tr("Accumulate Recorded &Path..."));
    path_->setObjectName("accumulateRecordedPath");
    path_->setToolTip(tr("Sample every frame of the project's recorded path (Record menu) and show the accumulated importance"));
    connect(path_, &QAction::triggered, this, &OverlayControls::accumulateRecordedPath);

    toolbar->addSeparator();
    toolbar->addWidget(kindCombo_);
    toolbar->addWidget(statisticCombo_);
    toolbar->addAction(accumulate_);
    toolbar->addAction(reset_);

    legend_ = new OverlayLegend(viewportHost);
    readOut_ = new QLabel(&window);
    readOut_->setObjectName("overlayReadOut");
    window.statusBar()->addWidget(readOut_, 1);

    connect(&viewport_, &Viewport::overlayUpdated, this, &OverlayControls::updateWidgets);
    connect(&viewport_, &Viewport::hovered, this, [this](QPointF position) {
        hover_ = position;
        updateReadOut();
    });
    connect(&viewport_, &Viewport::hoverLeft, this, [this] {
        hover_.reset();
        updateReadOut();
    });
    connect(&controller_, &ViewportController::viewChanged, this, &OverlayControls::updateReadOut);
    updateWidgets();
}

QAction* OverlayControls::kindAction(OverlayKind kind) const { return kinds_->actions().at(indexOf(kind)); }

void OverlayControls::setKind(OverlayKind kind)
{
    viewport_.overlay().setKind(kind);
    {
        const QSignalBlocker blocker(kindCombo_);
        kindCombo_->setCurrentIndex(indexOf(kind));
    }
    kindAction(kind)->setChecked(true);
    viewport_.update();
    updateWidgets();
}

void OverlayControls::setStatistic(ImportanceStatistic statistic)
{
    viewport_.overlay().setStatistic(statistic);
    {
        const QSignalBlocker blocker(statisticCombo_);
        statisticCombo_->setCurrentIndex(indexOf(statistic));
    }
    statistics_->actions().at(indexOf(statistic))->setChecked(true);
    viewport_.update();
    updateWidgets();
}

void OverlayControls::setAccumulating(bool on)
{
    viewport_.overlay().setAccumulating(on);
    accumulate_->setChecked(on);
    viewport_.update();
    updateWidgets();
}

void OverlayControls::resetAccumulation()
{
    viewport_.overlay().resetAccumulation();
    window_.statusBar()->showMessage(tr("Accumulation reset"), 3000);
    viewport_.update();
    updateWidgets();
}

bool OverlayControls::accumulateAnimation() { return accumulate(ProjectMotion::Kind::Animation); }

bool OverlayControls::accumulateRecordedPath() { return accumulate(ProjectMotion::Kind::RecordedPath); }

bool OverlayControls::accumulate(ProjectMotion::Kind kind)
{
    const bool animated = kind == ProjectMotion::Kind::Animation;
    const QString title = animated ? tr("Accumulate Animation") : tr("Accumulate Recorded Path");
    ProjectMotion motion;
    try {
        motion = parseProjectMotion(document_.project(), kind, document_.displayName().toStdString());
    } catch (const std::exception& e) {
        QMessageBox::warning(&window_, title, QString::fromUtf8(e.what()));
        return false;
    }
    if (motion.empty() && animated) {
        QMessageBox::information(&window_, title,
                                 tr("%1 has no animation. Add an \"animation\" key whose tracks move occluders or the "
                                    "patches over frames, for example\n\n\"animation\": {\"frames\": 60, \"tracks\": "
                                    "[{\"target\": \"occluder\", \"name\": \"door\", \"keys\": [{\"frame\": 0, "
                                    "\"translate\": [0, 0, 0]}, {\"frame\": 30, \"translate\": [0, 0, 1.5]}]}]}\n\n"
                                    "then accumulate again.")
                                     .arg(document_.displayName()));
        return false;
    }
    if (motion.empty()) {
        QMessageBox::information(&window_, title,
                                 tr("%1 has no recorded path. Record one with Record > Record Video (F9): move the "
                                    "patches or occluders while it records, stop with F9, then accumulate again.")
                                     .arg(document_.displayName()));
        return false;
    }
    const ImportanceSide side = viewport_.overlay().kind() == OverlayKind::SourceImportance ? ImportanceSide::Source
                                                                                           : ImportanceSide::Receiver;
    const int frames = motion.defaultFrames();   // as `sightline-cli importance [--path]` without --frames
    const QString what = animated ? tr("the animation") : tr("the recorded path");
    QProgressDialog progress(tr("Sampling %1 frames of %2...").arg(frames).arg(what), tr("Cancel"), 0, frames, &window_);
    progress.setWindowTitle(title);
    progress.setWindowModality(Qt::WindowModal);   // no edits while the frames are sampled
    progress.setMinimumDuration(300);
    progress.setValue(0);
    // The frames are sampled on a worker thread (a 512x512 floor takes about a second a frame);
    // the event loop keeps running, so the window repaints and Cancel answers at once.
    std::atomic<int> framesSampled{0};
    std::atomic<bool> cancel{false};
    std::optional<ImportanceRunResult> result;
    std::string failure;
    QEventLoop loop;
    std::thread worker([&, input = animationInput(document_)] {
        try {
            result = ui::accumulateMotion(input, motion, frames, side, [&](int d, int) {
                framesSampled = d;
                return !cancel;
            });
        } catch (const std::bad_alloc&) {
            failure = "out of memory";
        } catch (const std::exception& e) {
            failure = e.what();
        }
        QMetaObject::invokeMethod(&loop, &QEventLoop::quit, Qt::QueuedConnection);
    });
    QTimer poll;
    poll.setInterval(50);
    connect(&poll, &QTimer::timeout, &progress, [&] {
        if (progress.wasCanceled())
            cancel = true;
        else if (framesSampled < frames)   // at the maximum the dialog would close itself before the end
            progress.setValue(framesSampled);
    });
    connect(&progress, &QProgressDialog::canceled, &progress, [&] { cancel = true; });
    poll.start();
    loop.exec();
    worker.join();
    poll.stop();
    progress.close();
    if (!result) {
        QMessageBox::warning(&window_, title,
                             tr("%1 could not be accumulated: %2").arg(animated ? tr("The animation") : tr("The recorded path"), QString::fromStdString(failure)));
        return false;
    }
    ImportanceRunResult run = std::move(*result);
    if (run.framesDone == 0)
        return false;
    const int done = run.framesDone;
    const double perFrame = run.sampleMs / std::max(run.framesSampled, 1);
    viewport_.overlay().showAnimationResult(side, std::move(run.accumulator), !animated);
    setKind(side == ImportanceSide::Source ? OverlayKind::SourceImportance : OverlayKind::ReceiverImportance);
    window_.statusBar()->showMessage(
        run.cancelled ? tr("Cancelled after %1 of %2 frames: showing those; any edit returns to the live overlay").arg(done).arg(frames)
                      : tr("Accumulated %1 frames of %2 (%3 ms a frame sampled); any edit returns to the live overlay")
                            .arg(done)
                            .arg(what)
                            .arg(perFrame, 0, 'f', 1),
        10000);
    return true;
}

QString OverlayControls::readOutAt(QPointF position) const
{
    const PatchOverlay& overlay = viewport_.overlay();
    const ObjectKind which = overlayPatch(overlay.kind());
    if (which == ObjectKind::None)
        return {};
    const Project& project = document_.project();
    const Patch& patch = which == ObjectKind::Source ? project.source : project.receiver;
    const Ray ray = pixelRay(controller_.camera(), position.x(), position.y(), controller_.width(), controller_.height());
    const auto hit = pickPatchSample(patch, ray);
    return hit ? overlay.readOut(hit->a, hit->b) : QString();
}

void OverlayControls::updateWidgets()
{
    const PatchOverlay& overlay = viewport_.overlay();
    if (isImportance(overlay.kind()) && overlay.importance()) {
        legend_->setCaption(overlay.legendCaption());
        legend_->show();
    } else if (overlay.kind() == OverlayKind::LightOnReceiver && overlay.light()) {
        // The light overlay had no legend.
        legend_->setCaption(tr("light from the source, of full (its colour scaled)"), LegendScale::Light);
        legend_->show();
    } else {
        legend_->hide();
    }
    updateReadOut();
}

void OverlayControls::updateReadOut()
{
    const PatchOverlay& overlay = viewport_.overlay();
    QString text = hover_ ? readOutAt(*hover_) : QString();
    if (text.isEmpty() && overlay.kind() == OverlayKind::LightOnReceiver && !overlay.error().empty())
        text = tr("Light: %1").arg(QString::fromStdString(overlay.error()));
    readOut_->setText(text);
}

} // namespace sightline::ui
