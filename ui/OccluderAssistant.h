#pragma once
// The occluder assistant (docs/editor.md): the smallest occluder that cuts the current view, on a
// plane the designer slides between the patches, drawn in the view as a ghost with its area and
// the rays it leaves; Add Occluder (Enter) inserts it, undoably. Below it, the openings the view
// leaks through, most rays first (visibility/suggest/ViewGaps.h): a click, or N and Shift+N,
// looks through one from the source.
//
// It works on the live view's own answer (the exact hidden-samples map the viewport shows), in a
// worker thread so that a large share trim never stalls the window: a new answer or setting
// replaces a computation still waiting. The geometry is visibility/suggest/OccluderSuggestion.h,
// the same the CLI's `suggest` uses.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <QWidget>

#include "editor/LatestRequestWorker.h"
#include "visibility/suggest/OccluderSuggestion.h"
#include "visibility/suggest/ViewGaps.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QListWidget;
class QPushButton;
class QSlider;
class QTimer;

namespace sightline::ui {

class EditorDocument;
class Viewport;
class ViewportController;

class OccluderAssistant : public QWidget {
    Q_OBJECT
public:
    OccluderAssistant(EditorDocument& document, Viewport& viewport, ViewportController& controller, QWidget* parent = nullptr);
    ~OccluderAssistant() override;

    /// Shown: suggestions follow the view and the ghost is drawn. Hidden: no work, no ghost.
    void setActive(bool active);
    /// Asks for a suggestion on the view's current answer (soon: changes are gathered).
    void refresh();
    /// Adds the suggestion as an occluder (a convex one's mesh written beside the project as
    /// "<project>-occluder-NNN.glb"). False, with `message` saying why, when there is none.
    bool addSuggestion(QString* message);

    const std::optional<suggest::Suggestion>& suggestion() const { return suggestion_; }
    const std::vector<suggest::Opening>& gaps() const { return gaps_; }
    /// Looks through opening `k` from the source's centre and selects it in the list.
    void showGap(std::size_t k);
    /// The next (step 1) or previous (-1) opening after the one shown; false when there is none.
    bool stepGap(int step);
    QSlider* depthSlider() const { return depth_; }
    QDoubleSpinBox* shareBox() const { return share_; }
    QComboBox* shapeBox() const { return shape_; }
    QLabel* summary() const { return summary_; }
    QPushButton* addButton() const { return add_; }
    QListWidget* gapList() const { return gapList_; }
    QPushButton* pickSurfaceButton() const { return pickSurface_; }
    QCheckBox* weightedBox() const { return weighted_; }
    /// The occluder lies on this surface's plane (a doorway's frame) instead of between the
    /// patches at the slider's depth; none: between the patches again (as moving the slider does).
    void setSurface(std::optional<suggest::PickedSurface> surface);
    const std::optional<suggest::PickedSurface>& surface() const { return surface_; }

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
        std::shared_ptr<const WorldTriangles> triangles;
        suggest::Request request;
        bool findGaps = true;   ///< false: the map and level are the last openings' (kept)
    };
    struct Outcome {
        std::optional<suggest::Suggestion> suggestion;
        std::string error;
        std::vector<suggest::Opening> gaps;
        std::string gapsError;
        bool gapsFound = false;
        double ms = 0.0;
    };
    /// The settings, the summary, the Add button, the openings list and Pick Surface.
    void createControls();
    /// The controls in their form and column.
    void layOutControls();
    /// The gathering timer, and what the controls, the surface picker and the document's edits do.
    void connectControls();
    static Outcome work(const Job& job);
    void requestNow();
    void take(std::uint64_t generation, Outcome outcome);
    void withdraw(const QString& why);
    void listGaps(std::vector<suggest::Opening> gaps);
    suggest::Request settings() const;

    EditorDocument& document_;
    Viewport& viewport_;
    ViewportController& controller_;
    QSlider* depth_ = nullptr;
    QLabel* depthValue_ = nullptr;
    QPushButton* pickSurface_ = nullptr;
    QCheckBox* weighted_ = nullptr;   ///< the share is of the light (suggest::Request::sourceWeights)
    /// The source samples' light (sourceLightWeights), kept while the project's light is the same.
    std::vector<double> lightWeights() const;
    mutable std::vector<double> lightWeights_;
    mutable std::string lightWeightsKey_;
    std::optional<suggest::PickedSurface> surface_;   ///< setSurface
    QDoubleSpinBox* share_ = nullptr;
    QComboBox* shape_ = nullptr;
    QLabel* summary_ = nullptr;
    QPushButton* add_ = nullptr;
    QListWidget* gapList_ = nullptr;
    QTimer* gather_ = nullptr;
    bool active_ = false;
    std::uint64_t generation_ = 0;
    std::uint64_t shownGeneration_ = 0;                 ///< the request the shown suggestion answers
    std::optional<std::uint64_t> promised_;             ///< after an add: checked on the next answer
    std::shared_ptr<const HiddenSampleMap> gapsMap_;     ///< what the listed openings were found for
    std::shared_ptr<const WorldTriangles> gapsTriangles_;
    Patch gapsSource_, gapsReceiver_;
    std::optional<suggest::Suggestion> suggestion_;
    std::vector<suggest::Opening> gaps_;
    std::shared_ptr<const WorldTriangles> triangles_;   ///< the document's, until its geometry changes
    LatestRequestWorker<Job, Outcome> worker_;   // last: its thread calls back into the above
};

} // namespace sightline::ui
