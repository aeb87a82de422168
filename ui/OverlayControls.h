#pragma once
// The window's side of the patch overlay (PatchOverlay.h): the View menu's Overlay and Statistic
// choices and the toolbar's combos (kept in step), "Accumulate While Editing", "Reset
// Accumulation", "Accumulate Animation...", "Accumulate Recorded Path...", the legend over the view and the read-out of the
// sample under the cursor in the status bar. Kept out of MainWindow so it stays a wiring class.

#include <QObject>
#include <QPointF>

#include <optional>

#include "PatchOverlay.h"
#include "project/ProjectMotion.h"

class QAction;
class QActionGroup;
class QComboBox;
class QLabel;
class QMainWindow;
class QMenu;
class QToolBar;

namespace sightline::ui {

class EditorDocument;
class OverlayLegend;
class Viewport;
class ViewportController;

class OverlayControls : public QObject {
    Q_OBJECT
public:
    /// Adds its actions to `view` and `toolbar`, its read-out to `window`'s status bar, and its
    /// legend over `viewportHost` (the viewport's container).
    OverlayControls(QMainWindow& window, EditorDocument& document, Viewport& viewport, ViewportController& controller,
                    QWidget* viewportHost, QMenu* view, QToolBar* toolbar);

    void setKind(OverlayKind kind);
    void setStatistic(ImportanceStatistic statistic);
    void setAccumulating(bool on);
    void resetAccumulation();
    /// Runs the project's animation with a progress dialog and shows the result; explains in a
    /// message box when the project has no animation or the run fails. Returns whether a result is
    /// shown.
    bool accumulateAnimation();
    /// The same over the project's recorded path (project/RecordedPath.h: one frame per recorded
    /// frame, its edits applied), as `sightline-cli importance --path`.
    bool accumulateRecordedPath();
    /// The read-out for the cursor at `position` (logical pixels of the viewport): empty when the
    /// overlay is off or the cursor is not on the overlaid patch.
    QString readOutAt(QPointF position) const;

    QAction* kindAction(OverlayKind kind) const;
    QAction* accumulateAction() const { return accumulate_; }
    QAction* resetAction() const { return reset_; }
    QAction* animationAction() const { return animation_; }
    QAction* pathAction() const { return path_; }
    QComboBox* kindCombo() const { return kindCombo_; }
    QComboBox* statisticCombo() const { return statisticCombo_; }
    OverlayLegend* legend() const { return legend_; }
    QLabel* readOutLabel() const { return readOut_; }

private:
    /// Legend, read-out and the enabled state of the actions, from the overlay as it is.
    void updateWidgets();
    void updateReadOut();
    bool accumulate(ProjectMotion::Kind kind);

    QMainWindow& window_;
    EditorDocument& document_;
    Viewport& viewport_;
    ViewportController& controller_;
    QActionGroup* kinds_ = nullptr;
    QActionGroup* statistics_ = nullptr;
    QAction* accumulate_ = nullptr;
    QAction* reset_ = nullptr;
    QAction* animation_ = nullptr;
    QAction* path_ = nullptr;
    QComboBox* kindCombo_ = nullptr;
    QComboBox* statisticCombo_ = nullptr;
    OverlayLegend* legend_ = nullptr;
    QLabel* readOut_ = nullptr;
    std::optional<QPointF> hover_;   ///< the cursor over the view, for read-outs of new results
};

} // namespace sightline::ui
