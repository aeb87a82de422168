#pragma once
// The 3D view: a QOpenGLWindow (an empty frame costs about a third of a QOpenGLWidget's on a
// software rasteriser, docs/design.md §6), placed in the main window with
// QWidget::createWindowContainer.
// It owns the GL side (ViewportRenderer, the GL back end of LiveVisibility) and forwards input to
// the ViewportController. When the patches or the scene changed since the last frame, a frame asks
// for a new map: the CPU sampler answers on a worker thread (BackgroundSampler; the latest request
// wins) while frames keep drawing the last answer, and the answer's arrival draws a frame; only a
// GL sampler on a real GPU samples in the frame itself (it needs the context). Each new result also
// goes to the patch overlay (importance or light, PatchOverlay.h), which does nothing while it is
// off; its colours are uploaded only when they changed.

#include <QElapsedTimer>
#include <QOpenGLWindow>
#include <QTimer>

#include <deque>
#include <future>
#include <memory>
#include <optional>
#include <utility>

#include "editor/AoPreview.h"
#include "editor/LitPreview.h"
#include "editor/PvsDebugger.h"
#include "editor/PvsView.h"
#include "editor/BackgroundSampler.h"
#include "editor/DisagreementWorker.h"
#include "editor/LiveVisibility.h"
#include "PatchOverlay.h"
#include "ViewportController.h"
#include "editor/ViewportRenderer.h"

namespace sightline::ui {

class Viewport : public QOpenGLWindow {
    Q_OBJECT
public:
    Viewport(EditorDocument& document, ViewportController& controller);
    ~Viewport() override;

    ViewStyle& style() { return style_; }
    void setStyle(const ViewStyle& style);
    const VisibilityResult& visibility() const { return result_; }
    /// Which sampler answers, and the measurement behind the choice.
    const QString& backendReport() const { return backendReport_; }
    std::string backendName() const { return visibility_.backendName(); }
    /// Median interval between the last frames that re-sampled (a live update rate), in Hz; 0
    /// when nothing re-sampled for a second (idle).
    double updateRate() const;
    std::uint64_t raysDrawn() const { return raysDrawn_; }
    /// Milliseconds from the start of the last frame's painting to its swap: drawing, software
    /// rasterising and the copy to the window (the interaction benchmark reports it).
    double lastDrawMs() const { return lastDrawMs_; }
    /// The overlay painted on a patch. After changing it, call update(): the next frame brings it
    /// up to date (it may need the current result) and emits overlayUpdated().
    PatchOverlay& overlay() { return overlay_; }
    const PatchOverlay& overlay() const { return overlay_; }

    /// With the GL sampler (sampled in the frame): while a gizmo drag is under way and the last
    /// update took longer than this, frames show the last result and sampling waits for the
    /// release, so a drag must not freeze. Default 150 ms. The background CPU sampler needs none.
    void setDragBudgetMs(double ms) { dragBudgetMs_ = ms; }
    /// The shown result is older than the patches and occluders (an answer is on its way, or a
    /// slow GL update waits for the drag to end).
    bool resultIsStale() const { return samplesDirty_ || shownGeneration_ != requestedGeneration_; }
    /// The shown answer is for the document's pair and occluders as they are now.
    bool visibilityIsCurrent() const { return !resultIsStale(); }
    /// The receiver's bumps the live sampler answers with (empty: flat).
    const ReceiverHeights& receiverHeights() const { return visibility_.receiverHeights(); }
    /// A suggested occluder (world-space convex polygon, empty for none), drawn translucent with its
    /// outline over everything (OccluderAssistant.h).
    void setOccluderGhost(std::vector<glm::vec3> polygon);
    /// The level as the document has it is drawn whole. After an open it is prepared on a worker
    /// and its first draw spread over a few frames (the event loop keeps running meanwhile).
    bool levelDrawn() const { return !levelDirty_ && renderer_ && !renderer_->levelIncomplete(); }

    /// Shades the level with its ambient occlusion, computed progressively in the background
    /// (AoPreview.h); recomputed when the level changes while it is on.
    void setAmbientOcclusion(bool on);
    /// AO of the selected object only (AO of chosen objects), at a finer texel
    /// density, the whole level still occluding; with nothing (or a patch) selected, the level's.
    void setAoOfSelection(bool on);
    bool aoOfSelection() const { return aoOfSelection_; }
    /// The finest AO level shown (0: none yet), and its target.
    int aoLevel() const { return aoShownK_; }
    /// The instances of document().scene() the AO shown or on its way is for (empty: all).
    const std::vector<std::uint32_t>& aoInstances() const { return aoInstances_; }
    /// How the AO is lit (a uniform sky or an HDR environment, turned and exposed): relit from the
    /// matrix, never traced again.
    void setAoLighting(const AoLighting& lighting);
    const AoLighting& aoLighting() const { return aoLighting_; }

    /// The lit view (LitPreview.h): the level lit by the project's lights, live while lights move
    /// (amortised), exact once no light is stale; restarted when the scene changes while it is on.
    void setLitView(bool on);
    bool litView() const { return style_.litView; }
    /// What the lit view shows (LitPreview.h): the light, shadow complexity, light overlap against
    /// `budget` lights a texel, or staleness; changed without casting a shadow ray again.
    void setLitShading(LitShading shading, int budget);
    /// Adds one bounce of indirect light to the lit view (LitIndirect.h), or drops it.
    void setLitIndirect(bool on);
    bool litIndirect() const { return litIndirect_; }
    LitShading litShading() const { return litShading_; }
    int litBudget() const { return litBudget_; }
    /// O'Rorke's sets of the selected light (lighting/LightSets.h) over the lit view: the level's
    /// objects it lights that the camera sees (I) tinted yellow, those casting shadows into them
    /// (S) violet, those seen but out of its reach (V \ L) darkened, and its scissor rectangle;
    /// computed on the lit view's worker, again when the camera rests after a move.
    void setLightSetsShown(bool on);
    bool lightSetsShown() const { return setsShown_; }
    /// The sets shown (for the light named by lightSetsLight()), once they arrived.
    const std::optional<LightSets>& lightSets() const { return sets_; }
    std::size_t lightSetsLight() const { return setsLight_; }
    /// The last lit frame shown: whether it was exact, and its status line.
    bool litExact() const { return litExact_; }
    /// Per light, what its last refresh in the lit view cost (empty before the first frame).
    const std::vector<LightingCache::LightCost>& litCosts() const { return litCosts_; }
    std::size_t litFramesShown() const { return litFrames_; }
    /// Lit frames delivered by the worker for the level shown (some replaced before being drawn).
    std::size_t litFramesReceived() const { return litReceived_; }
    std::size_t litTexels() const { return litTexels_; }
    /// The VPLs of the bounce shown (0 without it).
    std::size_t litVpls() const { return litVpls_; }

    /// The PVS debugger: bakes the project's PVS in the background and tints the
    /// level's objects the camera's cell cannot see. Restarted when the scene changes while on.
    void setPvsDebugger(bool on);
    /// Keeps the current cell while the camera moves (fly around it and look at what it culls).
    void setPvsFrozen(bool frozen);
    /// Shows a PVS read from a file (readBakedPvs) in the debugger instead of baking one; `file`
    /// names it in the status. A change that needs a new bake bakes as usual.
    void showBakedPvs(pvs::PvsData data, const QString& file);
    /// What the debugger shows: cells, objects, rows as baked and as shown, the shown cell, gaps.
    const PvsView& pvsView() const { return pvsView_; }
    /// The status bar's text for the PVS debugger.
    QString pvsStatus() const;
    /// Frames gap k: the eye at the reference's witness point in the cell, looking along the
    /// witness ray at the object the bake culled (tinted, seen through the opening it missed).
    void framePvsGap(std::size_t k);
    /// The gap last framed (-1: none); drawn highlighted.
    /// The gap marker within `radius` pixels of `position` (logical pixels), nearest first.
    std::optional<std::size_t> pvsGapAt(QPointF position, double radius = 10.0) const;

    /// The disagreement view: the rays where `approximation` answers the pair differently from the
    /// live exact answer (false-blocked red, false-free blue, ties amber) drawn in place of the
    /// rays, computed on a worker for every new exact answer (DisagreementWorker.h); nothing: the
    /// rays again.
    void setDisagreementView(std::optional<Approximation> approximation);
    const std::optional<Approximation>& disagreementView() const { return disagreementView_; }
    /// The answer drawn, once one arrived for the view's approximation (it may be for an earlier
    /// pair while the next one is computed: disagreementIsCurrent()).
    const std::optional<DisagreementAnswer>& disagreement() const { return disagreement_; }
    /// The disagreement drawn answers the live exact answer shown now.
    bool disagreementIsCurrent() const;

    /// Rays drawn over the others in their own colour (kSelectedRayRgb): the opening the designer
    /// picked, each `receiver * sources + source` for a `sources` x `receivers` pair (drawn while
    /// the pair's grids are those). Empty: none.
    void setSelectedRays(std::vector<std::uint64_t> rays, int sources, int receivers);
    const std::vector<std::uint64_t>& selectedRays() const { return selectedRays_; }

signals:
    /// The disagreement view's answer arrived (its status line), or it failed (the line says why).
    void disagreementUpdated(const QString& status, bool failed);
    /// The PVS debugger's state for the status bar.
    void pvsUpdated(const QString& status);
    /// Gap k of the PVS debugger's list was framed (a click on its marker, or N / Shift+N).
    void pvsGapFramed(std::size_t k);
    /// An AO level arrived and is shown (k directions of `target`; `relit`: the same level lit
    /// anew), or the computation failed.
    /// A level of AO arrived (k of `target` directions; aoInstances() says for what), or failed.
    void aoUpdated(int k, int target, double ms, const QString& error, bool relit);
    /// A lit frame arrived and is shown (its status line), or lighting failed (`error`).
    void litUpdated(const QString& status, bool exact, const QString& error);
    /// The selected light's sets arrived (their status line).
    void lightSetsUpdated(const QString& status);
    /// After every frame that re-sampled.
    void visibilityUpdated();
    /// After every frame whose overlay colours changed.
    void overlayUpdated();
    /// The mouse moved over the view with no button held (position in logical pixels).
    void hovered(QPointF position);
    void hoverLeft();
    void backendChosen(const QString& report);
    void filesDropped(const QStringList& files);

protected:
    void initializeGL() override;
    void paintGL() override;
    void resizeGL(int w, int h) override;
    bool event(QEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;
    void keyPressEvent(QKeyEvent* event) override;
    void keyReleaseEvent(QKeyEvent* event) override;

private:
    /// EditorDocument::changed: marks what the change makes stale and asks for a frame.
    void documentChanged(unsigned changes);
    /// Restarts or refreshes the lit view and the AO for a change to the level or its occluders.
    void restartShading(unsigned changes);
    /// Marks the level, the occluders, the flags, the PVS and the overlay stale for a change.
    void markSceneStale(unsigned changes);
    // The steps of a frame (paintGL), in order.
    void syncRenderer();
    std::pair<bool, bool> updateAnswer(const Project& project);
    void startAoPreview();
    void startLitPreview();
    void takeAoLevel();
    void updatePvs(const Project& project);
    FrameState frameState(const Project& project, int w, int h);
    /// Posts the document's pair to the background sampler (CPU back end).
    void requestSample();
    /// On the GUI thread: a background answer arrived.
    void takeAnswer(std::uint64_t generation, VisibilityResult result);
    /// Posts the live exact answer to the disagreement worker (while the view is on and the answer
    /// is current).
    void requestDisagreement();
    void takeDisagreement(std::uint64_t generation, DisagreementAnswer answer);

    EditorDocument& document_;
    ViewportController& controller_;
    std::unique_ptr<gl::Functions> gl_;
    std::unique_ptr<ViewportRenderer> renderer_;
    LiveVisibility visibility_;   ///< the choice of back end, and the GL sampler
    VisibilityResult result_;
    std::unique_ptr<BackgroundSampler> worker_;
    std::shared_ptr<const Scene> workerScene_;            ///< the scene the worker samples against
    std::shared_ptr<const ReceiverHeights> workerHeights_;
    std::uint64_t requestedGeneration_ = 0, shownGeneration_ = 0;
    std::optional<VisibilityResult> arrived_;            ///< taken by the next frame (GL uploads)
    std::optional<Approximation> disagreementView_;
    std::unique_ptr<DisagreementWorker> disagreementWorker_;
    std::uint64_t disagreementGeneration_ = 0;
    std::uint64_t exactVersion_ = 0;         ///< counts the exact answers shown (result_)
    std::uint64_t disagreementFor_ = 0;      ///< the exactVersion_ last posted to the worker
    std::uint64_t disagreementShownFor_ = 0; ///< the exactVersion_ the drawn disagreement answers
    std::optional<DisagreementAnswer> disagreement_;
    std::unique_ptr<PvsDebugger> pvs_;
    std::uint64_t pvsGeneration_ = 0;
    bool pvsStale_ = false;      ///< a bake is wanted at the next frame
    bool pvsUploaded_ = false;   ///< the renderer has the shown cell's culled objects
    bool setsServed_ = false;   ///< the light sets shown took V and L from the PVS
    PvsView pvsView_;
    std::string pvsBakeKey_;   ///< the settings the running (or last) bake was started with
    void takePvsEvent(PvsDebugEvent event);
    /// Stops a bake and forgets its rows: the scene they were for is gone.
    void dropPvs();
    /// The bake's rows with the project's overrides applied (PvsView::shown).
    const pvs::VisibilityRows& pvsShownRows();
    std::vector<glm::vec3> occluderGhost_;   ///< setOccluderGhost
    std::unique_ptr<AoPreview> ao_;
    std::unique_ptr<LitPreview> lit_;
    std::uint64_t litGeneration_ = 0;
    std::optional<LitPreviewFrame> litArrived_;
    bool litStale_ = false;   ///< the level changed while the lit view is on: restart at the next frame
    bool litExact_ = false;   ///< the frame shown is exact for the lights as they are now
    std::uint64_t litWanted_ = 0;
    std::vector<LightingCache::LightCost> litCosts_;   ///< LitPreview's version of the lights as they are now
    std::size_t litFrames_ = 0;
    std::size_t litTexels_ = 0;
    std::size_t litVpls_ = 0;
    std::size_t litReceived_ = 0;
    bool litFailed_ = false;   ///< the last lit frame was an error: the worker has ended
    LitShading litShading_ = LitShading::Light;
    int litBudget_ = 4;
    bool litIndirect_ = false;
    bool setsShown_ = false;
    std::optional<LightSets> sets_;
    std::size_t setsLight_ = 0;
    std::vector<Bounds> setsLitBounds_;     ///< world boxes of I's scene instances: the scissor's
    std::optional<Camera> setsCamera_;       ///< the camera the sets on their way or shown are for
    QTimer setsRest_;                        ///< the camera rested: the sets again for it
    void requestLightSets();
    void showLightSets(const LightSets& sets, std::size_t light, bool served);
    AoLighting aoLighting_;
    std::uint64_t aoGeneration_ = 0;
    std::optional<AoPreviewLevel> aoArrived_;
    int aoShownK_ = 0;
    bool aoStale_ = false;   ///< the level changed while AO is on: restart at the next frame
    bool aoOfSelection_ = false;
    std::vector<std::uint32_t> aoInstances_;
    /// The instances of document().scene() the selection stands for (none for a patch).
    std::vector<std::uint32_t> selectedInstances() const;
    QString litStatus(const LitPreviewFrame& frame) const;
    /// The lit frame that arrived, into the renderer (the context current) and the status.
    void takeLitFrame();
    QString setsStatus() const;
    double dragBudgetMs_ = 150.0;
    /// The receiver grid the live sampler's heights were read for (re-read on a new document or
    /// a new grid: "receiver_heights" is resampled to the grid).
    std::optional<std::pair<int, int>> heightsGrid_;
    PatchOverlay overlay_;
    std::uint64_t overlayVersion_ = 0;   ///< the overlay version the renderer has
    ViewStyle style_;
    QString backendReport_;
    bool sceneFileDirty_ = true, occludersDirty_ = true, samplesDirty_ = true, flagsDirty_ = true;
    bool raySceneDirty_ = false;   ///< the coarse stand-ins changed: a new workerScene_
    std::vector<std::uint64_t> selectedRays_;   ///< setSelectedRays, handed to the renderer at the next frame
    int selectedSources_ = 0, selectedReceivers_ = 0;
    bool selectedRaysDirty_ = false;
    // The drawn level. A new document's is prepared on a worker (prepareLevel()); until it is
    // ready frames show no level. An edit to the level while it is prepared makes it stale: the
    // frame then builds the level from the document itself, as it does after every edit.
    void prepareLevel();
    void updateLevel();
    bool levelDirty_ = true, levelStale_ = false, levelCleared_ = false;
    std::future<LevelMesh> levelPrepared_;
    bool backendChosen_ = false;
    std::uint64_t raysDrawn_ = 0;
    qint64 paintStartNs_ = -1'000'000'000;
    QTimer frameCap_;   ///< a frame asked for sooner than kMinFrameMs after the last one waits for it
    double lastDrawMs_ = 0.0;
    QElapsedTimer clock_;
    std::deque<qint64> updateTimes_;   ///< ns timestamps of recent re-sampling frames
    QTimer flyTimer_;
    QElapsedTimer flyClock_;
};

} // namespace sightline::ui
