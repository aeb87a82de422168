#include "OccluderAssistant.h"

#include <chrono>

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QLocale>
#include <QPushButton>
#include <QSlider>
#include <QTimer>
#include <QVBoxLayout>

#include "EditorDocument.h"
#include "Viewport.h"
#include "ViewportController.h"
#include "plugins/SceneFormats.h"
#include "project/SuggestedOccluder.h"
#include "base/Error.h"

namespace sightline::ui {

namespace {

/// Changes within this many milliseconds (a drag's frames, a slider's steps) make one request.
constexpr int kGatherMs = 60;

QString count(std::uint64_t n)
{
    return QLocale().toString(qulonglong(n));
}

bool samePatch(const Patch& a, const Patch& b)
{
    return a.corner == b.corner && a.u == b.u && a.v == b.v && a.na == b.na && a.nb == b.nb;
}

} // namespace

OccluderAssistant::OccluderAssistant(EditorDocument& document, Viewport& viewport, ViewportController& controller,
                                     QWidget* parent)
    : QWidget(parent),
      document_(document),
      viewport_(viewport),
      controller_(controller),
      worker_(&OccluderAssistant::work, [this](std::uint64_t generation, Outcome outcome) {
          QMetaObject::invokeMethod(this, [this, generation, outcome = std::move(outcome)]() mutable {
              take(generation, std::move(outcome));
          }, Qt::QueuedConnection);
      })
{
    createControls();
    layOutControls();
    connectControls();
    depthValue_->setText(tr("%1 %").arg(depth_->value()));
    withdraw(tr("Open the assistant to see the occluder that cuts this view."));
    setMinimumHeight(sizeHint().height());   // a dock below another keeps every row readable
}

void OccluderAssistant::createControls()
{
    depth_ = new QSlider(Qt::Horizontal, this);
    depth_->setObjectName("suggestDepth");
    depth_->setRange(5, 95);
    depth_->setValue(50);
    depth_->setToolTip(tr("Where the occluder's plane lies: the share of the way from the source's centre to the "
                          "receiver's (perpendicular to that line)"));
    depthValue_ = new QLabel(this);
    share_ = new QDoubleSpinBox(this);
    share_->setObjectName("suggestShare");
    share_->setRange(1.0, 100.0);
    share_->setDecimals(1);
    share_->setValue(100.0);
    share_->setSuffix(tr(" %"));
    share_->setToolTip(tr("The share of the unblocked rays the occluder must block: below 100 % it may leave the "
                          "costliest stragglers, for a smaller occluder"));
    weighted_ = new QCheckBox(tr("of the light"), this);
    weighted_->setObjectName("suggestWeighted");
    weighted_->setToolTip(tr("Below 100 %: the share of the light the unblocked rays carry (each weighed by its source "
                             "sample's colour in the project's light texture), not of their number"));
    shape_ = new QComboBox(this);
    shape_->setObjectName("suggestShape");
    shape_->addItem(tr("Convex polygon"));
    shape_->addItem(tr("Rectangle"));
    summary_ = new QLabel(this);
    summary_->setObjectName("suggestSummary");
    summary_->setWordWrap(true);
    summary_->setTextFormat(Qt::RichText);
    summary_->setMinimumWidth(220);
    summary_->setMinimumHeight(4 * summary_->fontMetrics().lineSpacing());   // the longest summary, wrapped
    add_ = new QPushButton(tr("Add Occluder (Enter)"), this);
    add_->setObjectName("suggestAdd");
    add_->setEnabled(false);
    gapList_ = new QListWidget(this);
    gapList_->setObjectName("suggestGaps");
    gapList_->setToolTip(tr("Where the unblocked rays pass closest to the level: a click (or N, Shift+N) looks "
                            "through the opening from the source"));
    gapList_->setMinimumHeight(5 * gapList_->fontMetrics().lineSpacing());

    pickSurface_ = new QPushButton(tr("Pick Surface"), this);
    pickSurface_->setObjectName("suggestPickSurface");
    pickSurface_->setToolTip(tr("Put the occluder on a surface the rays cross instead, such as a doorway's frame: click "
                                "it in the view (moving the slider puts it between the patches again)"));
}

void OccluderAssistant::layOutControls()
{
    auto* depthRow = new QHBoxLayout;
    depthRow->addWidget(depth_, 1);
    depthRow->addWidget(depthValue_);
    depthRow->addWidget(pickSurface_);
    auto* form = new QFormLayout;
    form->addRow(tr("Plane at"), depthRow);
    auto* shareRow = new QHBoxLayout;
    shareRow->addWidget(share_, 1);
    shareRow->addWidget(weighted_);
    form->addRow(tr("Block"), shareRow);
    form->addRow(tr("Shape"), shape_);
    auto* layout = new QVBoxLayout(this);
    layout->addLayout(form);
    layout->addWidget(summary_);
    layout->addWidget(add_);
    layout->addWidget(new QLabel(tr("Openings the view leaks through:"), this));
    layout->addWidget(gapList_, 1);
}

void OccluderAssistant::connectControls()
{
    gather_ = new QTimer(this);
    gather_->setSingleShot(true);
    gather_->setInterval(kGatherMs);
    connect(gather_, &QTimer::timeout, this, &OccluderAssistant::requestNow);
    const auto changed = [this] {
        depthValue_->setText(tr("%1 %").arg(depth_->value()));
        refresh();
    };
    connect(depth_, &QSlider::valueChanged, this, [this] { setSurface(std::nullopt); });
    connect(pickSurface_, &QPushButton::clicked, this, [this] { controller_.setTool(Tool::PickSurface); });
    connect(&controller_, &ViewportController::surfacePicked, this, [this](glm::dvec3 point, glm::dvec3 normal) {
        if (active_)
            setSurface(suggest::PickedSurface{point, normal});
    });
    connect(share_, &QDoubleSpinBox::valueChanged, this, changed);
    connect(weighted_, &QCheckBox::toggled, this, changed);
    connect(shape_, &QComboBox::currentIndexChanged, this, changed);
    connect(gapList_, &QListWidget::itemClicked, this, [this](QListWidgetItem* item) { showGap(std::size_t(gapList_->row(item))); });
    // The level's triangles, shared with the worker until an edit changes what blocks rays.
    connect(&document_, &EditorDocument::changed, this, [this](unsigned changes) {
        if (changes & (OccludersChanged | SceneFileChanged | DocumentReset | CoarseOccludersChanged))
            triangles_.reset();
    });
    connect(add_, &QPushButton::clicked, this, [this] {
        QString message;
        addSuggestion(&message);
        emit added(message);
    });
}

OccluderAssistant::~OccluderAssistant() = default;

void OccluderAssistant::setActive(bool active)
{
    if (active == active_)
        return;
    active_ = active;
    if (active)
        refresh();
    else {
        withdraw(tr("Hidden."));
        listGaps({});
    }
}

void OccluderAssistant::setSurface(std::optional<suggest::PickedSurface> surface)
{
    surface_ = surface;
    depthValue_->setText(surface_ ? tr("on the surface") : tr("%1 %").arg(depth_->value()));
    refresh();
}

suggest::Request OccluderAssistant::settings() const
{
    suggest::Request request;
    request.depth = depth_->value() / 100.0;
    request.surface = surface_;
    if (weighted_->isChecked())
        request.sourceWeights = lightWeights();
    request.share = share_->value() / 100.0;
    request.shape = shape_->currentIndex() == 1 ? suggest::Shape::Rect : suggest::Shape::Convex;
    return request;
}

std::vector<double> OccluderAssistant::lightWeights() const
{
    // Read again only when the light or the source's grid changed: the texture is a file.
    const Project& project = document_.project();
    const auto light = project.extra.find("light");
    const std::string key = (light != project.extra.end() ? light->dump() : std::string()) + "|" +
                            std::to_string(project.source.na) + "x" + std::to_string(project.source.nb) + "|" +
                            project.folder.string();
    if (key != lightWeightsKey_) {
        lightWeights_ = sourceLightWeights(project);   // throws for a light that cannot be read
        lightWeightsKey_ = key;
    }
    return lightWeights_;
}

void OccluderAssistant::refresh()
{
    if (active_)
        gather_->start();
}

void OccluderAssistant::requestNow()
{
    if (!active_)
        return;
    const VisibilityResult& result = viewport_.visibility();
    if (!viewport_.visibilityIsCurrent()) {
        withdraw(tr("Waiting for the view to be sampled..."));
        return;
    }
    if (!result.valid) {
        withdraw(tr("This pair cannot be sampled: %1").arg(QString::fromStdString(result.error)));
        return;
    }
    Job job;
    job.source = result.source;
    job.receiver = result.receiver;
    const ReceiverHeights& heights = viewport_.receiverHeights();
    job.heights = std::make_shared<const ReceiverHeights>(heights);
    if (promised_) {   // the first answer after an add: did the view keep the promise?
        const std::uint64_t left = result.unblocked();
        emit added(left <= *promised_ ? tr("The view now leaves %1 rays (promised at most %2)").arg(count(left)).arg(count(*promised_))
                                      : tr("Warning: the view leaves %1 rays, more than the %2 promised (please report this pair)")
                                            .arg(count(left))
                                            .arg(count(*promised_)));
        promised_.reset();
    }
    if (!triangles_)
        triangles_ = std::make_shared<const WorldTriangles>(worldTriangles(document_.rayScene()));
    // The openings depend on the map and the level only: a new depth, share or shape keeps them.
    job.findGaps = !(gapsMap_ && gapsTriangles_ == triangles_ && samePatch(gapsSource_, result.source) &&
                     samePatch(gapsReceiver_, result.receiver) && *gapsMap_ == result.map);
    gapsSource_ = result.source;
    gapsReceiver_ = result.receiver;
    job.map = job.findGaps ? std::make_shared<const HiddenSampleMap>(result.map) : gapsMap_;
    gapsMap_ = job.map;
    gapsTriangles_ = triangles_;
    job.triangles = triangles_;
    try {
        job.request = settings();
    } catch (const Error& e) {
        withdraw(tr("The light cannot weigh the rays: %1").arg(QString::fromStdString(e.what())));
        return;
    }
    worker_.request(++generation_, std::move(job));
}

OccluderAssistant::Outcome OccluderAssistant::work(const Job& job)
{
    Outcome outcome;
    const auto start = std::chrono::steady_clock::now();
    try {
        outcome.suggestion = suggest::suggestOccluder(job.source, job.receiver, *job.heights, *job.map, job.request);
    } catch (const std::exception& e) {
        outcome.error = e.what();
    }
    outcome.gapsFound = job.findGaps;
    try {
        if (job.findGaps)
            outcome.gaps = suggest::findViewGaps(*job.triangles, job.source, job.receiver, *job.heights, *job.map);
    } catch (const std::exception& e) {
        outcome.gapsError = e.what();
    }
    outcome.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return outcome;
}

void OccluderAssistant::take(std::uint64_t generation, Outcome outcome)
{
    if (generation != generation_ || !active_)
        return;   // a later request is on its way, or the assistant was closed
    if (outcome.gapsFound) {
        listGaps(std::move(outcome.gaps));
        if (!outcome.gapsError.empty())
            gapList_->addItem(QString::fromStdString(outcome.gapsError));
    }
    if (!outcome.suggestion) {
        withdraw(QString::fromStdString(outcome.error));
        return;
    }
    suggestion_ = std::move(outcome.suggestion);
    shownGeneration_ = generation;
    const suggest::Suggestion& s = *suggestion_;
    std::vector<glm::vec3> ghost;
    for (const glm::dvec3& p : s.worldPolygon())
        ghost.emplace_back(p);
    viewport_.setOccluderGhost(std::move(ghost));
    const QString shape = s.shape == suggest::Shape::Rect ? tr("Rectangle %1 x %2 m")
                                                                 .arg(2.0 * s.rect.halfWidth, 0, 'f', 2)
                                                                 .arg(2.0 * s.rect.halfHeight, 0, 'f', 2)
                                                           : tr("Convex polygon, %1 corners").arg(s.polygon.size());
    const QString light = s.weighted ? tr("<br>and at least %1 % of the light they carry")
                                           .arg(100.0 * s.lightEnclosed / std::max(s.lightBefore, 1e-300), 0, 'f', 1)
                                     : QString();
    summary_->setText(tr("<b>%1: %2 m²</b><br>blocks at least %3 of the %4 unblocked rays, leaves at most %5%8"
                         "<br><span style='color:gray'>%6 of them cross the plane; %7 ms</span>")
                          .arg(shape)
                          .arg(s.area, 0, 'f', 3)
                          .arg(count(s.required))
                          .arg(count(s.unblockedBefore))
                          .arg(count(s.promised))
                          .arg(count(s.crossing))
                          .arg(outcome.ms, 0, 'f', 0)
                          .arg(light));
    add_->setEnabled(true);
    emit suggestionChanged();
}

void OccluderAssistant::listGaps(std::vector<suggest::Opening> gaps)
{
    gaps_ = std::move(gaps);
    gapList_->clear();
    if (!viewport_.selectedRays().empty())
        viewport_.setSelectedRays({}, 0, 0);   // they belonged to the openings of an earlier answer
    std::uint64_t all = 0;
    for (const suggest::Opening& gap : gaps_)
        all += gap.rays;
    for (std::size_t k = 0; k < gaps_.size(); ++k) {
        const suggest::Opening& gap = gaps_[k];
        const glm::dvec3 size = gap.max - gap.min;
        gapList_->addItem(tr("%1. %2 rays (%3 %), %4 x %5 x %6 m")
                              .arg(k + 1)
                              .arg(count(gap.rays))
                              .arg(100.0 * double(gap.rays) / double(std::max<std::uint64_t>(all, 1)), 0, 'f', 1)
                              .arg(size.x, 0, 'f', 2)
                              .arg(size.y, 0, 'f', 2)
                              .arg(size.z, 0, 'f', 2));
    }
}

void OccluderAssistant::showGap(std::size_t k)
{
    if (k >= gaps_.size())
        return;
    const suggest::Opening& gap = gaps_[k];
    const glm::dvec3 from = document_.project().source.centre();
    const glm::dvec3 along = gap.centre - from;
    if (!(glm::length(along) > 0.0))
        return;
    const double radius = std::max(0.5, 0.75 * glm::length(gap.max - gap.min));
    controller_.setCamera(lookThrough(from, glm::normalize(along), gap.centre, radius));
    gapList_->setCurrentRow(int(k));
    // Its rays (a spread of up to kOpeningRaySample) stand out from the others.
    const Project& project = document_.project();
    viewport_.setSelectedRays(gap.raySample, project.source.na * project.source.nb, project.receiver.na * project.receiver.nb);
}

bool OccluderAssistant::stepGap(int step)
{
    const int n = int(gaps_.size());
    if (n == 0)
        return false;
    const int at = gapList_->currentRow();
    showGap(std::size_t(((at < 0 ? (step > 0 ? -1 : 0) : at) + step + n) % n));
    return true;
}

void OccluderAssistant::withdraw(const QString& why)
{
    ++generation_;   // an answer still on its way is for what was withdrawn: dropped
    const bool had = suggestion_.has_value();
    suggestion_.reset();
    summary_->setText(why.toHtmlEscaped());
    add_->setEnabled(false);
    viewport_.setOccluderGhost({});
    if (had)
        emit suggestionChanged();
}

bool OccluderAssistant::addSuggestion(QString* message)
{
    if (!suggestion_) {
        *message = tr("No suggestion to add: open Create > Suggest Occluder on a view with unblocked rays");
        return false;
    }
    if (gather_->isActive() || shownGeneration_ != generation_) {
        *message = tr("The suggestion is being updated for the new settings: add it once it is shown");
        return false;
    }
    const suggest::Suggestion s = *suggestion_;
    if (s.shape == suggest::Shape::Convex && document_.filePath().empty()) {
        *message = tr("Save the project first: a convex occluder is a mesh file beside it (or choose Rectangle)");
        return false;
    }
    const Project& project = document_.project();
    const std::string name = unusedOccluderName(project, "suggested occluder");
    OccluderSpec spec;
    try {
        // A convex polygon is a mesh of its own: a new file beside the project, never an old one.
        const std::filesystem::path file = s.shape == suggest::Shape::Convex
                                               ? nextNumberedFile(project.folder, document_.filePath().stem().string() + "-occluder", ".glb")
                                               : std::filesystem::path();
        PlacedSuggestion placed = placeSuggestion(s, name, file.filename().string());
        if (!file.empty())
            saveScene(placed.mesh, file);
        spec = std::move(placed.spec);
        document_.addOccluder(spec);
    } catch (const std::exception& e) {
        *message = tr("Could not add the suggested occluder: %1").arg(QString::fromUtf8(e.what()));
        return false;
    }
    // Added once: the next suggestion is for the view with it in, and that view's first answer is
    // checked against the promise (requestNow).
    withdraw(tr("Added: waiting for the view to be sampled again..."));
    promised_ = s.promised;
    *message = tr("Added %1 (%2 m²): it leaves at most %3 of %4 rays (Ctrl+Z removes it)")
                   .arg(QString::fromStdString(spec.name))
                   .arg(s.area, 0, 'f', 3)
                   .arg(count(s.promised))
                   .arg(count(s.unblockedBefore));
    return true;
}

} // namespace sightline::ui
