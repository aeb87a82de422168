#pragma once
// The editor's recorder: Record (F9) captures the camera and the edits to the
// patches and placed occluders at a fixed rate while the designer works, Stop (F9 again) keeps
// them in the project as its recorded path (project/RecordedPath.h; one undoable edit) and renders
// the video chosen at the start. The video is rendered frame by frame, headless, on a worker
// thread (ui/VideoRecording.h), from a snapshot of the document: its frame rate is the capture's,
// whatever rate the viewport updated at while recording, and the editor stays responsive.
// "Play Recorded Path" (Shift+F9) plays the path in the viewport; "Render Recorded Path to
// Video..." renders the project's path (else its animation) again. The status bar shows the
// elapsed time while recording, then the rendering's progress. Kept out of MainWindow so it stays
// a wiring class.

#include <atomic>
#include <memory>
#include <optional>
#include <thread>

#include <QElapsedTimer>
#include <QObject>
#include <QString>
#include <QTimer>

#include "editor/Camera.h"
#include "project/Project.h"
#include "project/RecordedPath.h"

class QAction;
class QLabel;
class QMainWindow;
class QToolBar;

namespace sightline::ui {

class EditorDocument;
class Viewport;
class ViewportController;

class RecordingControls : public QObject {
    Q_OBJECT
public:
    /// Adds a Record menu before the window's last menu (Help), a button to `toolbar` and a label
    /// to the status bar.
    RecordingControls(QMainWindow& window, EditorDocument& document, Viewport& viewport, ViewportController& controller,
                      QToolBar* toolbar);
    /// Cancels a rendering under way and waits for its thread.
    ~RecordingControls() override;

    /// Starts capturing at `fps` samples a second. `video` (empty: none) is rendered from the
    /// capture when it stops (.mp4 or .webm; a bad name is refused here, before recording).
    /// Returns false with a message in the status bar when it cannot start.
    bool startRecording(const QString& video, double fps = 30.0);
    /// Stops capturing: the path becomes the project's "recorded_path" (undoable) and the video,
    /// if one was chosen, starts rendering.
    void stopRecording();
    bool isRecording() const { return timer_.isActive(); }
    /// What was captured so far (the last recording once stopped).
    const RecordedPath& capturedPath() const { return path_; }

    /// Renders the project's recorded path (else its animation, else the still view) to `video`,
    /// at the viewport's size rounded to even sides, on a worker thread. False when a rendering
    /// is already under way or the project's path cannot be read (said in the status bar).
    bool renderVideo(const QString& video);
    bool isRendering() const { return worker_.has_value(); }
    void cancelRendering() { cancel_ = true; }

    /// Plays the project's recorded path in the viewport at its own rate: the camera moves and the
    /// recorded edits are shown (not undoable); at the end, or on stopPlayback(), every object is
    /// back as it was.
    bool playPath();
    void stopPlayback();
    bool isPlaying() const { return playTimer_.isActive(); }

    QAction* recordAction() const { return record_; }
    QAction* playAction() const { return play_; }
    QAction* renderAction() const { return render_; }
    QLabel* statusLabel() const { return label_; }

signals:
    /// A rendering ended: `ok` false on failure or cancel, `message` says what happened ("Recorded
    /// 312 frames to clip.mp4 in 9.6 s (32.5 frames per second)" or the error).
    void videoFinished(bool ok, const QString& message);
    void playbackFinished();

private:
    void capture();
    void playFrame();
    void finishRendering(bool ok, const QString& message);
    QString suggestedVideo() const;

    QMainWindow& window_;
    EditorDocument& document_;
    Viewport& viewport_;
    ViewportController& controller_;
    QAction* record_ = nullptr;
    QAction* play_ = nullptr;
    QAction* render_ = nullptr;
    QAction* cancelAction_ = nullptr;
    QLabel* label_ = nullptr;

    // Recording.
    QTimer timer_;
    QElapsedTimer clock_;
    RecordedPath path_;
    Project start_;                    ///< the project when recording started
    Project last_;                     ///< the states last written to the path
    std::optional<Camera> lastCamera_;
    int lastFrame_ = -1;
    QString video_;

    // Rendering on the worker thread.
    std::optional<std::thread> worker_;
    std::atomic<bool> cancel_{false};
    std::atomic<int> done_{0}, total_{0};
    QTimer progressTimer_;
    QString renderingTo_;

    // Playback.
    QTimer playTimer_;
    QElapsedTimer playClock_;
    RecordedPath playing_;
    Project playStart_;
};

} // namespace sightline::ui
