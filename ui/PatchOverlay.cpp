#include "PatchOverlay.h"

#include <QObject>

#include "project/LightingSetup.h"
#include "base/Error.h"

namespace sightline::ui {

OverlayKind parseOverlayKind(std::string_view name)
{
    if (name == "none")
        return OverlayKind::None;
    if (name == "receiver")
        return OverlayKind::ReceiverImportance;
    if (name == "source")
        return OverlayKind::SourceImportance;
    if (name == "light")
        return OverlayKind::LightOnReceiver;
    throw Error("unknown overlay '" + std::string(name) + "' (use none, receiver, source or light)");
}

const char* toString(OverlayKind kind)
{
    switch (kind) {
    case OverlayKind::None: return "none";
    case OverlayKind::ReceiverImportance: return "receiver";
    case OverlayKind::SourceImportance: return "source";
    case OverlayKind::LightOnReceiver: return "light";
    }
    return "?";
}

ObjectKind overlayPatch(OverlayKind kind)
{
    switch (kind) {
    case OverlayKind::ReceiverImportance:
    case OverlayKind::LightOnReceiver: return ObjectKind::Receiver;
    case OverlayKind::SourceImportance: return ObjectKind::Source;
    case OverlayKind::None: break;
    }
    return ObjectKind::None;
}

bool isImportance(OverlayKind kind) { return kind == OverlayKind::ReceiverImportance || kind == OverlayKind::SourceImportance; }

namespace {
/// "37 frames", "1 animation frame", "312 recorded-path frames".
QString frameCount(int frames, bool animation, bool recordedPath = false)
{
    const QString unit = animation && recordedPath ? (frames == 1 ? QObject::tr("recorded-path frame") : QObject::tr("recorded-path frames"))
                         : animation ? (frames == 1 ? QObject::tr("animation frame") : QObject::tr("animation frames"))
                                     : (frames == 1 ? QObject::tr("frame") : QObject::tr("frames"));
    return QString::number(frames) + ' ' + unit;
}
} // namespace

QString statisticPhrase(ImportanceStatistic statistic, int frames, bool animation, bool recordedPath)
{
    const QString count = frameCount(frames, animation, recordedPath);
    switch (statistic) {
    case ImportanceStatistic::Mean: return QObject::tr("mean of %1").arg(count);
    case ImportanceStatistic::Maximum: return QObject::tr("maximum of %1").arg(count);
    case ImportanceStatistic::EverVisible: return QObject::tr("ever visible in %1").arg(count);
    }
    return {};
}

void PatchOverlay::setKind(OverlayKind kind)
{
    if (kind == kind_)
        return;
    kind_ = kind;
    refresh();
}

void PatchOverlay::setStatistic(ImportanceStatistic statistic)
{
    if (statistic == statistic_)
        return;
    statistic_ = statistic;
    refresh();
}

void PatchOverlay::setAccumulating(bool on)
{
    if (on == accumulating_)
        return;
    accumulating_ = on;
    seedPending_ = on && receiverFrames_.empty();
    refresh();
}

bool PatchOverlay::needsLive() const
{
    switch (kind_) {
    case OverlayKind::ReceiverImportance:
        if (!fresh_.receiver)
            return true;
        break;
    case OverlayKind::SourceImportance:
        if (!fresh_.source)
            return true;
        break;
    case OverlayKind::LightOnReceiver:
        if (!fresh_.light)
            return true;
        break;
    case OverlayKind::None: break;
    }
    return seedPending_;
}

void PatchOverlay::setLive(const VisibilityResult& live, const Project& project, bool newFrame)
{
    if (newFrame)
        fresh_ = {};
    const bool needReceiver = kind_ == OverlayKind::ReceiverImportance || accumulating_;
    const bool needSource = kind_ == OverlayKind::SourceImportance || accumulating_;
    const bool needLight = kind_ == OverlayKind::LightOnReceiver;
    if (!needReceiver && !needSource && !needLight)
        return;   // nothing shown or accumulated: no work per frame (fresh_ remembers it was skipped)

    if (!live.valid) {
        // An invalid pair: no current frame. The accumulation so far stays (and stays shown).
        currentReceiver_ = {};
        currentSource_ = {};
        currentLight_ = {};
        fresh_ = {true, true, true};
        seedPending_ = false;
        refresh();
        return;
    }

    const Grids grids{project.source.na, project.source.nb, project.receiver.na, project.receiver.nb};
    if (grids_ && *grids_ != grids) {
        // Other sample counts: earlier frames are per-sample values of another grid.
        receiverFrames_.reset();
        sourceFrames_.reset();
        animation_.reset();
        seedPending_ = accumulating_;
        if (grids_->sourceNa != grids.sourceNa || grids_->sourceNb != grids.sourceNb) {
            areaLight_.reset();
            error_.clear();
        }
    }
    grids_ = grids;

    if (needReceiver && !fresh_.receiver) {
        currentReceiver_ = receiverImportance(live.map);   // one popcount per row word
        fresh_.receiver = true;
    }
    if (needSource && !fresh_.source) {
        currentSource_ = sourceImportance(live.map, project.source.na, project.source.nb);
        fresh_.source = true;
    }
    if (needLight && !fresh_.light) {
        currentLight_ = {};
        if (!areaLight_ && error_.empty()) {
            try {
                areaLight_ = projectLight(project, project.source, "project");
            } catch (const std::exception& e) {
                error_ = e.what();
            }
        }
        if (areaLight_) {
            try {
                currentLight_ = shadeReceiver(live.map, *areaLight_);
            } catch (const std::exception& e) {
                error_ = e.what();
                areaLight_.reset();
            }
        }
        fresh_.light = true;
    }
    if (accumulating_ && (newFrame || seedPending_)) {
        receiverFrames_.add(currentReceiver_);
        sourceFrames_.add(currentSource_);
        seedPending_ = false;
    }
    refresh();
}

void PatchOverlay::resetAccumulation()
{
    receiverFrames_.reset();
    sourceFrames_.reset();
    animation_.reset();
    seedPending_ = accumulating_;   // starts again from the current frame
    refresh();
}

void PatchOverlay::clear()
{
    receiverFrames_.reset();
    sourceFrames_.reset();
    animation_.reset();
    areaLight_.reset();
    error_.clear();
    grids_.reset();
    fresh_ = {};
    currentReceiver_ = {};
    currentSource_ = {};
    currentLight_ = {};
    seedPending_ = accumulating_;
    refresh();
}

void PatchOverlay::showAnimationResult(ImportanceSide side, ImportanceAccumulator accumulator, bool recordedPath)
{
    animation_ = AnimationResult{side, std::move(accumulator), recordedPath};
    refresh();
}

void PatchOverlay::dropAnimationResult()
{
    if (!animation_)
        return;
    animation_.reset();
    refresh();
}

int PatchOverlay::frames() const { return shownFrames_; }

const ImportanceAccumulator& PatchOverlay::accumulator(ImportanceSide side) const
{
    return side == ImportanceSide::Receiver ? receiverFrames_ : sourceFrames_;
}

void PatchOverlay::refresh()
{
    shown_ = {};
    shownFrames_ = 0;
    shownAccumulated_ = shownIsAnimation_ = shownIsPath_ = false;
    light_ = {};
    if (isImportance(kind_)) {
        const ImportanceSide side = kind_ == OverlayKind::ReceiverImportance ? ImportanceSide::Receiver : ImportanceSide::Source;
        const ImportanceMap& current = side == ImportanceSide::Receiver ? currentReceiver_ : currentSource_;
        const bool fresh = side == ImportanceSide::Receiver ? fresh_.receiver : fresh_.source;
        if (animation_ && animation_->side == side && !animation_->accumulator.empty()) {
            shown_ = animation_->accumulator.result(statistic_);
            shownFrames_ = animation_->accumulator.frames();
            shownAccumulated_ = shownIsAnimation_ = true;
            shownIsPath_ = animation_->recordedPath;
        } else if (accumulating_ && !accumulator(side).empty()) {
            shown_ = accumulator(side).result(statistic_);
            shownFrames_ = accumulator(side).frames();
            shownAccumulated_ = true;
        } else if (fresh && !current.values.empty()) {
            shown_ = current;
            shownFrames_ = 1;
        }
    } else if (kind_ == OverlayKind::LightOnReceiver && fresh_.light) {
        light_ = currentLight_;
        shownFrames_ = light_.rgb.empty() ? 0 : 1;
    }
    texels_ = !shown_.values.empty() ? importanceTexels(shown_) : !light_.rgb.empty() ? lightTexels(light_) : OverlayTexels{};
    ++version_;
}

QString PatchOverlay::legendCaption() const
{
    if (!isImportance(kind_))
        return {};
    const bool receiver = kind_ == OverlayKind::ReceiverImportance;
    QString what = receiver ? QObject::tr("fraction of the source seen") : QObject::tr("fraction of the receiver seeing it");
    if (shownAccumulated_ && statistic_ == ImportanceStatistic::EverVisible)   // only 0 and 1
        what = receiver ? QObject::tr("saw the source (100%) or never (0%)") : QObject::tr("seen by the receiver (100%) or never (0%)");
    const QString over = shownAccumulated_ ? statisticPhrase(statistic_, shownFrames_, shownIsAnimation_, shownIsPath_) : QObject::tr("this frame");
    return what + QString::fromUtf8(" — ") + over;
}

QString PatchOverlay::readOut(int a, int b) const
{
    if (const LightImage* light = this->light()) {
        if (a < 0 || b < 0 || a >= light->na || b >= light->nb)
            return {};
        const glm::vec3 c = light->rgb[std::size_t(b) * std::size_t(light->na) + std::size_t(a)];
        return QObject::tr("receiver sample (%1, %2): light R %3%, G %4%, B %5% of full")
            .arg(a)
            .arg(b)
            .arg(100.0 * c.r, 0, 'f', 1)
            .arg(100.0 * c.g, 0, 'f', 1)
            .arg(100.0 * c.b, 0, 'f', 1);
    }
    const ImportanceMap* map = importance();
    if (!map || a < 0 || b < 0 || a >= map->na || b >= map->nb)
        return {};
    const bool receiver = kind_ == OverlayKind::ReceiverImportance;
    const QString where =
        (receiver ? QObject::tr("receiver sample (%1, %2): ") : QObject::tr("source sample (%1, %2): ")).arg(a).arg(b);
    const double value = map->at(a, b);
    const QString frames = frameCount(shownFrames_, shownIsAnimation_, shownIsPath_);
    if (shownAccumulated_ && statistic_ == ImportanceStatistic::EverVisible) {
        if (receiver)
            return where + (value > 0.0 ? QObject::tr("saw the source in at least one of %1").arg(frames)
                                        : QObject::tr("never saw the source in %1").arg(frames));
        return where + (value > 0.0 ? QObject::tr("seen by the receiver in at least one of %1").arg(frames)
                                    : QObject::tr("never seen by the receiver in %1").arg(frames));
    }
    const QString context =
        shownAccumulated_ ? statisticPhrase(statistic_, shownFrames_, shownIsAnimation_, shownIsPath_) : QObject::tr("this frame");
    if (receiver)
        return where + QObject::tr("%1% of the source seen (%2)").arg(100.0 * value, 0, 'f', 1).arg(context);
    return where + QObject::tr("seen by %1% of the receiver (%2)").arg(100.0 * value, 0, 'f', 1).arg(context);
}

} // namespace sightline::ui
