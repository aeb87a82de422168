#pragma once
// The editor's main window: viewport in the centre, outline and properties docked, menus,
// toolbar and status bar. It wires the pieces together and owns file handling (open, save,
// recent files, unsaved-changes prompt, autosave to a recovery file); the behaviour itself lives
// in EditorDocument, ViewportController and the panels.

#include <array>
#include <optional>
#include <filesystem>
#include <memory>

#include <QMainWindow>
#include <QTimer>

#include "EditorDocument.h"
#include "ViewportController.h"

class QAction;
class QDockWidget;
class QLabel;
class QPushButton;
class QMenu;
class QToolBar;

namespace sightline::ui {

class LightCostPanel;
class OccluderAssistant;
class OutlinePanel;
class OverlayControls;
class OverlayLegend;
class PropertiesPanel;
class RecordingControls;
class Viewport;

struct VisibilityResult;
/// The status bar's line: "412,113 of 1,048,576 rays unblocked (39.3% visible) · 18.2 ms".
QString visibilitySummary(const VisibilityResult& result);

struct EditorOptions {
    bool offerRecovery = true;   ///< ask to restore a recovery file found at start-up
    /// --allow-outside-paths: for this run, whatever the saved setting (File menu) says.
    bool allowOutsidePaths = false;
};

class MainWindow : public QMainWindow {
    Q_OBJECT
public:
    explicit MainWindow(const EditorOptions& options = {}, QWidget* parent = nullptr);
    ~MainWindow() override;

    EditorDocument& document() { return document_; }
    ViewportController& controller() { return *controller_; }
    Viewport& viewport() { return *viewport_; }
    QWidget* viewportContainer() { return container_; }
    OverlayControls& overlayControls() { return *overlay_; }
    RecordingControls& recorder() { return *recorder_; }
    OccluderAssistant& occluderAssistant() { return *assistant_; }

    /// Opens a project or mesh file; on failure shows the one-line error and returns false.
    bool openFile(const QString& file);
    /// Shows a baked .pvs or .pvs.json of the open project in the PVS debugger (checked that it
    /// belongs to the level; else a message says why).
    bool openPvsFile(const QString& file);
    static bool isPvsFile(const QString& file);
    bool saveTo(const QString& file);
    /// Lights the AO preview with a Radiance .hdr environment; an unreadable file is a message.
    bool setAoEnvironment(const QString& file);
    /// The PVS distance cut-off (the project's pvs.max_distance, metres; 0 removes it), undoable.
    void setPvsDistanceCutoff(double metres);
    /// The viewport as it is now, to a PNG.
    bool screenshotTo(const QString& file);
    /// Where autosave writes (QStandardPaths::AppDataLocation/recovery.json).
    static QString recoveryPath();
    void autosave();

protected:
    void closeEvent(QCloseEvent* event) override;
    void dragEnterEvent(QDragEnterEvent* event) override;
    void dropEvent(QDropEvent* event) override;
    /// Undo and redo are the document's while a properties field has focus (a field would
    /// otherwise take Ctrl+Z for its own text).
    bool eventFilter(QObject* watched, QEvent* event) override;

private:
    /// A menu item with a shortcut whose trigger runs `slot` (defined and used in MainWindow.cpp).
    template <typename Slot>
    QAction* action(QMenu* menu, const QString& text, const QKeySequence& shortcut, Slot slot);
    void createActions();   // one builder per menu, in the menu bar's order
    void createFileMenu();
    void createEditMenu();
    void createCreateMenu();
    /// Create > Placing Size: the patch's own size or a preset, one checked.
    void addPlacingSizeItems(QMenu* create);
    /// Create's built-in box and plane occluders and the mesh occluder from a file.
    void addOccluderItems(QMenu* create);
    /// Create's occluder assistant items: show it, and add its suggestion (Enter).
    void addAssistantItems(QMenu* create);
    /// Create's lights: placed on a surface, the sun, or at the view's centre.
    void addLightItems(QMenu* create);
    void createTransformMenu();   // also the tools toolbar
    void createViewMenu();
    void addPanelsAndCameraItems(QMenu* view);
    void addShadingItems(QMenu* view);   // AO, the lit view and what it shows, O'Rorke's sets
    void addPvsDebuggerItems(QMenu* view);
    void addAoEnvironmentItems(QMenu* view);
    void addSectionCutItems(QMenu* view);
    void addRayItems(QMenu* view, QAction* wire);   // and the ray toolbar
    void addDisagreementItems(QMenu* view);
    void createHelpMenu();
    void createPanels();
    bool maybeSave();
    bool save();
    bool saveAs();
    void open();
    void updateTitle();
    void updateStatus();
    void updateRateLabel();
    /// The status bar's projection and gizmo-axes labels, and the View menu's Orthographic check.
    void updateViewLabel();
    void applySnap();
    /// " · the source is inside wall_middle" when a patch sits inside a closed object, else empty.
    QString enclosedPatchNote();
    void addRecentFile(const QString& file);
    void rebuildRecentMenu();
    void storeView();
    /// The section cut 1.5 m above the higher patch (on every open; navigation never moves it).
    void resetSectionCut();
    /// The folder dialogs start in: the open project's (or level's), else the working folder.
    std::filesystem::path projectFolder() const;

    EditorDocument document_;
    std::unique_ptr<ViewportController> controller_;
    Viewport* viewport_ = nullptr;
    OverlayLegend* disagreementKey_ = nullptr;   ///< updateDisagreementKey
    QWidget* container_ = nullptr;
    QDockWidget* outlineDock_ = nullptr;
    QDockWidget* propertiesDock_ = nullptr;
    OutlinePanel* outline_ = nullptr;
    PropertiesPanel* properties_ = nullptr;
    LightCostPanel* lightCosts_ = nullptr;
    QDockWidget* lightCostsDock_ = nullptr;
    OccluderAssistant* assistant_ = nullptr;
    QDockWidget* assistantDock_ = nullptr;
    /// The cost panel from the lit view's latest frame (when the panel is shown).
    void showLightCosts();
    /// Edit > Coarse Occluder: the selected level object's stand-in (CoarseOccluderDialog.h).
    void chooseCoarseOccluder();
    /// The disagreement view's key in the view's top-left corner: its colours and counts, or hidden.
    void updateDisagreementKey();
    QMenu* recentMenu_ = nullptr;
    QLabel* raysLabel_ = nullptr;
    QPushButton* fixPairButton_ = nullptr;
    QLabel* backendLabel_ = nullptr;
    QLabel* viewLabel_ = nullptr;
    QLabel* spaceLabel_ = nullptr;
    QAction* spaceAction_ = nullptr;
    QAction* orthoAction_ = nullptr;
    QMenu* viewMenu_ = nullptr;
    QAction* cutAction_ = nullptr;
    QAction* disagreementLast_ = nullptr;   ///< the disagreement mode Ctrl+Shift+D turns on
    std::optional<std::array<glm::dvec3, 2>> enclosedFor_;   ///< patch centres enclosedNote_ was found for
    QString enclosedNote_;
    /// Patches that look misplaced (PatchWarnings.h), as " · ..." for the status line.
    QString patchWarningNote();
    std::optional<std::array<glm::dvec3, 7>> warningsFor_, warningsWanted_;
    QString warningNote_;
    QTimer warningTimer_;   ///< the patches' rest before their warnings are looked for
    QToolBar* toolbar_ = nullptr;
    OverlayControls* overlay_ = nullptr;
    RecordingControls* recorder_ = nullptr;
    QTimer autosaveTimer_;
    QTimer rateTimer_;
    QAction* snapAction_ = nullptr;
    double gridStep_ = 0.25;   ///< metres
};

} // namespace sightline::ui
