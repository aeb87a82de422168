#pragma once
// The 3D view: a QOpenGLWindow (about 6 ms per empty 1280x720 frame on llvmpipe against 19 ms for
// a QOpenGLWidget, DESIGN.md §6), placed in the main window with QWidget::createWindowContainer.
// It owns the GL side (ViewportRenderer, the GL back end of LiveVisibility) and forwards input to
// the ViewportController. Sampling happens at paint time, only when the patches or the scene
// changed since the last frame, so a drag costs one sample per frame drawn. Each new result also
// goes to the patch overlay (importance or light, PatchOverlay.h), which does nothing while it is
// off; its colours are uploaded only when they changed.

#include <QElapsedTimer>
#include <QOpenGLWindow>
#include <QTimer>

#include <deque>
#include <memory>
#include <optional>
#include <utility>

#include "LiveVisibility.h"
#include "PatchOverlay.h"
#include "ViewportController.h"
#include "ViewportRenderer.h"

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
    /// Median interval between the last frames that re-sampled (a live update rate), in Hz.
    double updateRate() const;
    std::uint64_t raysDrawn() const { return raysDrawn_; }
    /// The overlay painted on a patch. After changing it, call update(): the next frame brings it
    /// up to date (it may need the current result) and emits overlayUpdated().
    PatchOverlay& overlay() { return overlay_; }
    const PatchOverlay& overlay() const { return overlay_; }

    /// While a gizmo drag is under way and the last update took longer than this, frames show the
    /// last result and sampling waits for the release: a 512x512 floor takes seconds an update,
    /// and a drag must not freeze. Default 150 ms (the demo's 32x32 pair takes about 20).
    void setDragBudgetMs(double ms) { dragBudgetMs_ = ms; }
    /// The shown result is older than the patches and occluders (a slow update waits for the
    /// drag to end).
    bool resultIsStale() const { return samplesDirty_; }

signals:
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
    EditorDocument& document_;
    ViewportController& controller_;
    std::unique_ptr<gl::Functions> gl_;
    std::unique_ptr<ViewportRenderer> renderer_;
    LiveVisibility visibility_;
    VisibilityResult result_;
    double dragBudgetMs_ = 150.0;
    /// The receiver grid the live sampler's heights were read for (re-read on a new document or
    /// a new grid: "receiver_heights" is resampled to the grid).
    std::optional<std::pair<int, int>> heightsGrid_;
    PatchOverlay overlay_;
    std::uint64_t overlayVersion_ = 0;   ///< the overlay version the renderer has
    ViewStyle style_;
    QString backendReport_;
    bool sceneFileDirty_ = true, occludersDirty_ = true, samplesDirty_ = true;
    bool backendChosen_ = false;
    std::uint64_t raysDrawn_ = 0;
    QElapsedTimer clock_;
    std::deque<qint64> updateTimes_;   ///< ns timestamps of recent re-sampling frames
    QTimer flyTimer_;
    QElapsedTimer flyClock_;
};

} // namespace sightline::ui
