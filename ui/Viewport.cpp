#include "Viewport.h"

#include <algorithm>
#include <vector>

#include <QKeyEvent>
#include <QMimeData>
#include <QMouseEvent>
#include <QOpenGLContext>
#include <QWheelEvent>

#include "PvsStatusText.h"
#include "project/PvsSetup.h"
#include "base/Error.h"

namespace sightline::ui {

namespace {

void* resolveInQtContext(const char* name)
{
    return reinterpret_cast<void*>(QOpenGLContext::currentContext()->getProcAddress(name));
}

constexpr std::size_t kRateWindow = 15;   // frames the update rate is the median over
// At most one frame a display refresh (60 Hz). Frames drawn faster show nothing more, and on a
// software rasteriser they take the processor from the sampler: uncapped, a drag at 4,096 rays
// draws several frames per answer shown, each a stale answer at a new place.
constexpr qint64 kMinFrameNs = 16'000'000;
// While an answer is being sampled and none has arrived, frames can only show the last answer's
// rays at the patches' new places: at most 30 of those a second, so the sampler keeps the
// processor (without this limit a drag at 16,384 rays draws two frames per answer, each taking
// processor time the sampler needs on a software rasteriser).
constexpr qint64 kMinStaleFrameNs = 33'000'000;

bool pairIsValid(const Patch& source, const Patch& receiver)
{
    try {
        validatePatchPair(source, receiver);
        return true;
    } catch (const Error&) {
        return false;
    }
}

} // namespace

Viewport::Viewport(EditorDocument& document, ViewportController& controller)
    : QOpenGLWindow(QOpenGLWindow::NoPartialUpdate), document_(document), controller_(controller)
{
    clock_.start();
    connect(this, &QOpenGLWindow::frameSwapped, this,
            [this] { lastDrawMs_ = double(clock_.nsecsElapsed() - paintStartNs_) * 1e-6; });
    connect(&document_, &EditorDocument::changed, this, &Viewport::documentChanged);
    connect(&document_, &EditorDocument::selectionChanged, this, [this] {
        if (style_.ambientOcclusion && aoOfSelection_ && selectedInstances() != aoInstances_) {
            aoStale_ = true;
            update();
        }
        if (setsShown_)
            requestLightSets();
    });
    setsRest_.setSingleShot(true);
    setsRest_.setInterval(400);
    connect(&setsRest_, &QTimer::timeout, this, [this] { requestLightSets(); });
    connect(&controller_, &ViewportController::viewChanged, this, [this] { update(); });
    frameCap_.setSingleShot(true);
    connect(&frameCap_, &QTimer::timeout, this, [this] { requestUpdate(); });
    flyTimer_.setInterval(16);
    connect(&flyTimer_, &QTimer::timeout, this, [this] {
        controller_.advanceFly(flyClock_.restart() * 1e-3);
        if (!controller_.isFlying())
            flyTimer_.stop();
    });
}

void Viewport::documentChanged(unsigned changes)
{
    if (changes == NamesChanged)
        return;   // a rename changes no ray and no pixel of the view
    if (changes == FlagsChanged) {
        flagsDirty_ = true;   // hidden, locked or isolated: drawn anew, not sampled (hidden objects block rays)
        update();
        return;
    }
    if (changes == LightsChanged) {
        // The markers; the lights change no ray between the patches. The lit view refreshes
        // the lights that changed, by priority (LitPreview.h).
        if (style_.litView && lit_ && !litStale_) {
            litWanted_ = lit_->setLights(document_.lights());
            litExact_ = false;   // until a frame of these lights says so
        }
        update();
        return;
    }
    if (changes == CoarseOccludersChanged) {
        // The rays between the patches only: the level is drawn, lit and baked from full meshes.
        raySceneDirty_ = true;
        samplesDirty_ = true;
        update();
        return;
    }
    if (changes == ProjectKeysChanged) {
        // Overrides and the distance cut-off are shown anew over the same bake; other PVS
        // settings (cells, sample budgets, the mode) need a new one.
        pvsView_.markRowsChanged();
        if (pvsBakeKey(document_.project()) != pvsBakeKey_) {
            pvsStale_ = style_.pvsDebugger;
            if (!style_.pvsDebugger)
                dropPvs();
        }
        update();
        return;
    }
    restartShading(changes);
    markSceneStale(changes);
    samplesDirty_ = true;
    update();
}

void Viewport::restartShading(unsigned changes)
{
    if (changes & (SceneFileChanged | DocumentReset)) {
        litStale_ = style_.litView;   // a new level: the lit view starts again
    } else if ((changes & OccludersChanged) && style_.litView && lit_ && !litStale_ && !litFailed_) {
        // New shadows: each light refreshes the texels they could reach (LitPreview.h).
        litWanted_ = lit_->setScene(std::make_shared<const Scene>(document_.scene()));
        litExact_ = false;
    } else if (changes & OccludersChanged) {
        litStale_ = style_.litView;   // the last lit view failed (its worker has ended): start again
    }
    if (changes & (SceneFileChanged | OccludersChanged | DocumentReset)) {
        // Placed occluders darken the level around them and get AO of their own.
        aoStale_ = style_.ambientOcclusion;
        aoShownK_ = 0;   // the map was for the old level
        if (!aoStale_ && ao_) {
            ao_->cancel();     // a finished worker kept while AO is off would relight the old level
            ++aoGeneration_;
        }
    }
}

void Viewport::markSceneStale(unsigned changes)
{
    if (changes & (SceneFileChanged | DocumentReset)) {
        sceneFileDirty_ = true;
        levelDirty_ = true;
        if (changes & DocumentReset)
            prepareLevel();
        else
            levelStale_ = true;
        // Which sampler is faster depends on the level: timed on an empty document, GL wins
        // and would then cost many times the CPU sampler's update on the demo (llvmpipe).
        backendChosen_ = false;
    }
    if (changes & (OccludersChanged | DocumentReset))
        occludersDirty_ = true;
    flagsDirty_ = flagsDirty_ || (changes & FlagsChanged);
    if (changes & (OccludersChanged | SceneFileChanged | DocumentReset)) {
        // Baked for the old scene: again now while the debugger is on, else when it is next.
        pvsStale_ = style_.pvsDebugger;
        if (!style_.pvsDebugger)
            dropPvs();
    }
    // An animation's accumulation described the document before this change.
    if (changes & DocumentReset) {
        overlay_.clear();
        heightsGrid_.reset();
    }
    else
        overlay_.dropAnimationResult();
}

Viewport::~Viewport()
{
    pvs_.reset();      // joins, as the ones below
    ao_.reset();       // joins, as the sampler below
    lit_.reset();
    worker_.reset();   // joins: no answer arrives for a viewport being destroyed
    disagreementWorker_.reset();
    if (levelPrepared_.valid())
        levelPrepared_.wait();   // its posted update() is dropped with this object
    makeCurrent();
    renderer_.reset();
    visibility_.setGl(nullptr);
    doneCurrent();
}

void Viewport::setStyle(const ViewStyle& style)
{
    style_ = style;
    update();
}

double Viewport::updateRate() const
{
    // Idle is 0, not the rate of the last drag: nothing updated for a second.
    if (updateTimes_.size() < 2 || clock_.nsecsElapsed() - updateTimes_.back() > 1'000'000'000)
        return 0.0;
    std::vector<qint64> intervals;
    for (std::size_t i = 1; i < updateTimes_.size(); ++i)
        intervals.push_back(updateTimes_[i] - updateTimes_[i - 1]);
    std::nth_element(intervals.begin(), intervals.begin() + std::ptrdiff_t(intervals.size() / 2), intervals.end());
    const qint64 median = intervals[intervals.size() / 2];
    return median > 0 ? 1e9 / double(median) : 0.0;
}

void Viewport::initializeGL()
{
    gl_ = std::make_unique<gl::Functions>();
    try {
        gl_->load(&resolveInQtContext);
        renderer_ = std::make_unique<ViewportRenderer>(*gl_);
        visibility_.setGl(gl_.get());
    } catch (const std::exception& e) {
        backendReport_ = tr("OpenGL 4.5 core unavailable: %1").arg(e.what());
        emit backendChosen(backendReport_);
        renderer_.reset();
        gl_.reset();
    }
    sceneFileDirty_ = occludersDirty_ = samplesDirty_ = levelDirty_ = true;
}

void Viewport::resizeGL(int w, int h) { controller_.setViewportSize(w, h); }

void Viewport::prepareLevel()
{
    // A new document's level, built on a worker: on the demo's first open building it on the GUI
    // thread, mostly touching new memory, would stall the event loop on top of the upload and
    // the first draw (docs/benchmarks.md). The scene is copied: the document may change while the
    // worker reads.
    auto scene = std::make_shared<const Scene>(document_.sceneFile());
    levelPrepared_ = std::async(std::launch::async, [this, scene] {
        LevelMesh mesh = prepareLevelMesh(*scene);
        // Posted to this object: dropped if the view is gone (its destructor waits for this worker).
        QMetaObject::invokeMethod(this, [this] { update(); }, Qt::QueuedConnection);
        return mesh;
    });
    levelStale_ = false;
}

void Viewport::updateLevel()
{
    if (levelPrepared_.valid() && !levelStale_) {
        if (levelPrepared_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
            if (!levelCleared_)
                renderer_->setSceneFile(LevelMesh{});   // not the old document's level meanwhile
            levelCleared_ = true;
            return;
        }
        try {
            renderer_->setSceneFile(levelPrepared_.get(), true);
        } catch (const std::exception&) {   // out of memory on the worker: once more here
            renderer_->setSceneFile(document_.sceneFile());
        }
    } else {
        renderer_->setSceneFile(document_.sceneFile());
    }
    levelDirty_ = levelCleared_ = false;
}

void Viewport::paintGL()
{
    paintStartNs_ = clock_.nsecsElapsed();
    const int w = int(width() * devicePixelRatio()), h = int(height() * devicePixelRatio());
    controller_.setViewportSize(width(), height());
    if (!renderer_)
        return;
    syncRenderer();
    const Project& project = document_.project();
    const auto [resampled, deferred] = updateAnswer(project);
    startAoPreview();
    startLitPreview();
    takeLitFrame();
    takeAoLevel();
    updatePvs(project);
    const bool overlayChanged = overlay_.version() != overlayVersion_;
    if (overlayChanged) {
        overlayVersion_ = overlay_.version();
        renderer_->setOverlay(overlayPatch(overlay_.kind()), &overlay_.texels());
    }
    renderer_->render(frameState(project, w, h));
    raysDrawn_ = renderer_->raysDrawn();
    if (renderer_->levelIncomplete())
        update();   // the rest of a new level's first draw

    if (resampled || deferred) {
        if (resampled)
            updateTimes_.push_back(clock_.nsecsElapsed());
        while (updateTimes_.size() > kRateWindow)
            updateTimes_.pop_front();
        emit visibilityUpdated();
    }
    if (overlayChanged)
        emit overlayUpdated();
}

/// The level, occluders, hidden objects, the worker's ray scene and the picked rays, where edits
/// changed them.
void Viewport::syncRenderer()
{
    const bool sceneChanged = sceneFileDirty_ || occludersDirty_;
    if (levelDirty_)
        updateLevel();
    if (occludersDirty_)
        renderer_->setOccluders(document_.occluderScene(), document_.occluderOfInstance());
    if (flagsDirty_ || sceneChanged)
        renderer_->setHiddenObjects(document_.hiddenMask(ObjectKind::SceneObject), document_.hiddenMask(ObjectKind::Occluder));
    flagsDirty_ = false;
    if (!backendChosen_)
        visibility_.forgetChoice();   // before setScene: the GL sampler needs the level for its timing
    if (sceneChanged || raySceneDirty_) {
        workerScene_ = std::make_shared<const Scene>(document_.rayScene());
        if (visibility_.mayUseGl())
            visibility_.setScene(*workerScene_);   // the GUI thread's copy serves only the GL sampler
    }
    sceneFileDirty_ = occludersDirty_ = raySceneDirty_ = false;
    if (selectedRaysDirty_) {
        renderer_->setSelectedRays(selectedRays_, selectedSources_, selectedReceivers_);
        selectedRaysDirty_ = false;
    }
}

/// The samples for the pair: sampled in the frame (GL), or asked of the worker and taken when
/// they arrive; the overlay and the disagreement view follow a new answer. Returns whether a new
/// answer is shown, and whether sampling was put off for a drag.
std::pair<bool, bool> Viewport::updateAnswer(const Project& project)
{
    if (!backendChosen_) {
        backendChosen_ = true;
        backendReport_ = QString::fromStdString(visibility_.chooseBackend(project.source, project.receiver));
        emit backendChosen(backendReport_);
    }
    // A bumpy receiver (§8): the CPU sampler answers with the project's heights, read again
    // for each new receiver grid.
    if (const std::pair grid{project.receiver.na, project.receiver.nb}; heightsGrid_ != grid) {
        heightsGrid_ = grid;
        visibility_.loadReceiverHeights(project, document_.displayName().toStdString());
        workerHeights_ = visibility_.receiverHeights().empty()
                             ? nullptr
                             : std::make_shared<const ReceiverHeights>(visibility_.receiverHeights());
        samplesDirty_ = true;
    }
    const bool inFrame = visibility_.backend() == LiveVisibility::Backend::Gl && visibility_.receiverHeights().empty();
    const bool deferred = inFrame && samplesDirty_ && controller_.isDragging() && result_.ms > dragBudgetMs_;
    bool resampled = false;
    if (samplesDirty_ && inFrame && !deferred) {
        result_ = visibility_.sample(project.source, project.receiver);
        samplesDirty_ = false;
        shownGeneration_ = requestedGeneration_;   // a late background answer is older: dropped
        arrived_.reset();
        resampled = true;
    } else if (samplesDirty_ && !inFrame) {
        requestSample();
    }
    if (arrived_) {
        result_ = std::move(*arrived_);
        arrived_.reset();
        resampled = true;
    }
    // Blocked rays shown, or more of them: the answer needs their ends (the worker finds them).
    const int wantedEnds = style_.showBlocked && style_.showRays ? style_.rayCap : 0;
    if (!inFrame && !resultIsStale() && result_.valid && wantedEnds > 0 && result_.rayEndsCap != wantedEnds)
        requestSample();
    // The overlay reads the answer's own pair: a background answer may be for an older one.
    const auto answeredProject = [&] {
        Project answered = project;
        answered.source = result_.source;
        answered.receiver = result_.receiver;
        return answered;
    };
    if (resampled) {
        renderer_->setHiddenSamples(result_.valid ? &result_.map : nullptr);
        renderer_->setRayEnds(result_.rayEnds, result_.rayEndsCap);
        overlay_.setLive(result_, answeredProject(), true);   // returns at once while the overlay is off
        ++exactVersion_;
        requestDisagreement();
    } else if (overlay_.needsLive()) {
        overlay_.setLive(result_, answeredProject(), false);
    }
    return {resampled, deferred};
}

/// The AO preview (again) on a worker, after the level or its settings changed.
void Viewport::startAoPreview()
{
    if (!aoStale_)
        return;
    aoStale_ = false;
    aoShownK_ = 0;
    if (!ao_)
        ao_ = std::make_unique<AoPreview>([this](AoPreviewLevel level) {
            QMetaObject::invokeMethod(
                this, [this, l = std::move(level)]() mutable {
                    if (l.generation != aoGeneration_)
                        return;   // for a level or a setting since replaced
                    aoArrived_ = std::move(l);
                    update();
                },
                Qt::QueuedConnection);
        });
    ao_->setLighting(aoLighting_);
    aoInstances_ = aoOfSelection_ ? selectedInstances() : std::vector<std::uint32_t>{};
    ao_->start(++aoGeneration_, {.scene = std::make_shared<const Scene>(document_.scene()), .instances = aoInstances_});
}

/// The lit view (again) on a worker, after the level or its lights changed.
void Viewport::startLitPreview()
{
    if (!litStale_)
        return;
    litStale_ = false;
    litExact_ = false;
    if (!lit_)
        lit_ = std::make_unique<LitPreview>([this](LitPreviewFrame frame) {
            QMetaObject::invokeMethod(
                this, [this, f = std::move(frame)]() mutable {
                    if (f.generation != litGeneration_)
                        return;   // for a level since replaced
                    ++litReceived_;
                    litArrived_ = std::move(f);
                    // Taken now where the renderer has the scene it is for: a dragged light's
                    // next pass then starts without waiting for the window's next paint.
                    if (renderer_ && !levelDirty_ && !sceneFileDirty_ && !occludersDirty_ && !litStale_) {
                        makeCurrent();
                        takeLitFrame();
                    }
                    update();
                },
                Qt::QueuedConnection);
        });
    litFailed_ = false;
    litWanted_ = lit_->start(++litGeneration_, {.scene = std::make_shared<const Scene>(document_.scene()),
                                   .lights = document_.lights(),
                                   .shading = litShading_,
                                   .budget = litBudget_,
                                   .indirect = litIndirect_});
    if (setsShown_)
        requestLightSets();
}

/// An AO level that arrived, into the renderer (unless the lit view holds the map).
void Viewport::takeAoLevel()
{
    if (!aoArrived_)
        return;
    AoPreviewLevel level = std::move(*aoArrived_);
    aoArrived_.reset();
    if (level.error.empty() && style_.litView) {
        aoShownK_ = 0;   // the lit view holds the map; AO is computed again when it ends
    } else if (level.error.empty()) {
        renderer_->setAmbientOcclusion(level.uvs, level.width, level.height, level.map);
        aoShownK_ = level.k;
    }
    emit aoUpdated(level.k, level.targetK, level.ms, QString::fromStdString(level.error), level.relit);
}

/// The PVS debugger: a bake (again) after the level changed, and the culled objects of the
/// eye's (or the frozen) view cell.
void Viewport::updatePvs(const Project& project)
{
    if (pvsStale_) {
        pvsStale_ = false;
        pvsView_.reset({}, {}, {}, false);
        if (!pvs_)
            pvs_ = std::make_unique<PvsDebugger>([this](PvsDebugEvent event) {
                QMetaObject::invokeMethod(
                    this, [this, e = std::move(event)]() mutable { takePvsEvent(std::move(e)); }, Qt::QueuedConnection);
            });
        pvsBakeKey_ = pvsBakeKey(project);
        pvs_->start(++pvsGeneration_, std::make_shared<const Scene>(document_.scene()), project,
                    document_.displayName().toStdString());
    }
    if (style_.pvsDebugger) {
        // The cell the eye is in (or the frozen one); the level's objects it cannot see are tinted.
        if (pvsView_.showFrom(controller_.camera().eye()) || !pvsUploaded_) {
            pvsUploaded_ = true;
            const std::optional<std::size_t> cell = pvsView_.shownCell();
            const pvs::VisibilityRows& rows = pvsShownRows();
            renderer_->setPvsCulled(cell && *cell < rows.cellCount()
                                        ? culledInstances(pvsView_.objects(), rows.row(*cell), document_.sceneFile().instances.size())
                                        : std::vector<std::uint8_t>{});
            emit pvsUpdated(pvsStatus());
        }
    }
}

/// What the renderer draws this frame.
FrameState Viewport::frameState(const Project& project, int w, int h)
{
    FrameState frame;
    frame.camera = controller_.camera();
    frame.width = w;
    frame.height = h;
    frame.framebuffer = defaultFramebufferObject();
    frame.sceneRadius = controller_.sceneRadius();
    frame.source = project.source;
    frame.receiver = project.receiver;
    frame.sourceHidden = !document_.isShown({ObjectKind::Source, 0});
    frame.receiverHidden = !document_.isShown({ObjectKind::Receiver, 0});
    // Red patches say the pair is invalid now, whatever the last answer was for.
    frame.pairValid = resultIsStale() ? pairIsValid(project.source, project.receiver) : result_.valid;
    frame.selection = document_.selection();
    frame.gizmo = controller_.gizmo();
    frame.gizmoMode = controller_.gizmoMode();
    frame.placementGhost = controller_.placementGhost();
    frame.occluderGhost = occluderGhost_;
    frame.hoveredAxis = controller_.hoveredAxis();
    frame.cutHandle = controller_.cutHandle();
    frame.cutHandleHovered = controller_.cutHandleHovered() || controller_.isDraggingCut();
    frame.levelBounds = controller_.levelBounds();
    frame.lights = document_.lights();
    frame.sunLevel = document_.levelBounds();
    if (setsShown_ && sets_ && !setsLitBounds_.empty()) {
        // O'Rorke's scissor: the screen box of what the light lights and the camera sees.
        glm::dvec4 r(w, h, 0.0, 0.0);
        bool behind = false;
        for (const Bounds& b : setsLitBounds_)
            for (int c = 0; c < 8; ++c) {
                const glm::dvec3 corner((c & 1 ? b.max : b.min).x, (c & 2 ? b.max : b.min).y, (c & 4 ? b.max : b.min).z);
                const glm::dvec3 p = toPixels(frame.camera, corner, w, h);
                behind = behind || p.z <= 0.0;
                r = {std::min(r.x, p.x), std::min(r.y, p.y), std::max(r.z, p.x), std::max(r.w, p.y)};
            }
        frame.scissor = behind ? glm::dvec4(0.0, 0.0, w, h)
                               : glm::dvec4(std::clamp(r.x, 0.0, double(w)), std::clamp(r.y, 0.0, double(h)),
                                            std::clamp(r.z, 0.0, double(w)), std::clamp(r.w, 0.0, double(h)));
    }
    if (setsShown_ && setsCamera_ && (setsCamera_->eye() != frame.camera.eye() || setsCamera_->target != frame.camera.target))
        setsRest_.start();   // V follows the camera once it rests
    frame.style = style_;
    if (style_.pvsDebugger)
        for (const pvs::Gap& gap : pvsView_.gaps())
            frame.gapMarkers.push_back({gap.from, gap.to, glm::vec3(gap.opening.centre), pvsView_.shownCell() == std::optional<std::size_t>(gap.cell)});
    const int selectedGap = pvsView_.gapSelected();
    frame.gapSelected = selectedGap;
    if (style_.pvsDebugger && selectedGap >= 0 && std::size_t(selectedGap) < pvsView_.gaps().size())
        frame.gapWitnesses = pvsView_.gaps()[std::size_t(selectedGap)].witnesses;
    if (style_.pvsDebugger && pvsView_.shownCell() && *pvsView_.shownCell() < pvsView_.cells().size())
        frame.viewCell = pvsView_.cells()[*pvsView_.shownCell()];
    return frame;
}

void Viewport::setAmbientOcclusion(bool on)
{
    style_.ambientOcclusion = on;
    if (!on) {
        aoStale_ = false;
        if (aoShownK_ < 258) {
            if (ao_)
                ao_->cancel();   // never waits: a worker in its set-up ends on its own
            ++aoGeneration_;     // an answer on its way is dropped
            aoShownK_ = 0;
        }
        // A finished one stays: it costs nothing while it waits, and relights (for when AO is
        // shown again) if the environment changes meanwhile.
    } else if (aoShownK_ < 258) {
        aoStale_ = true;   // never computed, or stopped part way: again from the start
    }
    update();
}

void Viewport::takeLitFrame()
{
    if (!litArrived_)
        return;
    LitPreviewFrame f = std::move(*litArrived_);
    litArrived_.reset();
    if (f.error.empty() && setsShown_ && f.sets &&
        (!sets_ || *sets_ != *f.sets || setsLight_ != f.setsLight || setsServed_ != f.setsServed))
        showLightSets(*f.sets, f.setsLight, f.setsServed);
    if (f.error.empty()) {
        renderer_->setAmbientOcclusion(*f.uvs, f.width, f.height, f.map);
        lit_->recycle(std::move(f.map));
        litExact_ = f.exact && f.lightsVersion >= litWanted_ && f.indirect == litIndirect_;
        f.exact = litExact_;   // an exact frame of lights since moved is not the answer now
        litTexels_ = f.texels;
        litVpls_ = f.vpls;
        litCosts_ = std::move(f.costs);
        ++litFrames_;
    }
    litFailed_ = !f.error.empty();
    emit litUpdated(litStatus(f), f.exact, QString::fromStdString(f.error));
}

QString Viewport::litStatus(const LitPreviewFrame& f) const
{
    if (f.lights == 0)
        return tr("Lit view: no lights yet (Create > Place Point Light on Surface, Ctrl+3)");
    if (setsShown_ && sets_)
        return setsStatus();   // the selected light's sets say more than the lit view's progress
    const QString state = f.exact ? tr("exact") : tr("%1 stale, refining (%2 refreshed in %3 ms)").arg(f.stale).arg(f.refreshed).arg(f.frameMs, 0, 'f', 0);
    switch (f.shading) {
    case LitShading::Light: break;
    case LitShading::Overlap:
        return tr("Light overlap: green to yellow 1 to %1 lights a texel, red over; %2% of the lit texels over %1, at most %3 (%4)")
            .arg(f.budget).arg(100.0 * f.overBudget, 0, 'f', 1).arg(f.mostLights).arg(state);
    case LitShading::Complexity:
        return tr("Shadow complexity: green fully lit, blue partly, red shadowed, brighter up to %1 lights; %2 lights shadowed "
                  "a lit texel on average, at most %3 lights reach one (%4)")
            .arg(f.budget).arg(f.meanShadowed, 0, 'f', 1).arg(f.mostLights).arg(state);
    case LitShading::Staleness: return tr("Staleness: red where the light shown is from stale lights (%1)").arg(state);
    case LitShading::Error:
        if (f.referenceLights < f.lights)
            return tr("Error against the reference: computing the reference, %1 of %2 lights").arg(f.referenceLights).arg(f.lights);
        return tr("Error against the reference: green agrees (under 0.01%), blue to red 0.01% to 100%; largest %1%, "
                  "%2% of the lit texels off by more than 1% (%3)")
            .arg(100.0 * f.errorMax, 0, 'g', 2).arg(f.errorOverPercent, 0, 'f', 1).arg(state);
    }
    const QString lights = f.indirect ? tr("%1 lights and one bounce by %2 VPLs").arg(f.lights).arg(f.vpls) : tr("%1 lights").arg(f.lights);
    if (f.exact)
        return tr("Lit view: %1, exact (%2 texels, %3 s)").arg(lights).arg(f.texels).arg(f.ms / 1000.0, 0, 'f', 1);
    if (f.indirect && f.stale == 0)
        return tr("Lit view: %1, the direct light exact, the bounce refining").arg(lights);
    return tr("Lit view: %1, %2").arg(lights, state);
}

void Viewport::setLightSetsShown(bool on)
{
    setsShown_ = on;
    style_.lightSets = on;
    sets_.reset();
    setsLitBounds_.clear();
    setsCamera_.reset();
    if (on && !style_.litView)
        setLitView(true);   // the sets are computed on the lit view's worker
    requestLightSets();
    if (!on && !style_.pvsDebugger && renderer_)
        renderer_->setPvsCulled({});
    update();
}

void Viewport::requestLightSets()
{
    if (!lit_ || !style_.litView || litStale_)
        return;   // asked again when the lit view starts
    const ObjectRef selected = document_.selection();
    if (!setsShown_ || selected.kind != ObjectKind::Light) {
        lit_->requestSets(std::nullopt);
        setsCamera_.reset();
        if (sets_) {
            sets_.reset();
            setsLitBounds_.clear();
            if (!style_.pvsDebugger && renderer_)
                renderer_->setPvsCulled({});
            emit lightSetsUpdated(setsShown_ ? tr("Light sets: select a light") : QString());
        }
        return;
    }
    setsCamera_ = controller_.camera();
    LitPreview::SetsRequest request{selected.index, *setsCamera_, std::nullopt, std::nullopt};
    // A finished, current PVS serves them: V the camera cell's row, L bounded by the light's cells'.
    if (pvsView_.usable() && !pvsStale_ && selected.index < document_.lights().size()) {
        const pvs::VisibilityRows& rows = pvsShownRows();
        const std::optional<std::size_t> cell = pvs::cellAt(pvsView_.cells(), setsCamera_->eye());
        if (cell && rows.cellCount() == pvsView_.cells().size()) {
            request.visible = pvs::instancesVisibleFrom(rows, pvsView_.objects(), *cell);
            request.reach = pvsReach(pvsView_.cells(), rows, pvsView_.objects(), document_.lights()[selected.index]);
        }
    }
    lit_->requestSets(std::move(request));
}

void Viewport::showLightSets(const LightSets& sets, std::size_t light, bool served)
{
    sets_ = sets;
    setsLight_ = light;
    setsServed_ = served;
    const std::size_t fileObjects = document_.sceneFile().instances.size();
    std::vector<std::uint8_t> classes(fileObjects, 0);
    const auto has = [](const std::vector<std::uint32_t>& list, std::uint32_t i) { return std::binary_search(list.begin(), list.end(), i); };
    setsLitBounds_.clear();
    const Scene& scene = document_.scene();
    for (std::uint32_t i = 0; i < scene.instances.size(); ++i) {
        const bool lit = has(sets.I, i);
        if (lit)
            setsLitBounds_.push_back(scene.instanceBounds(scene.instances[i]));
        if (i >= fileObjects)
            continue;
        classes[i] = lit ? 2 : has(sets.S, i) ? 3 : has(sets.V, i) && !has(sets.L, i) ? 4 : 0;
    }
    if (!style_.pvsDebugger && renderer_)
        renderer_->setPvsCulled(classes);
    emit lightSetsUpdated(setsStatus());
}

QString Viewport::setsStatus() const
{
    if (!sets_)
        return {};
    const QString name = setsLight_ < document_.lights().size() ? document_.objectName({ObjectKind::Light, setsLight_}) : QString();
    return tr("%1: V %2 seen%6, L %3 reached, I %4 lit and seen (yellow), S %5 casting shadows into them "
              "(violet); seen but out of reach darkened; the dashed frame is its scissor rectangle")
        .arg(name).arg(sets_->V.size()).arg(sets_->L.size()).arg(sets_->I.size()).arg(sets_->S.size())
        .arg(setsServed_ ? tr(" from the camera's PVS cell") : QString());
}

void Viewport::setLitShading(LitShading shading, int budget)
{
    litShading_ = shading;
    litBudget_ = std::max(budget, 1);
    if (lit_ && style_.litView && !litStale_)
        lit_->setShading(litShading_, litBudget_);
}

void Viewport::setLitIndirect(bool on)
{
    litIndirect_ = on;
    litExact_ = false;   // until a frame with (or without) the bounce says so
    if (lit_ && style_.litView && !litStale_)
        lit_->setIndirect(on);
}

void Viewport::setLitView(bool on)
{
    if (on == style_.litView)
        return;
    style_.litView = on;
    // The lit view and the AO share the renderer's light map: whichever shows next computes its own.
    if (ao_)
        ao_->cancel();
    ++aoGeneration_;
    aoShownK_ = 0;
    if (on) {
        litStale_ = true;
        aoStale_ = false;
    } else {
        litStale_ = false;
        if (lit_)
            lit_->cancel();
        ++litGeneration_;
        litFrames_ = 0;
        litExact_ = false;
        if (setsShown_) {
            setsShown_ = style_.lightSets = false;
            sets_.reset();
            setsLitBounds_.clear();
            if (!style_.pvsDebugger && renderer_)
                renderer_->setPvsCulled({});
        }
        aoStale_ = style_.ambientOcclusion;   // the map was the lights': AO, when on, is computed again
    }
    update();
}

void Viewport::setAoOfSelection(bool on)
{
    aoOfSelection_ = on;
    if (style_.ambientOcclusion && (aoOfSelection_ ? selectedInstances() : std::vector<std::uint32_t>{}) != aoInstances_) {
        aoStale_ = true;
        update();
    }
}

std::vector<std::uint32_t> Viewport::selectedInstances() const
{
    const ObjectRef selected = document_.selection();
    std::vector<std::uint32_t> instances;
    if (selected.kind == ObjectKind::SceneObject) {
        instances.push_back(std::uint32_t(selected.index));
    } else if (selected.kind == ObjectKind::Occluder) {
        // document().scene() is the scene file's instances, then the occluders'.
        const auto first = std::uint32_t(document_.sceneFile().instances.size());
        const std::vector<std::size_t>& occluderOf = document_.occluderOfInstance();
        for (std::size_t i = 0; i < occluderOf.size(); ++i)
            if (occluderOf[i] == selected.index)
                instances.push_back(first + std::uint32_t(i));
    }
    return instances;
}

void Viewport::setPvsDebugger(bool on)
{
    style_.pvsDebugger = on;
    if (on && pvsView_.cells().empty())   // never baked, baked for an older scene, or failed: (again) now
        pvsStale_ = true;
    pvsUploaded_ = false;
    update();
}

void Viewport::dropPvs()
{
    if (pvs_)
        pvs_->stop();
    ++pvsGeneration_;   // an answer on its way is dropped
    pvsView_.clear();
}

const pvs::VisibilityRows& Viewport::pvsShownRows()
{
    // The designer's distance cut-off and overrides over the bake: shown at once, no new bake.
    return pvsView_.applyProjectSettings(document_.project(), document_.displayName().toStdString());
}

void Viewport::showBakedPvs(pvs::PvsData data, const QString& file)
{
    if (pvs_)
        pvs_->stop();
    ++pvsGeneration_;   // a bake on its way is dropped
    pvsStale_ = false;
    pvsView_.reset(std::move(data.cells), std::move(data.objects), std::move(data.rows), true, file.toStdString());
    pvsUploaded_ = false;
    if (setsShown_)
        requestLightSets();   // the file now serves V and L
    pvsBakeKey_ = pvsBakeKey(document_.project());
    style_.pvsDebugger = true;
    emit pvsUpdated(pvsStatus());
    update();
}

void Viewport::setPvsFrozen(bool frozen)
{
    pvsView_.setFrozen(frozen);
    pvsUploaded_ = false;
    update();
}

QString Viewport::pvsStatus() const { return pvsStatusText(pvsView_); }

void Viewport::framePvsGap(std::size_t k)
{
    if (k >= pvsView_.gaps().size())
        return;
    const pvs::Gap& gap = pvsView_.gaps()[k];
    const glm::dvec3 from(gap.from), to(gap.to);
    const glm::dvec3 along = to - from;
    const double length = glm::length(along);
    if (!(length > 0.0))
        return;
    // The eye at the witness ray's start (in the cell), the target where it meets the object.
    const glm::dvec3 direction = along / length;
    Camera camera = lookThrough(from - 0.01 * direction, direction, to, std::max(0.3, 0.1 * length));
    controller_.setCamera(camera);
    pvsView_.selectGap(k);
    pvsUploaded_ = false;
    emit pvsGapFramed(k);
    emit pvsUpdated(pvsStatus());
    update();
}

std::optional<std::size_t> Viewport::pvsGapAt(QPointF position, double radius) const
{
    const std::vector<pvs::Gap>& gaps = pvsView_.gaps();
    if (!style_.pvsDebugger || gaps.empty())
        return std::nullopt;
    std::optional<std::size_t> best;
    double bestDistance = radius;
    for (std::size_t k = 0; k < gaps.size(); ++k) {
        const glm::dvec3 p = toPixels(controller_.camera(), gaps[k].opening.centre, width(), height());
        if (p.z <= 0.0)
            continue;   // behind the eye
        const double d = std::hypot(p.x - position.x(), p.y - position.y());
        if (d <= bestDistance) {
            bestDistance = d;
            best = k;
        }
    }
    return best;
}

void Viewport::takePvsEvent(PvsDebugEvent event)
{
    if (event.generation != pvsGeneration_)
        return;   // a bake since replaced
    const bool failed = !event.error.empty(), started = event.started, finished = event.finished;
    pvsView_.take(std::move(event));
    if (failed) {
        emit pvsUpdated(pvsStatus());
        return;
    }
    if (finished && setsShown_)
        requestLightSets();   // the bake now serves V and L
    pvsUploaded_ = pvsUploaded_ && !started;
    emit pvsUpdated(pvsStatus());
    update();
}

void Viewport::setAoLighting(const AoLighting& lighting)
{
    aoLighting_ = lighting;
    if (ao_)
        ao_->setLighting(lighting);   // a finished computation is relit at once
}

void Viewport::requestSample()
{
    if (!worker_)
        worker_ = std::make_unique<BackgroundSampler>([this](std::uint64_t generation, VisibilityResult result) {
            // On the worker thread: hand the answer to the GUI thread. The viewport outlives the
            // worker (its destructor joins it first), and Qt drops events queued for a dead object.
            QMetaObject::invokeMethod(
                this, [this, generation, r = std::move(result)]() mutable { takeAnswer(generation, std::move(r)); },
                Qt::QueuedConnection);
        });
    const Project& project = document_.project();
    BackgroundSampler::Request request;
    request.generation = ++requestedGeneration_;
    request.scene = workerScene_;
    request.source = project.source;
    request.receiver = project.receiver;
    request.heights = workerHeights_;
    request.heightsError = visibility_.receiverHeightsError();
    request.rayEndsCap = style_.showBlocked && style_.showRays ? style_.rayCap : 0;
    worker_->request(std::move(request));
    samplesDirty_ = false;   // asked; resultIsStale() stays true until the answer is shown
}

void Viewport::takeAnswer(std::uint64_t generation, VisibilityResult result)
{
    if (generation <= shownGeneration_)
        return;   // an answer older than the one shown
    shownGeneration_ = generation;
    arrived_ = std::move(result);
    if (frameCap_.isActive())
        frameCap_.stop();   // a frame for the answer waits at most for the 60 Hz cap
    update();
}

void Viewport::setSelectedRays(std::vector<std::uint64_t> rays, int sources, int receivers)
{
    selectedRays_ = std::move(rays);
    selectedSources_ = sources;
    selectedReceivers_ = receivers;
    selectedRaysDirty_ = true;
    update();
}

void Viewport::setDisagreementView(std::optional<Approximation> approximation)
{
    disagreementView_ = std::move(approximation);
    disagreement_.reset();
    if (renderer_)
        renderer_->setDisagreement(nullptr);
    disagreementFor_ = disagreementShownFor_ = 0;
    ++disagreementGeneration_;   // an answer on its way is for the view before
    if (disagreementView_)
        requestDisagreement();
    update();
}

bool Viewport::disagreementIsCurrent() const
{
    return disagreement_ && visibilityIsCurrent() && disagreementShownFor_ == exactVersion_;
}

void Viewport::requestDisagreement()
{
    if (!disagreementView_ || !result_.valid || resultIsStale() || disagreementFor_ == exactVersion_)
        return;
    if (!disagreementWorker_)
        disagreementWorker_ = std::make_unique<DisagreementWorker>([this](std::uint64_t generation, DisagreementAnswer answer) {
            QMetaObject::invokeMethod(
                this, [this, generation, a = std::move(answer)]() mutable { takeDisagreement(generation, std::move(a)); },
                Qt::QueuedConnection);
        });
    DisagreementRequest request;
    request.generation = ++disagreementGeneration_;
    request.approximation = *disagreementView_;
    request.scene = workerScene_;
    request.source = result_.source;
    request.receiver = result_.receiver;
    request.heights = workerHeights_;
    request.exact = std::make_shared<const HiddenSampleMap>(result_.map);
    disagreementFor_ = exactVersion_;
    disagreementWorker_->request(std::move(request));
}

void Viewport::takeDisagreement(std::uint64_t generation, DisagreementAnswer answer)
{
    if (generation != disagreementGeneration_ || !disagreementView_)
        return;   // for a view or an answer since replaced
    const bool failed = !answer.error.empty();
    const QString status = QString::fromStdString(disagreementStatus(answer));
    if (failed) {
        disagreement_.reset();
        if (renderer_)
            renderer_->setDisagreement(nullptr);
    } else {
        disagreement_ = std::move(answer);
        disagreementShownFor_ = disagreementFor_;   // the latest request answered: for the latest exact answer posted
        if (renderer_)
            renderer_->setDisagreement(disagreement_->disagreement.get());
    }
    update();
    emit disagreementUpdated(status, failed);
}

bool Viewport::event(QEvent* event)
{
    switch (event->type()) {
    case QEvent::ShortcutOverride:
        // While flying, W/A/S/D/Q/E move the camera instead of triggering the menus' shortcuts.
        if (controller_.isFlying()) {
            event->accept();
            return true;
        }
        break;
    case QEvent::DragEnter: {
        auto* drag = static_cast<QDragEnterEvent*>(event);
        if (drag->mimeData()->hasUrls())
            drag->acceptProposedAction();
        return true;
    }
    case QEvent::Drop: {
        auto* drop = static_cast<QDropEvent*>(event);
        QStringList files;
        for (const QUrl& url : drop->mimeData()->urls())
            if (url.isLocalFile())
                files << url.toLocalFile();
        if (!files.isEmpty())
            emit filesDropped(files);
        return true;
    }
    case QEvent::Leave: emit hoverLeft(); break;
    case QEvent::UpdateRequest: {
        // Moved patches go to the sampler now, even when their frame waits (below).
        const Project& project = document_.project();
        const bool onWorker = backendChosen_ && renderer_ &&
                              !(visibility_.backend() == LiveVisibility::Backend::Gl && visibility_.receiverHeights().empty());
        if (samplesDirty_ && onWorker && !sceneFileDirty_ && !occludersDirty_ && !raySceneDirty_ &&
            heightsGrid_ == std::pair{project.receiver.na, project.receiver.nb})
            requestSample();
        const qint64 since = clock_.nsecsElapsed() - paintStartNs_;
        const qint64 least = resultIsStale() && !arrived_ && !samplesDirty_ ? kMinStaleFrameNs : kMinFrameNs;
        if (since < least) {
            if (!frameCap_.isActive() || frameCap_.remainingTime() > int((least - since) / 1'000'000))
                frameCap_.start(int((least - since + 999'999) / 1'000'000));
            return true;   // drawn when the timer fires
        }
        break;
    }
    default: break;
    }
    return QOpenGLWindow::event(event);
}

void Viewport::mousePressEvent(QMouseEvent* event)
{
    // A click on a PVS gap marker frames that gap (the gap list).
    if (event->button() == Qt::LeftButton && event->modifiers() == Qt::NoModifier)
        if (const std::optional<std::size_t> gap = pvsGapAt(event->position())) {
            framePvsGap(*gap);
            event->accept();
            return;
        }
    controller_.mousePress(event->button(), event->modifiers(), event->position());
    if (controller_.isFlying() && !flyTimer_.isActive()) {
        flyClock_.start();
        flyTimer_.start();
    }
}

void Viewport::mouseMoveEvent(QMouseEvent* event)
{
    controller_.mouseMove(event->buttons(), event->modifiers(), event->position());
    if (event->buttons() == Qt::NoButton)
        emit hovered(event->position());
}

void Viewport::mouseReleaseEvent(QMouseEvent* event)
{
    controller_.mouseRelease(event->button(), event->position());
    if (samplesDirty_)
        update();   // a slow update waited for the drag to end
}

void Viewport::wheelEvent(QWheelEvent* event) { controller_.wheel(event->angleDelta().y() / 120.0); }

void Viewport::keyPressEvent(QKeyEvent* event)
{
    if (!event->isAutoRepeat() && controller_.key(event->key(), true))
        return;
    QOpenGLWindow::keyPressEvent(event);
}

void Viewport::keyReleaseEvent(QKeyEvent* event)
{
    if (!event->isAutoRepeat() && controller_.key(event->key(), false))
        return;
    QOpenGLWindow::keyReleaseEvent(event);
}

void Viewport::setOccluderGhost(std::vector<glm::vec3> polygon)
{
    if (polygon == occluderGhost_)
        return;
    occluderGhost_ = std::move(polygon);
    update();
}

} // namespace sightline::ui
