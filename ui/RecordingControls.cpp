#include "RecordingControls.h"

#include <cmath>

#include <QAction>
#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QStatusBar>
#include <QToolBar>
#include <QUndoCommand>

#include "EditorDocument.h"
#include "PathPlayback.h"
#include "VideoRecording.h"
#include "Viewport.h"
#include "ViewportController.h"
#include "EditCommands.h"
#include "plugins/VideoEncoder.h"
#include "base/Error.h"

namespace sightline::ui {

namespace {

QString clock(double seconds)
{
    const int tenths = int(seconds * 10.0);
    return QString::asprintf("%d:%02d.%d", tenths / 600, (tenths / 10) % 60, tenths % 10);
}

bool samePatch(const Patch& a, const Patch& b) { return a.corner == b.corner && a.u == b.u && a.v == b.v; }

bool sameCamera(const Camera& a, const Camera& b)
{
    return a.target == b.target && a.distance == b.distance && a.yaw == b.yaw && a.pitch == b.pitch && a.fovY == b.fovY &&
           a.orthographic == b.orthographic;
}

} // namespace

RecordingControls::RecordingControls(QMainWindow& window, EditorDocument& document, Viewport& viewport,
                                     ViewportController& controller, QToolBar* toolbar)
    : QObject(&window), window_(window), document_(document), viewport_(viewport), controller_(controller)
{
    auto* menu = new QMenu(tr("&Record"), &window);
    const QList<QAction*> menus = window.menuBar()->actions();
    window.menuBar()->insertMenu(menus.isEmpty() ? nullptr : menus.back(), menu);   // before Help

    record_ = menu->addAction(tr("&Record Video..."));
    record_->setCheckable(true);
    record_->setShortcut(QKeySequence(Qt::Key_F9));   // Ctrl+R is Reset Accumulation
    record_->setToolTip(tr("Record the camera and your edits, then render them to a video (F9 starts and stops)"));
    connect(record_, &QAction::triggered, this, [this](bool on) {
        if (!on) {
            stopRecording();
            return;
        }
        record_->setChecked(false);   // checked again once recording starts
        const QString file = QFileDialog::getSaveFileName(&window_, tr("Record Video"), suggestedVideo(),
                                                          tr("Videos (*.mp4 *.webm);;MP4, H.264 (*.mp4);;WebM, VP9 (*.webm)"));
        if (!file.isEmpty())
            startRecording(file);
    });
    play_ = menu->addAction(tr("&Play Recorded Path"));
    play_->setShortcut(QKeySequence(Qt::SHIFT | Qt::Key_F9));
    connect(play_, &QAction::triggered, this, [this] { isPlaying() ? stopPlayback() : void(playPath()); });
    render_ = menu->addAction(tr("Render Recorded Path to &Video..."));
    connect(render_, &QAction::triggered, this, [this] {
        const QString file = QFileDialog::getSaveFileName(&window_, tr("Render Video"), suggestedVideo(),
                                                          tr("Videos (*.mp4 *.webm);;MP4, H.264 (*.mp4);;WebM, VP9 (*.webm)"));
        if (!file.isEmpty())
            renderVideo(file);
    });
    cancelAction_ = menu->addAction(tr("&Cancel Rendering"));
    cancelAction_->setEnabled(false);
    connect(cancelAction_, &QAction::triggered, this, [this] { cancelRendering(); });
    menu->addSeparator();
    menu->addAction(tr("C&lear Recorded Path"), this, [this] {
        const nlohmann::json before = document_.project().extra.value(kRecordedPathKey, nlohmann::json());
        if (!before.is_null())
            document_.undoStack()->push(new SetProjectKeyCommand(document_, kRecordedPathKey, before, nullptr, tr("Clear Recorded Path")));
    });
    if (toolbar) {
        toolbar->addSeparator();
        toolbar->addAction(record_);
        record_->setIconText(tr("● Rec"));
    }

    label_ = new QLabel(&window);
    window.statusBar()->addPermanentWidget(label_);
    label_->hide();

    timer_.setTimerType(Qt::PreciseTimer);
    connect(&timer_, &QTimer::timeout, this, &RecordingControls::capture);
    progressTimer_.setInterval(100);
    connect(&progressTimer_, &QTimer::timeout, this, [this] {
        label_->setText(tr("Rendering %1: %2 of %3 frames").arg(QFileInfo(renderingTo_).fileName()).arg(done_.load()).arg(total_.load()));
    });
    playTimer_.setTimerType(Qt::PreciseTimer);
    connect(&playTimer_, &QTimer::timeout, this, &RecordingControls::playFrame);
}

RecordingControls::~RecordingControls()
{
    cancel_ = true;
    if (worker_ && worker_->joinable())
        worker_->join();
}

QString RecordingControls::suggestedVideo() const
{
    // Beside the project, numbered like F12's images: never over an earlier video.
    const std::filesystem::path file = document_.filePath();
    const std::filesystem::path folder = file.empty() ? std::filesystem::current_path() : std::filesystem::absolute(file).parent_path();
    const std::string stem = file.empty() ? "sightline" : file.stem().string();
    return QString::fromStdString(nextNumberedFile(folder, stem, ".mp4").string());
}

bool RecordingControls::startRecording(const QString& video, double fps)
{
    if (isRecording() || isRendering()) {
        window_.statusBar()->showMessage(tr("A recording is already under way"), 4000);
        return false;
    }
    if (!video.isEmpty()) {
        try {
            videoFormatFor(video.toStdString());   // a bad name is said now, not after the recording
        } catch (const std::exception& e) {
            window_.statusBar()->showMessage(QString::fromUtf8(e.what()), 8000);
            return false;
        }
    }
    stopPlayback();
    video_ = video;
    path_ = RecordedPath{};
    path_.fps = fps;
    start_ = document_.project();
    last_ = start_;
    lastCamera_.reset();
    lastFrame_ = -1;
    clock_.start();
    capture();   // frame 0 now
    timer_.start(std::max(1, int(std::lround(1000.0 / fps))));
    const QSignalBlocker blocker(record_);
    record_->setChecked(true);
    record_->setText(tr("Stop &Recording"));
    label_->setStyleSheet("color: #e04040; font-weight: bold");
    label_->show();
    return true;
}

void RecordingControls::capture()
{
    // The frame is the time since the start, not a tick count: a late tick (the editor busy
    // sampling) skips frames, which then hold the last state, as the recording's keys do.
    const int frame = int(std::floor(double(clock_.nsecsElapsed()) * 1e-9 * path_.fps));
    if (frame <= lastFrame_)
        return;
    lastFrame_ = frame;
    const Camera& camera = controller_.camera();
    if (!lastCamera_ || !sameCamera(*lastCamera_, camera)) {
        path_.camera.push_back({frame, toPathCamera(camera)});
        lastCamera_ = camera;
    }
    const Project& now = document_.project();
    auto patchEdit = [&](PathEdit::Object object, const Patch& current, Patch& last) {
        if (samePatch(current, last))
            return;
        PathEdit edit;
        edit.frame = frame;
        edit.object = object;
        edit.patch = current;
        path_.edits.push_back(edit);
        last = current;
    };
    patchEdit(PathEdit::Object::Source, now.source, last_.source);
    patchEdit(PathEdit::Object::Receiver, now.receiver, last_.receiver);
    for (std::size_t i = 0; i < now.occluders.size(); ++i) {
        const OccluderSpec& o = now.occluders[i];
        const bool known = i < last_.occluders.size() && last_.occluders[i].name == o.name;
        if (known && last_.occluders[i].transform == o.transform)
            continue;
        PathEdit edit;
        edit.frame = frame;
        edit.object = PathEdit::Object::Occluder;
        edit.index = i;
        edit.name = o.name;
        edit.transform = o.transform;
        path_.edits.push_back(edit);
    }
    last_.occluders = now.occluders;
    path_.frames = frame + 1;
    label_->setText(tr("● REC %1 · %2 frames").arg(clock(path_.seconds())).arg(path_.frames));
}

void RecordingControls::stopRecording()
{
    if (!isRecording())
        return;
    capture();
    timer_.stop();
    {
        const QSignalBlocker blocker(record_);
        record_->setChecked(false);
        record_->setText(tr("&Record Video..."));
    }
    label_->setStyleSheet(QString());
    label_->hide();
    // Each edited object's state at the start, as its frame-0 key: played back from the start,
    // the path shows the objects where they were, not where the recording left them.
    std::vector<PathEdit> starts;
    auto edited = [&](PathEdit::Object object, std::size_t index) {
        for (const PathEdit& e : path_.edits)
            if (e.object == object && e.index == index)
                return e.frame > 0;
        return false;
    };
    for (auto object : {PathEdit::Object::Source, PathEdit::Object::Receiver})
        if (edited(object, 0)) {
            PathEdit e;
            e.object = object;
            e.patch = object == PathEdit::Object::Source ? start_.source : start_.receiver;
            starts.push_back(e);
        }
    for (std::size_t i = 0; i < start_.occluders.size(); ++i)
        if (edited(PathEdit::Object::Occluder, i)) {
            PathEdit e;
            e.object = PathEdit::Object::Occluder;
            e.index = i;
            e.name = start_.occluders[i].name;
            e.transform = start_.occluders[i].transform;
            starts.push_back(e);
        }
    path_.edits.insert(path_.edits.begin(), starts.begin(), starts.end());

    const nlohmann::json before = document_.project().extra.value(kRecordedPathKey, nlohmann::json());
    document_.undoStack()->push(new SetProjectKeyCommand(document_, kRecordedPathKey, before, toJson(path_), tr("Record Path")));
    window_.statusBar()->showMessage(tr("Recorded %1 s (%2 frames) into the project's path").arg(path_.seconds(), 0, 'f', 1).arg(path_.frames), 5000);
    if (!video_.isEmpty())
        renderVideo(video_);
}

bool RecordingControls::renderVideo(const QString& video)
{
    if (isRendering() || isRecording()) {
        window_.statusBar()->showMessage(tr("A recording is already under way"), 4000);
        return false;
    }
    auto scene = std::make_shared<RecordingScene>();
    RecordingOptions options;
    try {
        *scene = recordingScene(document_, controller_.camera(), viewport_.style());
        scene->overlay = viewport_.overlay().kind();
        scene->statistic = viewport_.overlay().statistic();
        const qreal ratio = viewport_.devicePixelRatio();
        std::tie(options.width, options.height) = evenVideoSize(int(viewport_.width() * ratio), int(viewport_.height() * ratio));
        options.output = video.toStdString();
        options.fps = defaultRecordingFps(*scene);
        options.frames = defaultRecordingFrames(*scene, options.fps);
        videoFormatFor(options.output);
    } catch (const std::exception& e) {
        window_.statusBar()->showMessage(QString::fromStdString(describeFailure(e, "rendering " + video.toStdString())), 8000);
        return false;
    }
    cancel_ = false;
    done_ = 0;
    total_ = options.frames;
    renderingTo_ = video;
    label_->setStyleSheet(QString());
    label_->show();
    progressTimer_.start();
    cancelAction_->setEnabled(true);
    record_->setEnabled(false);
    // The worker owns its copies: the document may change (or close) while it renders.
    worker_.emplace([this, scene, options] {
        bool ok = false;
        QString message;
        try {
            const RecordingFigures f = recordVideo(*scene, options, [this](int done, int total) {
                done_ = done;
                total_ = total;
                return !cancel_.load();
            });
            ok = f.frames == options.frames;
            message = ok ? tr("Recorded %1 frames (%2x%3) to %4 in %5 s (%6 frames per second)")
                               .arg(f.frames).arg(f.width).arg(f.height)
                               .arg(QString::fromStdString(options.output.string()))
                               .arg(f.seconds, 0, 'f', 1).arg(f.framesPerSecond(), 0, 'f', 1)
                         : tr("Rendering cancelled; no file written");
        } catch (const std::exception& e) {
            message = QString::fromStdString(describeFailure(e, "rendering " + options.output.string()));
        }
        QMetaObject::invokeMethod(this, [this, ok, message] { finishRendering(ok, message); }, Qt::QueuedConnection);
    });
    return true;
}

void RecordingControls::finishRendering(bool ok, const QString& message)
{
    if (worker_ && worker_->joinable())
        worker_->join();
    worker_.reset();
    progressTimer_.stop();
    label_->hide();
    cancelAction_->setEnabled(false);
    record_->setEnabled(true);
    window_.statusBar()->showMessage(message, 10000);
    emit videoFinished(ok, message);
}

bool RecordingControls::playPath()
{
    if (isRecording())
        return false;
    try {
        playing_ = parseRecordedPath(document_.project(), document_.displayName().toStdString());
    } catch (const std::exception& e) {
        window_.statusBar()->showMessage(QString::fromUtf8(e.what()), 8000);
        return false;
    }
    if (playing_.empty()) {
        window_.statusBar()->showMessage(tr("The project has no recorded path: record one with F9"), 5000);
        return false;
    }
    playStart_ = document_.project();
    playClock_.start();
    playFrame();
    playTimer_.start(std::max(1, int(std::lround(1000.0 / playing_.fps))));
    return true;
}

void RecordingControls::playFrame()
{
    const double seconds = double(playClock_.nsecsElapsed()) * 1e-9;
    const bool ended = seconds >= playing_.seconds();
    // At the end every object returns to its state before the playback.
    if (ended)
        showProjectState(document_, playStart_);
    else
        showPathFrame(document_, controller_, playStart_, playing_, playing_.frameAtTime(seconds));
    if (ended && !playing_.empty()) {   // to its last view at the end (not when stopped early)
        if (const auto camera = playing_.cameraAt(playing_.frameAtTime(seconds)))
            controller_.setCamera(toCamera(*camera));
    }
    viewport_.requestUpdate();
    if (ended) {
        playTimer_.stop();
        emit playbackFinished();
    }
}

void RecordingControls::stopPlayback()
{
    if (!isPlaying())
        return;
    playing_.frames = 0;   // ended: playFrame restores every object
    playFrame();
}

} // namespace sightline::ui
