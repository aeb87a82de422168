#pragma once
// The occluder assistant (docs/editor.md): the smallest occluder that cuts the current view, on a
// plane the designer slides between the patches, drawn in the view as a ghost with its area and
// the rays it leaves; Add Occluder (Enter) inserts it, undoably.
//
// It works on the live view's own answer (the exact hidden-samples map the viewport shows), in a
// worker thread so that a large share trim never stalls the window: a new answer or setting
// replaces a computation still waiting. The geometry is visibility/suggest/OccluderSuggestion.h,
// the same the CLI's `suggest` uses.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <QWidget>

#include "LatestRequestWorker.h"
#include "visibility/suggest/OccluderSuggestion.h"

class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QPushButton;
class QSlider;
class QTimer;

namespace sightline::ui {

class EditorDocument;
class Viewport;

class OccluderAssistant : public QWidget {
    Q_OBJECT
public:
    OccluderAssistant(EditorDocument& document, Viewport& viewport, QWidget* parent = nullptr);
    ~OccluderAssistant() override;

    /// Shown: suggestions follow the view and the ghost is drawn. Hidden: no work, no ghost.
    void setActive(bool active);
    /// Asks for a suggestion on the view's current answer (soon: changes are gathered).
    void refresh();
    /// Adds the suggestion as an occluder (a convex one's mesh written beside the project as
    /// "<project>-occluder-NNN.glb"). False, with `message` saying why, when there is none.
    bool addSuggestion(QString* message);

    const std::optional<suggest::Suggestion>& suggestion() const { return suggestion_; }
    QSlider* depthSlider() const { return depth_; }
    QDoubleSpinBox* shareBox() const { return share_; }
    QComboBox* shapeBox() const { return shape_; }
    QLabel* summary() const { return summary_; }
    QPushButton* addButton() const { return add_; }

signals:
    /// A suggestion arrived or was withdrawn (the summary line changed).
    void suggestionChanged();
    /// Add Occluder ran: what happened, for the status bar.
    void added(const QString& status);

private:
    struct Job {
        Patch source, receiver;
        std::shared_ptr<const ReceiverHeights> heights;
        std::shared_ptr<const HiddenSampleMap> map;
        suggest::Request request;
    };
    struct Outcome {
        std::optional<suggest::Suggestion> suggestion;
        std::string error;
        double ms = 0.0;
    };
    static Outcome work(const Job& job);
    void requestNow();
    void take(std::uint64_t generation, Outcome outcome);
    void withdraw(const QString& why);
    suggest::Request settings() const;

    EditorDocument& document_;
    Viewport& viewport_;
    QSlider* depth_ = nullptr;
    QLabel* depthValue_ = nullptr;
    QDoubleSpinBox* share_ = nullptr;
    QComboBox* shape_ = nullptr;
    QLabel* summary_ = nullptr;
    QPushButton* add_ = nullptr;
    QTimer* gather_ = nullptr;
    bool active_ = false;
    std::uint64_t generation_ = 0;
    std::optional<suggest::Suggestion> suggestion_;
    LatestRequestWorker<Job, Outcome> worker_;   // last: its thread calls back into the above
};

} // namespace sightline::ui
