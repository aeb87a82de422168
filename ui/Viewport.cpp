#include "Viewport.h"

#include <algorithm>
#include <vector>

#include <QKeyEvent>
#include <QMimeData>
#include <QMouseEvent>
#include <QOpenGLContext>
#include <QWheelEvent>

namespace sightline::ui {

namespace {

void* resolveInQtContext(const char* name)
{
    return reinterpret_cast<void*>(QOpenGLContext::currentContext()->getProcAddress(name));
}

constexpr std::size_t kRateWindow = 15;   // frames the update rate is the median over

} // namespace

Viewport::Viewport(EditorDocument& document, ViewportController& controller)
    : QOpenGLWindow(QOpenGLWindow::NoPartialUpdate), document_(document), controller_(controller)
{
    clock_.start();
    connect(&document_, &EditorDocument::changed, this, [this](unsigned changes) {
        if (changes & (SceneFileChanged | DocumentReset)) {
            sceneFileDirty_ = true;
            // Which sampler is faster depends on the level: timed on an empty document, GL wins
            // (0.6 against 3.4 ms) and would then cost 700 ms an update on the demo (llvmpipe).
            backendChosen_ = false;
        }
        if (changes & (OccludersChanged | DocumentReset))
            occludersDirty_ = true;
        // An animation's accumulation described the document before this change.
        if (changes & DocumentReset) {
            overlay_.clear();
            heightsGrid_.reset();
        }
        else
            overlay_.dropAnimationResult();
        samplesDirty_ = true;
        update();
    });
    connect(&controller_, &ViewportController::viewChanged, this, [this] { update(); });
    flyTimer_.setInterval(16);
    connect(&flyTimer_, &QTimer::timeout, this, [this] {
        controller_.advanceFly(flyClock_.restart() * 1e-3);
        if (!controller_.isFlying())
            flyTimer_.stop();
    });
}

Viewport::~Viewport()
{
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
    if (updateTimes_.size() < 2)
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
    sceneFileDirty_ = occludersDirty_ = samplesDirty_ = true;
}

void Viewport::resizeGL(int w, int h) { controller_.setViewportSize(w, h); }

void Viewport::paintGL()
{
    const int w = int(width() * devicePixelRatio()), h = int(height() * devicePixelRatio());
    controller_.setViewportSize(width(), height());
    if (!renderer_)
        return;
    const bool sceneChanged = sceneFileDirty_ || occludersDirty_;
    if (sceneFileDirty_)
        renderer_->setSceneFile(document_.sceneFile());
    if (occludersDirty_)
        renderer_->setOccluders(document_.occluderScene(), document_.occluderOfInstance());
    if (!backendChosen_)
        visibility_.forgetChoice();   // before setScene: the GL sampler needs the level for its timing
    if (sceneChanged)
        visibility_.setScene(document_.scene());
    sceneFileDirty_ = occludersDirty_ = false;

    const Project& project = document_.project();
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
        samplesDirty_ = true;
    }
    const bool deferred = samplesDirty_ && controller_.isDragging() && result_.ms > dragBudgetMs_;
    const bool resampled = samplesDirty_ && !deferred;
    if (resampled) {
        result_ = visibility_.sample(project.source, project.receiver);
        renderer_->setHiddenSamples(result_.valid ? &result_.map : nullptr);
        samplesDirty_ = false;
        overlay_.setLive(result_, project, true);   // returns at once while the overlay is off
    } else if (overlay_.needsLive()) {
        overlay_.setLive(result_, project, false);
    }
    const bool overlayChanged = overlay_.version() != overlayVersion_;
    if (overlayChanged) {
        overlayVersion_ = overlay_.version();
        renderer_->setOverlay(overlayPatch(overlay_.kind()), &overlay_.texels());
    }

    FrameState frame;
    frame.camera = controller_.camera();
    frame.width = w;
    frame.height = h;
    frame.framebuffer = defaultFramebufferObject();
    frame.sceneRadius = controller_.sceneRadius();
    frame.source = project.source;
    frame.receiver = project.receiver;
    frame.pairValid = result_.valid;
    frame.selection = document_.selection();
    frame.gizmo = controller_.gizmo();
    frame.hoveredAxis = controller_.hoveredAxis();
    frame.style = style_;
    renderer_->render(frame);
    raysDrawn_ = renderer_->raysDrawn();

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
    default: break;
    }
    return QOpenGLWindow::event(event);
}

void Viewport::mousePressEvent(QMouseEvent* event)
{
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

} // namespace sightline::ui
