#include "MainWindow.h"

#include "editor/LightObjects.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCloseEvent>
#include <QComboBox>
#include <QDir>
#include <QDockWidget>
#include <QAbstractItemView>
#include <QAbstractSpinBox>
#include <QPushButton>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QKeyEvent>
#include <QLabel>
#include <QLineEdit>
#include <QLocale>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QSettings>
#include <QStandardPaths>
#include <QStatusBar>
#include <QToolBar>

#include <cmath>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

#include "CoarseOccluderDialog.h"
#include "EditCommands.h"
#include "ImportSettingsDialog.h"
#include "LightCostPanel.h"
#include "OccluderAssistant.h"
#include "OutlinePanel.h"
#include "editor/PatchPairFix.h"
#include "editor/PatchWarnings.h"
#include "editor/PatchPresets.h"
#include "OverlayControls.h"
#include "OverlayLegend.h"
#include "editor/Picking.h"
#include "PreferencesDialog.h"
#include "PropertiesPanel.h"
#include "RecordingControls.h"
#include "editor/ViewSettings.h"
#include "Viewport.h"
#include "plugins/SceneFormats.h"
#include "project/Approximation.h"
#include "report/PngFile.h"
#include "base/Error.h"

namespace sightline::ui {

namespace {
constexpr int kMaxRecentFiles = 8;
constexpr int kAutosaveMs = 60'000;
constexpr const char* kAllowOutsidePathsKey = "files/allowOutsidePaths";
} // namespace

template <typename Slot>
QAction* MainWindow::action(QMenu* menu, const QString& text, const QKeySequence& shortcut, Slot slot)
{
    QAction* a = menu->addAction(text);
    a->setShortcut(shortcut);
    connect(a, &QAction::triggered, this, slot);
    return a;
}

QString visibilitySummary(const VisibilityResult& result)
{
    if (!result.valid) {
        // The error says what is wrong ("invalid patch pair: the receiver touches ..."): as is.
        QString error = QString::fromStdString(result.error);
        if (!error.isEmpty())
            error[0] = error[0].toUpper();
        return error;
    }
    const QLocale locale(QLocale::English);
    return QObject::tr("%1 of %2 rays unblocked (%3% visible) · %4 ms")
        .arg(locale.toString(qulonglong(result.unblocked())), locale.toString(qulonglong(result.rays)))
        .arg(100.0 * result.visibleFraction(), 0, 'f', 1)
        .arg(result.ms, 0, 'f', 1);
}

MainWindow::MainWindow(const EditorOptions& options, QWidget* parent) : QMainWindow(parent)
{
    controller_ = std::make_unique<ViewportController>(document_);
    controller_->setSpeeds(loadNavigationSpeeds());
    viewport_ = new Viewport(document_, *controller_);
    container_ = QWidget::createWindowContainer(viewport_, this);
    container_->setMinimumSize(320, 240);
    container_->setFocusPolicy(Qt::StrongFocus);
    setCentralWidget(container_);
    setAcceptDrops(true);

    document_.setAllowOutsidePaths(options.allowOutsidePaths || QSettings().value(kAllowOutsidePathsKey).toBool());
    createPanels();
    createActions();
    qApp->installEventFilter(this);

    warningTimer_.setSingleShot(true);
    warningTimer_.setInterval(250);
    connect(&warningTimer_, &QTimer::timeout, this, &MainWindow::updateStatus);
    raysLabel_ = new QLabel(this);
    raysLabel_->setObjectName("raysLabel");
    backendLabel_ = new QLabel(this);
    viewLabel_ = new QLabel(this);
    viewLabel_->setObjectName("viewLabel");
    viewLabel_->setToolTip(tr("The projection (5 switches it)"));
    statusBar()->addWidget(raysLabel_, 1);
    // An invalid pair's fix in one click (PatchPairFix.h), beside the message that says why.
    fixPairButton_ = new QPushButton(this);
    fixPairButton_->setObjectName("fixPatchPair");
    fixPairButton_->setFlat(true);
    fixPairButton_->hide();
    statusBar()->addPermanentWidget(fixPairButton_);   // never hidden by a passing message
    connect(fixPairButton_, &QPushButton::clicked, this, [this] {
        const Project& project = document_.project();
        const auto fix = fixPatchPair(project.source, project.receiver, document_.selection().kind == ObjectKind::Source);
        if (!fix)
            return;
        const ObjectRef patch{fix->source ? ObjectKind::Source : ObjectKind::Receiver, 0};
        document_.setState(patch, fix->patch, tr("Fix patch pair"));
        statusBar()->showMessage(tr("Done: %1 (Ctrl+Z undoes)").arg(QString::fromStdString(fix->description)), 5000);
    });
    spaceLabel_ = new QLabel(this);
    spaceLabel_->setObjectName("spaceLabel");
    spaceLabel_->setToolTip(tr("The gizmo's axes for moving and rotating (X switches world / local)"));
    statusBar()->addPermanentWidget(spaceLabel_);
    statusBar()->addPermanentWidget(viewLabel_);
    statusBar()->addPermanentWidget(backendLabel_);
    updateViewLabel();
    overlay_ = new OverlayControls(*this, document_, *viewport_, *controller_, container_, viewMenu_, toolbar_);
    recorder_ = new RecordingControls(*this, document_, *viewport_, *controller_, toolbar_);
    connect(viewport_, &Viewport::visibilityUpdated, this, &MainWindow::updateStatus);
    connect(viewport_, &Viewport::backendChosen, this, [this](const QString& report) {
        backendLabel_->setToolTip(report);
        updateStatus();
    });
    connect(viewport_, &Viewport::filesDropped, this, [this](const QStringList& files) {
        if (maybeSave())
            openFile(files.front());
    });
    connect(controller_.get(), &ViewportController::message, this, [this](const QString& text) { statusBar()->showMessage(text, 5000); });
    connect(&document_, &EditorDocument::modifiedChanged, this, &MainWindow::updateTitle);
    connect(&document_, &EditorDocument::fileChanged, this, &MainWindow::updateTitle);
    connect(&document_, &EditorDocument::changed, this, [this](unsigned changes) {
        if (changes & DocumentReset) {
            controller_->setCamera(projectView(document_.editorSettings(), document_.project().source, document_.project().receiver));
            resetSectionCut();
        }
    });

    QSettings settings;
    restoreGeometry(settings.value("window/geometry").toByteArray());
    restoreState(settings.value("window/state").toByteArray());
    if (!settings.contains("window/geometry"))
        resize(1600, 900);

    // The update rate falls to "idle" when nothing changes (it kept the last drag's figure).
    rateTimer_.setInterval(500);
    connect(&rateTimer_, &QTimer::timeout, this, &MainWindow::updateRateLabel);
    rateTimer_.start();

    autosaveTimer_.setInterval(kAutosaveMs);
    connect(&autosaveTimer_, &QTimer::timeout, this, &MainWindow::autosave);
    autosaveTimer_.start();

    controller_->setCamera(shaftView(document_.project().source, document_.project().receiver));
    controller_->setStyle(&viewport_->style());
    resetSectionCut();
    updateTitle();

    if (options.offerRecovery && QFileInfo::exists(recoveryPath())) {
        const auto answer = QMessageBox::question(this, tr("Recover unsaved work"),
                                                  tr("Sightline closed with unsaved changes. Open the recovered project?"));
        if (answer == QMessageBox::Yes && openFile(recoveryPath()))
            document_.undoStack()->resetClean();   // recovered work is unsaved work
        QFile::remove(recoveryPath());
    }
}

MainWindow::~MainWindow() = default;

void MainWindow::createPanels()
{
    outline_ = new OutlinePanel(document_, this);
    outlineDock_ = new QDockWidget(tr("Outline"), this);
    outlineDock_->setObjectName("outline");
    outlineDock_->setWidget(outline_);
    addDockWidget(Qt::LeftDockWidgetArea, outlineDock_);

    properties_ = new PropertiesPanel(document_, this);
    propertiesDock_ = new QDockWidget(tr("Properties"), this);
    propertiesDock_->setObjectName("properties");
    propertiesDock_->setWidget(properties_);
    addDockWidget(Qt::RightDockWidgetArea, propertiesDock_);

    lightCosts_ = new LightCostPanel(this);
    lightCostsDock_ = new QDockWidget(tr("Light Costs"), this);
    lightCostsDock_->setObjectName("lightCosts");
    lightCostsDock_->setWidget(lightCosts_);
    addDockWidget(Qt::RightDockWidgetArea, lightCostsDock_);
    lightCostsDock_->hide();   // offered with the lit view (View > Lit View Shows > Light Costs Panel)
    connect(lightCosts_, &LightCostPanel::lightChosen, this, [this](int index) {
        if (index >= 0 && std::size_t(index) < document_.lights().size())
            document_.select({ObjectKind::Light, std::size_t(index)});
    });
    connect(lightCostsDock_, &QDockWidget::visibilityChanged, this, [this](bool shown) {
        if (shown)
            showLightCosts();
    });

    assistant_ = new OccluderAssistant(document_, *viewport_, *controller_, this);
    assistantDock_ = new QDockWidget(tr("Occluder Assistant"), this);
    assistantDock_->setObjectName("occluderAssistant");
    assistantDock_->setWidget(assistant_);
    addDockWidget(Qt::RightDockWidgetArea, assistantDock_);
    assistantDock_->hide();   // Create > Suggest Occluder (Ctrl+Alt+B)
    connect(assistantDock_, &QDockWidget::visibilityChanged, assistant_, &OccluderAssistant::setActive);
    connect(viewport_, &Viewport::visibilityUpdated, assistant_, &OccluderAssistant::refresh);
    connect(assistant_, &OccluderAssistant::added, this, [this](const QString& status) { statusBar()->showMessage(status, 8000); });
}

void MainWindow::showLightCosts()
{
    if (!lightCostsDock_->isVisible())
        return;
    if (!viewport_->style().litView || viewport_->litCosts().empty()) {
        lightCosts_->clear(tr("Turn on the lit view (View > Lit View, I) to see what each light costs."));
        return;
    }
    std::vector<QString> names;
    for (std::size_t l = 0; l < document_.lights().size(); ++l)
        names.push_back(document_.objectName({ObjectKind::Light, l}));
    lightCosts_->showCosts(viewport_->litCosts(), names);
}

bool MainWindow::eventFilter(QObject* watched, QEvent* event)
{
    if (event->type() == QEvent::ShortcutOverride) {
        auto* key = static_cast<QKeyEvent*>(event);
        auto* widget = qobject_cast<QWidget*>(watched);
        const bool undoKey = key->matches(QKeySequence::Undo) || key->matches(QKeySequence::Redo) ||
                             (key->modifiers() == Qt::ControlModifier && key->key() == Qt::Key_Y);
        if (undoKey && widget && properties_ && properties_->isAncestorOf(widget)) {
            event->ignore();   // not overridden: the Edit menu's shortcut runs
            return true;
        }
        const bool enterKey = (key->key() == Qt::Key_Return || key->key() == Qt::Key_Enter) &&
                              (key->modifiers() & ~Qt::KeypadModifier) == Qt::NoModifier;
        const bool field = qobject_cast<QLineEdit*>(widget) || qobject_cast<QAbstractSpinBox*>(widget) ||
                           qobject_cast<QComboBox*>(widget) || qobject_cast<QAbstractItemView*>(widget);
        if (enterKey && field && !(assistantDock_ && assistantDock_->isAncestorOf(widget))) {
            event->accept();   // overridden: Enter commits the field's edit, it adds no occluder
            return true;
        }
    }
    return QMainWindow::eventFilter(watched, event);
}

std::filesystem::path MainWindow::projectFolder() const
{
    // Where the open project (or level) lies; the working folder for a new document.
    if (!document_.filePath().empty())
        return std::filesystem::absolute(document_.filePath()).parent_path();
    if (!document_.project().folder.empty())   // a level opened without a project
        return document_.project().folder;
    return std::filesystem::current_path();
}

void MainWindow::setPvsDistanceCutoff(double metres)
{
    // The project's pvs.max_distance (undoable); the debugger shows it over the bake at once and
    // `pvs bake` culls by it.
    const auto it = document_.project().extra.find("pvs");
    const nlohmann::json before = it != document_.project().extra.end() ? *it : nlohmann::json();
    nlohmann::json after = before.is_object() ? before : nlohmann::json::object();
    if (metres > 0.0)
        after["max_distance"] = metres;
    else
        after.erase("max_distance");
    if (after == before)
        return;
    document_.undoStack()->push(new SetProjectKeyCommand(document_, "pvs", before, after,
                                                         metres > 0.0 ? tr("PVS cut-off %1 m").arg(metres) : tr("No PVS cut-off")));
}

void MainWindow::resetSectionCut()
{
    const Project& project = document_.project();
    ViewStyle& style = viewport_->style();
    style.cutHeight = std::max(project.source.centre().y, project.receiver.centre().y) + 1.5;
    // The cut looks into rooms past their ceilings. Where both patches stand under open sky (a
    // terrain, a courtyard) it has no ceiling to remove and would only hide the hills and roofs
    // between them (a terrain opened as dark holes where its hills were cut): it starts off.
    style.cutaway = !(controller_->openSkyAbove(project.source.centre()) && controller_->openSkyAbove(project.receiver.centre()));
    if (cutAction_)
        cutAction_->setChecked(style.cutaway);
    viewport_->requestUpdate();
}

void MainWindow::createActions()
{
    createFileMenu();
    createEditMenu();
    createCreateMenu();
    createTransformMenu();
    createViewMenu();
    createHelpMenu();
}

void MainWindow::createFileMenu()
{
    QMenu* file = menuBar()->addMenu(tr("&File"));
    action(file, tr("&New"), QKeySequence::New, [this] {
        if (maybeSave())
            document_.newDocument();
    });
    action(file, tr("&Open..."), QKeySequence::Open, [this] { open(); });
    recentMenu_ = file->addMenu(tr("Open &Recent"));
    recentMenu_->setObjectName("recentMenu");
    rebuildRecentMenu();
    QAction* openPvs = action(file, tr("Open &PVS..."), QKeySequence(), [this] {
        const QString chosen = QFileDialog::getOpenFileName(this, tr("Open PVS"), QString::fromStdString(projectFolder().string()),
                                                            tr("Baked PVS (*.pvs *.pvs.json)"));
        if (!chosen.isEmpty())
            openPvsFile(chosen);
    });
    openPvs->setObjectName("openPvs");
    action(file, tr("&Save"), QKeySequence::Save, [this] { save(); });
    // QKeySequence::SaveAs has no binding outside KDE and GNOME (e.g. under Xvfb): spelled out.
    action(file, tr("Save &As..."), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_S), [this] { saveAs(); });
    file->addSeparator();
    action(file, tr("Save Screens&hot..."), QKeySequence(Qt::Key_F12), [this] {
        // Beside the project, numbered: repeated F12 presses never overwrite an earlier image.
        const std::string stem = document_.filePath().empty() ? "sightline" : document_.filePath().stem().string();
        const QString suggested = QString::fromStdString(nextNumberedFile(projectFolder(), stem).string());
        const QString path = QFileDialog::getSaveFileName(this, tr("Save Screenshot"), suggested, tr("PNG images (*.png)"));
        if (!path.isEmpty())
            screenshotTo(path);
    });
    file->addSeparator();
    QAction* importSettings = action(file, tr("&Import Settings..."), QKeySequence(), [this] {
        ImportSettingsDialog dialog(document_.sceneImportSettings(), document_.guessedFileUp(), this);
        if (dialog.exec() != QDialog::Accepted)
            return;
        try {
            document_.setSceneImportSettings(dialog.settings());
        } catch (const std::exception& e) {
            QMessageBox::warning(this, tr("Import Settings"), QString::fromStdString(e.what()));
        }
    });
    importSettings->setObjectName("importSettingsAction");
    // The project-path rule (base/PathRule.h): a file someone sent must not read files
    // outside its folder unless the user says so; the choice is remembered.
    QAction* outside = file->addAction(tr("Allow Project Paths &Outside Its Folder"));
    outside->setCheckable(true);
    outside->setChecked(document_.allowOutsidePaths());
    connect(outside, &QAction::toggled, this, [this](bool allow) {
        document_.setAllowOutsidePaths(allow);
        QSettings().setValue(kAllowOutsidePathsKey, allow);
    });
    file->addSeparator();
    action(file, tr("&Quit"), QKeySequence::Quit, [this] { close(); });
}

void MainWindow::createEditMenu()
{
    QMenu* edit = menuBar()->addMenu(tr("&Edit"));
    QAction* undo = document_.undoStack()->createUndoAction(this, tr("&Undo"));
    undo->setShortcut(QKeySequence::Undo);
    QAction* redo = document_.undoStack()->createRedoAction(this, tr("&Redo"));
    redo->setShortcuts({QKeySequence::Redo, QKeySequence(Qt::CTRL | Qt::Key_Y)});
    edit->addAction(undo);
    edit->addAction(redo);
    edit->addSeparator();
    action(edit, tr("&Duplicate"), QKeySequence(Qt::CTRL | Qt::Key_D), [this] { document_.duplicateSelected(); });
    action(edit, tr("&Find Object..."), QKeySequence::Find, [this] {
        outlineDock_->show();
        outline_->searchField()->setFocus();
        outline_->searchField()->selectAll();
    });
    action(edit, tr("De&lete"), QKeySequence::Delete, [this] {
        // Only placed occluders are the project's to delete; say so instead of doing nothing.
        const ObjectRef selected = document_.selection();
        if (selected.kind == ObjectKind::SceneObject)
            statusBar()->showMessage(tr("%1 is part of the level file and cannot be deleted here: move it (W) or edit the level")
                                         .arg(document_.objectName(selected)), 6000);
        else if (selected.kind == ObjectKind::Source || selected.kind == ObjectKind::Receiver)
            statusBar()->showMessage(tr("The source and the receiver cannot be deleted: move them, or place them again (Ctrl+1, Ctrl+2)"), 6000);
        else if (selected && document_.flags(selected).locked)
            statusBar()->showMessage(tr("%1 is locked: Ctrl+L unlocks it").arg(document_.objectName(selected)), 6000);
        else
            document_.removeSelected();
    });
    // Hide, isolate, lock (ObjectFlags.h): Blender's and Unity's H and Shift+H; Ctrl+Shift+H shows
    // all, Ctrl+L locks.
    edit->addSeparator();
    const auto flagSelection = [this](bool hide) {
        const ObjectRef selected = document_.selection();
        if (!selected) {
            statusBar()->showMessage(tr("Select an object first (in the view or the outline)"), 4000);
            return;
        }
        ObjectFlags flags = document_.flags(selected);
        const QString name = document_.objectName(selected);
        if (hide) {
            flags.hidden = !flags.hidden;
            document_.setFlags(selected, flags, (flags.hidden ? tr("Hide %1") : tr("Show %1")).arg(name));
            statusBar()->showMessage(flags.hidden ? tr("%1 hidden: not drawn, not picked; it still blocks rays (H shows it, Ctrl+Shift+H shows all)").arg(name)
                                                  : tr("%1 shown").arg(name),
                                     5000);
        } else {
            flags.locked = !flags.locked;
            document_.setFlags(selected, flags, (flags.locked ? tr("Lock %1") : tr("Unlock %1")).arg(name));
            statusBar()->showMessage(flags.locked ? tr("%1 locked: clicks pass through it, it cannot be moved (Ctrl+L unlocks)").arg(name)
                                                  : tr("%1 unlocked").arg(name),
                                     5000);
        }
    };
    QAction* hide = action(edit, tr("&Hide / Show Selected"), QKeySequence(Qt::Key_H), [flagSelection] { flagSelection(true); });
    hide->setObjectName("hideSelected");
    QAction* isolate = action(edit, tr("&Isolate Selected"), QKeySequence(Qt::SHIFT | Qt::Key_H), [this] {
        if (document_.isolated()) {
            document_.setIsolated({});
            statusBar()->showMessage(tr("Isolation ended"), 3000);
        } else if (const ObjectRef selected = document_.selection()) {
            document_.setIsolated(selected);
            statusBar()->showMessage(tr("Isolating %1: only it and the patches are drawn and picked (Shift+H ends it)")
                                         .arg(document_.objectName(selected)), 5000);
        } else {
            statusBar()->showMessage(tr("Select the object to isolate first"), 4000);
        }
    });
    isolate->setObjectName("isolateSelected");
    // Not Blender's Alt+H: that opens the Help menu here.
    QAction* showAll = action(edit, tr("Show &All"), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_H), [this] {
        document_.showAll();
        statusBar()->showMessage(tr("Every object shown"), 3000);
    });
    showAll->setObjectName("showAll");
    QAction* lock = action(edit, tr("&Lock / Unlock Selected"), QKeySequence(Qt::CTRL | Qt::Key_L), [flagSelection] { flagSelection(false); });
    lock->setObjectName("lockSelected");
    QAction* coarse = action(edit, tr("&Coarse Occluder..."), QKeySequence(Qt::CTRL | Qt::ALT | Qt::Key_C), [this] { chooseCoarseOccluder(); });
    coarse->setObjectName("coarseOccluder");
    outline_->setContextActions({hide, isolate, showAll, lock, coarse});
    edit->addSeparator();
    // The designer's own settings (QSettings, not the project): orbit and fly speeds.
    action(edit, tr("&Preferences..."), QKeySequence(Qt::CTRL | Qt::Key_Comma), [this] {
        PreferencesDialog dialog(controller_->speeds(), this);
        if (dialog.exec() != QDialog::Accepted)
            return;
        controller_->setSpeeds(dialog.speeds());
        saveNavigationSpeeds(dialog.speeds());
    })->setObjectName("preferences");
    action(edit, tr("Select &None"), QKeySequence(Qt::Key_Escape), [this] {
        controller_->setTool(Tool::Select);
        document_.select({});
    });
}

void MainWindow::chooseCoarseOccluder()
{
    const ObjectRef selected = document_.selection();
    if (selected.kind != ObjectKind::SceneObject) {
        statusBar()->showMessage(tr("Select an object of the level first: a coarse stand-in answers the rays in place of its mesh"), 5000);
        return;
    }
    const Scene& level = document_.sceneFile();
    const Mesh& mesh = level.meshes.at(level.instances.at(selected.index).mesh);
    std::optional<CoarseOccluder> current;
    for (const CoarseOccluder& standIn : document_.coarseOccluders())
        if (standIn.instance == selected.index)
            current = standIn;
    const QString name = document_.objectName(selected);
    CoarseMeasureInput measure{.scene = std::make_shared<const Scene>(document_.scene()),
                               .instance = selected.index,
                               .source = document_.project().source,
                               .receiver = document_.project().receiver,
                               .heights = nullptr};
    if (!viewport_->receiverHeights().empty())
        measure.heights = std::make_shared<const ReceiverHeights>(viewport_->receiverHeights());
    CoarseOccluderDialog dialog(name, mesh.triangleCount(), closedAndOutward(mesh), current, std::move(measure), this);
    if (dialog.exec() != QDialog::Accepted)
        return;
    const std::optional<CoarseOccluder> choice = dialog.choice();
    QString done = tr("%1: its rays answered by its full mesh again").arg(name);
    QApplication::setOverrideCursor(Qt::WaitCursor);   // simplifying a dense mesh takes seconds
    try {
        document_.setCoarseOccluder(selected.index, choice);
        if (choice)
            done = tr("%1: its rays answered by a stand-in of %2 triangles (the mesh has %3); the view still draws the "
                      "full mesh; Ctrl+Z undoes")
                       .arg(name, QLocale().toString(qulonglong(document_.standInTriangles(selected.index, *choice))),
                            QLocale().toString(qulonglong(mesh.triangleCount())));
    } catch (const Error& e) {
        QApplication::restoreOverrideCursor();
        QMessageBox::warning(this, tr("Coarse Occluder"), QString::fromStdString(e.what()));
        return;
    }
    QApplication::restoreOverrideCursor();
    statusBar()->showMessage(done, 8000);
}

void MainWindow::createCreateMenu()
{
    QMenu* create = menuBar()->addMenu(tr("&Create"));
    action(create, tr("Place &Source on Surface"), QKeySequence(Qt::CTRL | Qt::Key_1), [this] { controller_->setTool(Tool::PlaceSource); });
    action(create, tr("Place &Receiver on Surface"), QKeySequence(Qt::CTRL | Qt::Key_2), [this] { controller_->setTool(Tool::PlaceReceiver); });
    addPlacingSizeItems(create);
    create->addSeparator();
    addOccluderItems(create);
    create->addSeparator();
    addAssistantItems(create);
    create->addSeparator();
    addLightItems(create);
}

void MainWindow::addPlacingSizeItems(QMenu* create)
{
    // The size placing gives a patch: its own, or a preset, checked in the menu.
    QMenu* placingSize = create->addMenu(tr("Placing Si&ze"));
    placingSize->setObjectName("placingSize");
    auto* sizes = new QActionGroup(this);
    QAction* keep = placingSize->addAction(tr("The Patch's Own Size"), this, [this] { controller_->setPlacementSize(std::nullopt); });
    keep->setCheckable(true);
    keep->setChecked(true);
    sizes->addAction(keep);
    for (const PatchPreset& preset : patchPresets()) {
        const QString name = QString::fromUtf8(preset.name.data(), qsizetype(preset.name.size()));
        QAction* a = placingSize->addAction(tr("%1 %2 × %3 m").arg(name).arg(preset.width, 0, 'g', 3).arg(preset.height, 0, 'g', 3), this,
                                            [this, preset] { controller_->setPlacementSize(std::pair(preset.width, preset.height)); });
        a->setCheckable(true);
        a->setObjectName("placingSize-" + name);
        sizes->addAction(a);
    }
}

void MainWindow::addOccluderItems(QMenu* create)
{
    auto addBuiltin = [this](const std::string& mesh) {
        OccluderSpec spec;
        spec.mesh = mesh;
        spec.name = mesh + " " + std::to_string(document_.project().occluders.size() + 1);
        // One metre in size, in the shaft halfway between the patches when that is on screen (a
        // plane across it), else at the orbit target (it landed half inside a wall there).
        const Project& project = document_.project();
        const glm::dvec3 middle = 0.5 * (project.source.centre() + project.receiver.centre());
        const glm::dvec3 pixel = toPixels(controller_->camera(), middle, controller_->width(), controller_->height());
        const bool onScreen = pixel.z > 0.0 && pixel.x >= 0.0 && pixel.x <= controller_->width() && pixel.y >= 0.0 &&
                              pixel.y <= controller_->height();
        const glm::dvec3 at = onScreen ? middle : controller_->camera().target;
        spec.transform = glm::translate(glm::mat4(1.0f), glm::vec3(at));
        const glm::dvec3 way = project.receiver.centre() - project.source.centre();
        if (onScreen && mesh == "plane" && glm::length(way) > 1e-9) {   // its normal (+Y) along the shaft
            const glm::dvec3 n = glm::normalize(way);
            const glm::dvec3 axis = glm::cross(glm::dvec3(0.0, 1.0, 0.0), n);
            const double angle = std::acos(std::clamp(n.y, -1.0, 1.0));
            if (glm::length(axis) > 1e-9)
                spec.transform = glm::rotate(spec.transform, float(angle), glm::vec3(glm::normalize(axis)));
        }
        document_.addOccluder(spec);
    };
    action(create, tr("Add &Box Occluder"), QKeySequence(Qt::CTRL | Qt::Key_B), [=] { addBuiltin("box"); });
    action(create, tr("Add &Plane Occluder"), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_B), [=] { addBuiltin("plane"); });
    action(create, tr("Add &Mesh Occluder..."), QKeySequence(), [this] {
        const QString filter = tr("Meshes (%1)").arg(QString::fromStdString(SceneFormatRegistry::builtin().importFilter()));
        const QString path = QFileDialog::getOpenFileName(this, tr("Add Mesh Occluder"), QString::fromStdString(projectFolder().string()), filter);
        if (path.isEmpty())
            return;
        OccluderSpec spec;
        spec.mesh = path.toStdString();
        spec.name = QFileInfo(path).baseName().toStdString();
        spec.transform = glm::translate(glm::mat4(1.0f), glm::vec3(controller_->camera().target));
        try {
            document_.addOccluder(spec);
        } catch (const std::exception& e) {
            QMessageBox::warning(this, tr("Add Mesh Occluder"), QString::fromUtf8(e.what()));
        }
    });
}

void MainWindow::addAssistantItems(QMenu* create)
{
    // The occluder assistant: the smallest occluder that cuts the view, as a ghost; Enter adds it
    // (except in the fields and lists outside the assistant, where Enter stays their own:
    // eventFilter).
    action(create, tr("Suggest &Occluder..."), QKeySequence(Qt::CTRL | Qt::ALT | Qt::Key_B), [this] {
        assistantDock_->show();
        assistantDock_->raise();
        resizeDocks({assistantDock_}, {assistant_->minimumSizeHint().height() + 40}, Qt::Vertical);
    })->setObjectName("suggestOccluder");
    QAction* addSuggested = action(create, tr("Add Suggested Occluder"), QKeySequence(Qt::Key_Return), [this] {
        QString status;
        assistant_->addSuggestion(&status);
        statusBar()->showMessage(status, 8000);
    });
    addSuggested->setObjectName("addSuggestedOccluder");
    addSuggested->setShortcuts({QKeySequence(Qt::Key_Return), QKeySequence(Qt::Key_Enter)});
    addSuggested->setEnabled(false);
    connect(assistant_, &OccluderAssistant::suggestionChanged, addSuggested,
            [this, addSuggested] { addSuggested->setEnabled(assistant_->suggestion().has_value()); });
}

void MainWindow::addLightItems(QMenu* create)
{
    // Lights on the surface a click picks (as the patches are placed), or at once at the orbit
    // target, half a metre up (in a room the target is usually on or over the floor); selected so
    // that the gizmo and the properties take them at once.
    action(create, tr("Place Point &Light on Surface"), QKeySequence(Qt::CTRL | Qt::Key_3), [this] { controller_->setTool(Tool::PlacePointLight); })
        ->setObjectName("addPointLight");
    action(create, tr("Place Sp&ot Light on Surface"), QKeySequence(Qt::CTRL | Qt::Key_4), [this] { controller_->setTool(Tool::PlaceSpotLight); })
        ->setObjectName("addSpotLight");
    action(create, tr("Place &Area Light on Surface"), QKeySequence(Qt::CTRL | Qt::Key_5), [this] { controller_->setTool(Tool::PlaceAreaLight); })
        ->setObjectName("addAreaLight");
    auto addLight = [this](LightType type, const QString& kind) {
        const glm::dvec3 at = controller_->camera().target + glm::dvec3(0.0, 0.5, 0.0);
        const std::string name = kind.toStdString() + " " + std::to_string(document_.lights().size() + 1);
        try {
            document_.addLight(newLightJson(type, at, name));
        } catch (const std::exception& e) {
            QMessageBox::warning(this, tr("Add Light"), QString::fromUtf8(e.what()));
        }
    };
    action(create, tr("Add S&un"), QKeySequence(Qt::CTRL | Qt::Key_6), [=] { addLight(LightType::Directional, tr("Sun")); })
        ->setObjectName("addSun");
    QMenu* atCentre = create->addMenu(tr("Add Light at the View's &Centre"));
    atCentre->setObjectName("addLightAtCentre");
    action(atCentre, tr("&Point Light"), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_3), [=] { addLight(LightType::Point, tr("Point light")); })
        ->setObjectName("addPointLightAtCentre");
    action(atCentre, tr("&Spot Light"), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_4), [=] { addLight(LightType::Spot, tr("Spot light")); })
        ->setObjectName("addSpotLightAtCentre");
    action(atCentre, tr("&Area Light"), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_5), [=] { addLight(LightType::Area, tr("Area light")); })
        ->setObjectName("addAreaLightAtCentre");
}

void MainWindow::createTransformMenu()
{
    QMenu* transform = menuBar()->addMenu(tr("&Transform"));
    auto* modes = new QActionGroup(this);
    const std::pair<QString, GizmoMode> modeList[] = {{tr("&Move"), GizmoMode::Move}, {tr("&Rotate"), GizmoMode::Rotate}, {tr("&Scale"), GizmoMode::Scale}};
    const Qt::Key modeKeys[] = {Qt::Key_W, Qt::Key_E, Qt::Key_R};
    toolbar_ = addToolBar(tr("Tools"));
    toolbar_->setObjectName("tools");
    for (int i = 0; i < 3; ++i) {
        QAction* a = action(transform, modeList[i].first, QKeySequence(modeKeys[i]), [this, mode = modeList[i].second] { controller_->setGizmoMode(mode); });
        a->setCheckable(true);
        a->setChecked(i == 0);
        modes->addAction(a);
        toolbar_->addAction(a);
    }
    // World or local axes for moving and rotating (X, as Unity's pivot rotation toggle).
    transform->addSeparator();
    spaceAction_ = action(transform, tr("&Local Axes"), QKeySequence(Qt::Key_X), [this](bool local) {
        controller_->setGizmoSpace(local ? GizmoSpace::Local : GizmoSpace::World);
        statusBar()->showMessage(local ? tr("Local axes: moves and turns follow the object's own axes (X: world)")
                                       : tr("World axes: moves and turns follow the world's X, Y, Z (X: local)"),
                                 3000);
    });
    spaceAction_->setCheckable(true);
    spaceAction_->setObjectName("localAxes");
    spaceAction_->setToolTip(tr("Move and rotate along the object's own axes (X)"));
    toolbar_->addAction(spaceAction_);
    connect(controller_.get(), &ViewportController::gizmoSpaceChanged, this, [this](GizmoSpace space) {
        const QSignalBlocker quiet(spaceAction_);
        spaceAction_->setChecked(space == GizmoSpace::Local);
        updateViewLabel();
    });
    // Snapping: a world grid for moves ([ and ] halve and double it, as in
    // TrenchBroom), 15 degree steps for rotations, 10% steps for scaling.
    transform->addSeparator();
    action(transform, tr("&Drop to Floor"), QKeySequence(Qt::Key_End), [this] { controller_->dropSelectionToFloor(); })
        ->setObjectName("dropToFloor");
    snapAction_ = action(transform, tr("S&nap"), QKeySequence(Qt::Key_G), [this](bool) { applySnap(); });
    snapAction_->setCheckable(true);
    snapAction_->setObjectName("snap");
    toolbar_->addAction(snapAction_);
    action(transform, tr("Finer Grid"), QKeySequence(Qt::Key_BracketLeft), [this] {
        gridStep_ = std::max(gridStep_ / 2.0, 1.0 / 64.0);
        applySnap();
    });
    action(transform, tr("Coarser Grid"), QKeySequence(Qt::Key_BracketRight), [this] {
        gridStep_ = std::min(gridStep_ * 2.0, 64.0);
        applySnap();
    });
    toolbar_->addSeparator();
}

void MainWindow::createViewMenu()
{
    QMenu* view = menuBar()->addMenu(tr("&View"));
    viewMenu_ = view;
    addPanelsAndCameraItems(view);
    QAction* wire = action(view, tr("&Wireframe"), QKeySequence(Qt::Key_Z), [this](bool on) {
        viewport_->style().wireframe = on;
        viewport_->requestUpdate();
    });
    wire->setCheckable(true);
    addShadingItems(view);
    addPvsDebuggerItems(view);
    addAoEnvironmentItems(view);
    addSectionCutItems(view);
    addRayItems(view, wire);
    addDisagreementItems(view);
}

void MainWindow::addPanelsAndCameraItems(QMenu* view)
{
    // A closed panel comes back from here (once closed, it stayed closed).
    QMenu* panels = view->addMenu(tr("&Panels"));
    for (QDockWidget* dock : {outlineDock_, propertiesDock_, lightCostsDock_, assistantDock_}) {
        QAction* toggle = dock->toggleViewAction();
        toggle->setObjectName("panel-" + dock->objectName());
        panels->addAction(toggle);
    }
    view->addSeparator();
    action(view, tr("&Frame Selection"), QKeySequence(Qt::Key_F), [this] { controller_->frameSelection(); });
    // Camera presets. Looking through a patch puts the eye on it, where the section
    // cut (which hides the near half of the way) would hide the view: it is switched off.
    QMenu* cameraMenu = view->addMenu(tr("&Camera"));
    const auto sceneBounds = [this] {
        Bounds bounds = document_.scene().bounds();
        if (bounds.empty())
            bounds.extend(glm::vec3(0.0f));
        return bounds;
    };
    action(cameraMenu, tr("Frame &All"), QKeySequence(Qt::Key_Home), [this, sceneBounds] {
        controller_->setCamera(overviewCamera(sceneBounds()));
        viewport_->update();
    });
    const std::pair<QString, std::pair<AxisView, Qt::Key>> axes[] = {
        {tr("&Top"), {AxisView::Top, Qt::Key_7}}, {tr("&Front"), {AxisView::Front, Qt::Key_1}}, {tr("&Side"), {AxisView::Side, Qt::Key_3}}};
    for (const auto& [name, axis] : axes) {
        const AxisView which = axis.first;
        action(cameraMenu, name, QKeySequence(axis.second), [this, which, sceneBounds] { controller_->showAxisView(axisView(which, sceneBounds())); });
    }
    // Perspective / orthographic (Blender's numpad 5; Qt matches Key_5 on the keypad too). The axis
    // views are orthographic until an orbit leaves them; the designer's choice here stays.
    orthoAction_ = action(cameraMenu, tr("&Orthographic"), QKeySequence(Qt::Key_5), [this](bool on) {
        controller_->setOrthographic(on);
        statusBar()->showMessage(on ? tr("Orthographic view (5: perspective)") : tr("Perspective view (5: orthographic)"), 3000);
    });
    orthoAction_->setCheckable(true);
    orthoAction_->setObjectName("orthographic");
    connect(controller_.get(), &ViewportController::viewChanged, this, &MainWindow::updateViewLabel);
    cameraMenu->addSeparator();
    const auto lookFrom = [this](bool fromSource) {
        const Project& p = document_.project();
        const Patch& from = fromSource ? p.source : p.receiver;
        const Patch& to = fromSource ? p.receiver : p.source;
        controller_->setCamera(lookThrough(from.centre(), from.normal(), to.centre(), 0.5 * glm::length(to.u + to.v)));
        if (cutAction_->isChecked())
            cutAction_->trigger();
        statusBar()->showMessage(fromSource ? tr("Looking through the source at the receiver (section cut off; C brings it back)")
                                            : tr("Looking from the receiver at the source (section cut off; C brings it back)"),
                                 5000);
    };
    action(cameraMenu, tr("Look Through &Source"), QKeySequence(Qt::Key_L), [lookFrom] { lookFrom(true); });
    action(cameraMenu, tr("Look From &Receiver"), QKeySequence(Qt::SHIFT | Qt::Key_L), [lookFrom] { lookFrom(false); });
}

void MainWindow::addShadingItems(QMenu* view)
{
    // Ambient occlusion of the level: computed in the background, coarse at once
    // (k = 6), refined to k = 258; the status bar follows it.
    QAction* ao = action(view, tr("&Ambient Occlusion"), QKeySequence(Qt::Key_O), [this](bool on) {
        viewport_->setAmbientOcclusion(on);
        if (!on)
            statusBar()->showMessage(tr("Ambient occlusion off"), 3000);
    });
    ao->setCheckable(true);
    ao->setObjectName("ambientOcclusion");
    // The lit view: the project's lights on the level's light-map texels, exact once converged.
    QAction* lit = action(view, tr("&Lit View (Lights)"), QKeySequence(Qt::Key_I), [this](bool on) {
        viewport_->setLitView(on);
        if (!on)
            statusBar()->showMessage(tr("Lit view off"), 3000);
    });
    lit->setCheckable(true);
    lit->setObjectName("litView");
    // What the lit view shows: Barczak's and the engines' questions (how many lights overlap, where
    // shadows are partial, what is stale) over the same computed light; switching casts no ray.
    QMenu* litShows = view->addMenu(tr("Lit View Shows"));
    litShows->setObjectName("litShows");
    auto* litModes = new QActionGroup(this);
    const std::pair<QString, LitShading> shadings[] = {{tr("&Light"), LitShading::Light},
                                                       {tr("Shadow &Complexity"), LitShading::Complexity},
                                                       {tr("Light &Overlap Against the Budget"), LitShading::Overlap},
                                                       {tr("&Staleness"), LitShading::Staleness},
                                                       {tr("&Error Against the Reference"), LitShading::Error}};
    const char* shadingNames[] = {"litLight", "litComplexity", "litOverlap", "litStaleness", "litError"};
    for (std::size_t k = 0; k < std::size(shadings); ++k) {
        QAction* a = litShows->addAction(shadings[k].first, this, [this, lit, shading = shadings[k].second] {
            viewport_->setLitShading(shading, viewport_->litBudget());
            if (!lit->isChecked())
                lit->trigger();
        });
        a->setCheckable(true);
        a->setChecked(k == 0);
        a->setObjectName(shadingNames[k]);
        litModes->addAction(a);
    }
    litShows->addSeparator();
    QAction* indirect = litShows->addAction(tr("&Indirect Light (One Bounce)"), this, [this, lit](bool on) {
        viewport_->setLitIndirect(on);
        if (on && !lit->isChecked())
            lit->trigger();
    });
    indirect->setCheckable(true);
    indirect->setObjectName("litIndirect");
    QAction* sets = action(view, tr("Light &Sets of the Selected Light"), QKeySequence(Qt::SHIFT | Qt::Key_I), [this, lit](bool on) {
        if (on && !lit->isChecked())
            lit->trigger();
        viewport_->setLightSetsShown(on);
        if (on && document_.selection().kind != ObjectKind::Light)
            statusBar()->showMessage(tr("Light sets: select a light (its sets show over the lit view)"), 5000);
    });
    sets->setCheckable(true);
    sets->setObjectName("lightSets");
    connect(lit, &QAction::toggled, this, [this, sets](bool on) {
        if (!on)
            sets->setChecked(false);   // the sets live on the lit view's worker
        showLightCosts();
    });
    connect(viewport_, &Viewport::lightSetsUpdated, this, [this](const QString& status) {
        if (!status.isEmpty())
            statusBar()->showMessage(status, 0);
    });
    QMenu* budget = litShows->addMenu(tr("Overlapping Lights &Budget"));
    auto* budgets = new QActionGroup(this);
    for (int n : {1, 2, 3, 4, 6, 8, 16}) {
        QAction* a = budget->addAction(QString::number(n), this, [this, n] { viewport_->setLitShading(viewport_->litShading(), n); });
        a->setCheckable(true);
        a->setChecked(n == viewport_->litBudget());
        a->setObjectName("litBudget-" + QString::number(n));
        budgets->addAction(a);
    }
    litShows->addSeparator();
    litShows->addAction(lightCostsDock_->toggleViewAction());   // what each light costs
    connect(viewport_, &Viewport::litUpdated, this, [this](const QString& status, bool exact, const QString& error) {
        if (!error.isEmpty())
            statusBar()->showMessage(tr("Lit view failed: %1").arg(error), 10000);
        else
            statusBar()->showMessage(status, exact ? 8000 : 0);
        showLightCosts();
    });
    // AO of chosen objects: the selected object only, at finer texels, the level still occluding.
    QAction* aoSelection = action(view, tr("AO of Selected &Object Only"), QKeySequence(Qt::ALT | Qt::Key_O), [this, ao](bool on) {
        viewport_->setAoOfSelection(on);
        if (on && !ao->isChecked())
            ao->trigger();   // asking for the selection's AO means wanting to see it
        statusBar()->showMessage(on ? tr("Ambient occlusion of the selected object only (the whole level when none is)")
                                    : tr("Ambient occlusion of the whole level"),
                                 3000);
    });
    aoSelection->setCheckable(true);
    aoSelection->setObjectName("aoOfSelection");
}

void MainWindow::addPvsDebuggerItems(QMenu* view)
{
    // The PVS debugger: the project's PVS baked in the background, coarse for every
    // cell first; the level's objects the camera's view cell cannot see are tinted magenta.
    QAction* pvsView = action(view, tr("&PVS Debugger"), QKeySequence(Qt::Key_P), [this](bool on) {
        viewport_->setPvsDebugger(on);
        if (!on)
            statusBar()->showMessage(tr("PVS debugger off"), 3000);
    });
    pvsView->setCheckable(true);
    pvsView->setObjectName("pvsDebugger");
    QAction* freeze = action(view, tr("&Freeze PVS Cell"), QKeySequence(Qt::SHIFT | Qt::Key_P),
                             [this](bool on) { viewport_->setPvsFrozen(on); });
    freeze->setCheckable(true);
    freeze->setObjectName("pvsFreeze");
    // Overrides: the designer's word over the bake for the selected level object in
    // the shown cell, kept in the project's pvs.overrides (undoable), applied as `pvs bake` does.
    const auto overrideSelected = [this](const char* visible) {
        const ObjectRef selection = document_.selection();
        const std::optional<std::size_t> cell = viewport_->pvsView().shownCell();
        if (selection.kind != ObjectKind::SceneObject || !cell) {
            statusBar()->showMessage(tr("Select an object of the level, with the PVS debugger on and the camera in a cell "
                                        "(or the cell frozen)"),
                                     5000);
            return;
        }
        const auto it = document_.project().extra.find("pvs");
        const nlohmann::json before = it != document_.project().extra.end() ? *it : nlohmann::json();
        nlohmann::json after = before.is_object() ? before : nlohmann::json::object();
        nlohmann::json overrides = nlohmann::json::array();
        for (const nlohmann::json& o : after.value("overrides", nlohmann::json::array()))
            if (!(o.value("instance", -1) == int(selection.index) && o.value("cells", nlohmann::json::array()) == nlohmann::json::array({*cell})))
                overrides.push_back(o);   // an earlier word on this object and cell is replaced
        if (visible)
            overrides.push_back({{"instance", selection.index}, {"visible", visible}, {"cells", {*cell}}});
        after["overrides"] = overrides;
        document_.undoStack()->push(new SetProjectKeyCommand(document_, "pvs", before, after,
                                                             visible ? tr("PVS override: %1").arg(visible) : tr("Clear PVS override")));
    };
    action(view, tr("PVS: Always Visible From This Cell"), QKeySequence(), [overrideSelected] { overrideSelected("always"); })
        ->setObjectName("pvsAlways");
    action(view, tr("PVS: Never Visible From This Cell"), QKeySequence(), [overrideSelected] { overrideSelected("never"); })
        ->setObjectName("pvsNever");
    action(view, tr("PVS: Clear Override Here"), QKeySequence(), [overrideSelected] { overrideSelected(nullptr); })
        ->setObjectName("pvsClear");
    // The gap list: where the dense reference saw an object the bake culls, drawn as
    // markers (a click on one frames it); N and Shift+N step through them.
    // Without the debugger, N steps through the openings the occluder assistant lists.
    const auto stepGap = [this](int step) {
        if (!viewport_->style().pvsDebugger && assistantDock_->isVisible() && assistant_->stepGap(step))
            return;
        const std::size_t n = viewport_->pvsView().gaps().size();
        if (!viewport_->pvsView().gapsReady() || n == 0) {
            statusBar()->showMessage(viewport_->pvsView().gapsReady() ? tr("PVS: the reference found no gaps")
                                                               : tr("PVS: no gap list yet (the debugger checks the bake once it is over)"),
                                     5000);
            return;
        }
        const int at = viewport_->pvsView().gapSelected();
        viewport_->framePvsGap(std::size_t(((at < 0 ? (step > 0 ? -1 : 0) : at) + step + int(n)) % int(n)));
    };
    action(view, tr("Next Gap (PVS or Openings)"), QKeySequence(Qt::Key_N), [stepGap] { stepGap(1); })->setObjectName("pvsNextGap");
    action(view, tr("Previous Gap (PVS or Openings)"), QKeySequence(Qt::SHIFT | Qt::Key_N), [stepGap] { stepGap(-1); })
        ->setObjectName("pvsPreviousGap");
    action(view, tr("PVS: Distance Cut-off..."), QKeySequence(), [this] {
        const auto it = document_.project().extra.find("pvs");
        const double now = it != document_.project().extra.end() && it->is_object() && (*it).value("max_distance", nlohmann::json()).is_number()
                               ? (*it)["max_distance"].get<double>()
                               : 0.0;
        bool ok = false;
        const double metres = QInputDialog::getDouble(this, tr("PVS Distance Cut-off"),
                                                      tr("Cull objects farther than this from the view cell (metres, 0: none):"),
                                                      now, 0.0, 1e6, 1, &ok);
        if (ok)
            setPvsDistanceCutoff(metres);
    })->setObjectName("pvsCutoff");
    connect(viewport_, &Viewport::pvsUpdated, this, [this, pvsView](const QString& status) {
        if (pvsView->isChecked())
            statusBar()->showMessage(status);
    });
    // A framed gap is seen with the section cut off: with it on, the culled object behind the
    // walls would look exposed (C brings the cut back).
    connect(viewport_, &Viewport::pvsGapFramed, this, [this] {
        if (cutAction_->isChecked())
            cutAction_->trigger();
    });
}

void MainWindow::addAoEnvironmentItems(QMenu* view)
{
    // The light around the level (Sattler et al. §4): an HDR environment relights the AO from the
    // visibility matrix, without tracing; its turn about +Y in 15 degree steps.
    action(view, tr("AO &Environment..."), QKeySequence(), [this] {
        const QString chosen = QFileDialog::getOpenFileName(this, tr("Light the AO with an Environment"),
                                                            QString::fromStdString(projectFolder().string()),
                                                            tr("Radiance HDR (*.hdr);;All files (*)"));
        if (!chosen.isEmpty())
            setAoEnvironment(chosen);
    })->setObjectName("aoEnvironment");
    action(view, tr("AO Uniform Sky"), QKeySequence(), [this] {
        AoLighting lighting = viewport_->aoLighting();
        lighting.environment.reset();
        viewport_->setAoLighting(lighting);
    })->setObjectName("aoUniformSky");
    action(view, tr("Turn AO Environment"), QKeySequence(Qt::SHIFT | Qt::Key_O), [this] {
        AoLighting lighting = viewport_->aoLighting();
        lighting.rotationDegrees = std::fmod(lighting.rotationDegrees + 15.0, 360.0);
        viewport_->setAoLighting(lighting);
        statusBar()->showMessage(tr("AO environment turned to %1°").arg(lighting.rotationDegrees), 3000);
    })->setObjectName("aoTurn");
    connect(viewport_, &Viewport::aoUpdated, this, [this](int k, int target, double ms, const QString& error, bool relit) {
        if (relit && error.isEmpty()) {
            statusBar()->showMessage(tr("Ambient occlusion relit in %1 ms (no rays traced)").arg(ms, 0, 'f', 0), 5000);
            return;
        }
        if (!error.isEmpty())
            statusBar()->showMessage(tr("Ambient occlusion failed: %1").arg(error), 10000);
        else {
            const QString what = viewport_->aoInstances().empty() ? tr("Ambient occlusion") : tr("Ambient occlusion of the selection");
            statusBar()->showMessage(k < target ? tr("%1: %2 of %3 directions (%4 s), refining...").arg(what).arg(k).arg(target).arg(ms / 1000.0, 0, 'f', 1)
                                                : tr("%1: %2 directions (%3 s)").arg(what).arg(k).arg(ms / 1000.0, 0, 'f', 1),
                                     k < target ? 0 : 8000);
        }
    });
}

void MainWindow::addSectionCutItems(QMenu* view)
{
    // The section cut: its own toggle and height (navigation never moves it).
    cutAction_ = action(view, tr("Section &Cut"), QKeySequence(Qt::Key_C), [this](bool on) {
        viewport_->style().cutaway = on;
        statusBar()->showMessage(on ? tr("Section cut at %1 m").arg(viewport_->style().cutHeight, 0, 'f', 2)
                                    : tr("Section cut off"), 3000);
        viewport_->requestUpdate();
    });
    cutAction_->setCheckable(true);
    cutAction_->setChecked(true);
    cutAction_->setObjectName("sectionCut");
    auto moveCut = [this](double metres) {
        ViewStyle& style = viewport_->style();
        style.cutHeight += metres;
        style.cutaway = true;
        cutAction_->setChecked(true);
        statusBar()->showMessage(tr("Section cut at %1 m").arg(style.cutHeight, 0, 'f', 2), 3000);
        viewport_->requestUpdate();
    };
    // Its handle in the view (a cyan grip with arrows on the cut plane) drags it: a view setting, no undo.
    connect(controller_.get(), &ViewportController::cutMoved, this, [this](double height) {
        statusBar()->showMessage(tr("Section cut at %1 m").arg(height, 0, 'f', 2), 3000);
    });
    action(view, tr("Raise Section Cut"), QKeySequence(Qt::Key_PageUp), [moveCut] { moveCut(0.5); });
    action(view, tr("Lower Section Cut"), QKeySequence(Qt::Key_PageDown), [moveCut] { moveCut(-0.5); });
}

void MainWindow::addRayItems(QMenu* view, QAction* wire)
{
    QAction* rays = action(view, tr("Show &Rays"), QKeySequence(Qt::Key_V), [this](bool on) {
        viewport_->style().showRays = on;
        viewport_->requestUpdate();
    });
    rays->setCheckable(true);
    rays->setChecked(true);
    QAction* blocked = action(view, tr("Show &Blocked Rays"), QKeySequence(Qt::Key_B), [this](bool on) {
        viewport_->style().showBlocked = on;
        viewport_->requestUpdate();
    });
    blocked->setCheckable(true);
    toolbar_->addAction(wire);
    toolbar_->addAction(rays);
    toolbar_->addAction(blocked);

    // Ray density: how many rays are drawn at most (the status bar always counts all of them).
    auto* density = new QComboBox(this);
    density->setToolTip(tr("Most rays drawn (a spread-out subset beyond; counts always cover every ray)"));
    for (int cap : {1024, 4096, 16384, 65536, 262144, 1048576})
        density->addItem(tr("%1 rays").arg(QLocale(QLocale::English).toString(cap)), cap);
    density->setCurrentIndex(1);   // 4,096: readable, and a quarter of 16,384's drawing cost on llvmpipe
    viewport_->style().rayCap = 4096;
    connect(density, &QComboBox::currentIndexChanged, this, [this, density](int) {
        viewport_->style().rayCap = density->currentData().toInt();
        viewport_->requestUpdate();
    });
    toolbar_->addWidget(density);
}

void MainWindow::addDisagreementItems(QMenu* view)
{
    // What a fast or coarse mode costs, ray by ray: the rays it answers differently from the exact
    // sampler drawn in place of the rays, each judged (ties apart).
    QMenu* menu = view->addMenu(tr("&Disagreement With Exact"));
    menu->setObjectName("disagreementMenu");
    auto* modes = new QActionGroup(this);
    const std::pair<QString, const char*> choices[] = {
        {tr("&Off"), ""},
        {tr("Hough Table 256x128 (&CPU)"), "table-256x128"},
        {tr("Hough Table &64x32 (CPU)"), "table-64x32"},
        {tr("&GL Bitmask, Exact Masks"), "gl"},
        {tr("GL &Hough Table 256x128"), "gl-table-256x128"},
        {tr("A &Quarter of the Samples"), "samples-2"},
        {tr("A &Sixteenth of the Samples"), "samples-4"},
        {tr("Coarse Occluders, 5,000 &Triangles"), "coarse-5000"},
        {tr("Coarse Occluders, &1,000 Triangles"), "coarse-1000"},
        {tr("&Inner Occluders (Conservative)"), "inner-32"}};
    auto choose = [this](const QString& name) {
        viewport_->setDisagreementView(name.isEmpty() ? std::nullopt
                                                      : std::optional(parseApproximation(name.toStdString())));
        updateDisagreementKey();
        statusBar()->showMessage(name.isEmpty() ? tr("Rays as sampled (disagreement view off)")
                                                : tr("Disagreement with exact: %1...")
                                                      .arg(QString::fromStdString(describeApproximation(
                                                          parseApproximation(name.toStdString())))),
                                 name.isEmpty() ? 3000 : 0);
    };
    QAction* off = nullptr;
    for (const auto& [text, name] : choices) {
        QAction* a = menu->addAction(text, this, [choose, n = QString(name)] { choose(n); });
        a->setCheckable(true);
        a->setObjectName(QString("disagreement-") + (*name ? name : "off"));
        modes->addAction(a);
        if (!*name)
            off = a, a->setChecked(true);
    }
    // Ctrl+Shift+D: on with the last mode chosen (the CPU Hough table at first), or off.
    disagreementLast_ = modes->actions().at(1);
    connect(modes, &QActionGroup::triggered, this, [this, off](QAction* a) {
        if (a != off)
            disagreementLast_ = a;
    });
    action(menu, tr("Toggle Disagreement View"), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_D), [this, off] {
        (viewport_->disagreementView() ? off : disagreementLast_)->trigger();
    });
    connect(viewport_, &Viewport::disagreementUpdated, this, [this](const QString& status, bool failed) {
        statusBar()->showMessage(status, failed ? 10000 : 0);
        updateDisagreementKey();
    });
}

void MainWindow::updateDisagreementKey()
{
    if (!disagreementKey_)
        disagreementKey_ = new OverlayLegend(container_, OverlayLegend::Corner::TopLeft);
    const std::optional<DisagreementAnswer>& answer = viewport_->disagreement();
    if (!viewport_->disagreementView() || !answer || !answer->disagreement) {
        disagreementKey_->hide();
        return;
    }
    const RayDisagreement& d = *answer->disagreement;
    const auto colour = [](const std::uint8_t rgb[3]) { return QColor(rgb[0], rgb[1], rgb[2]); };
    const auto rays = [](std::uint64_t n) { return QLocale().toString(qulonglong(n)); };
    disagreementKey_->setEntries(
        tr("%1 vs exact, %2 rays").arg(QString::fromStdString(describeApproximation(answer->approximation)), rays(d.rays)),
        {{colour(kFalseBlockedRgb), tr("false-blocked: %1 (blocked here, free by the exact answer)").arg(rays(d.falseBlockedCount))},
         {colour(kFalseFreeRgb), tr("false-free: %1 (free here, blocked by the exact answer)").arg(rays(d.falseFreeCount))},
         {colour(kTieRgb), d.judged ? tr("ties: %1 (within the tie distance: either answer allowed)").arg(rays(d.tieCount))
                                    : tr("ties: not judged (too many differences: each counted as wrong)")}});
    disagreementKey_->show();
}

void MainWindow::createHelpMenu()
{
    QMenu* help = menuBar()->addMenu(tr("&Help"));
    help->addAction(tr("&Controls"), this, [this] {
        QMessageBox::information(this, tr("Controls"),
                                 tr("Orbit: left drag (or Alt + left drag)\nPan: middle drag or Shift + left drag\n"
                                    "Zoom: wheel\nFly: hold the right button, W A S D Q E, Shift for speed\n"
                                    "Orbit and fly speeds: Edit > Preferences (Ctrl+,)\n"
                                    "Frame selection: F; frame all: Home\n"
                                    "Top / front / side view (orthographic): 7 / 1 / 3; perspective / orthographic: 5\n"
                                    "Look through the source / from the receiver: L / Shift+L\n"
                                    "Move / Rotate / Scale handles: W / E / R; world / local axes: X\n"
                                    "Snapping: G; finer / coarser grid: [ / ]\n"
                                    "Section cut on / off: C; raise / lower it: Page Up / Page Down, or drag its cyan handle\n"
                                    "Wireframe: Z; rays: V; blocked rays: B; add a box: Ctrl+B\n"
                                    "Hide / show the selection: H; isolate it: Shift+H; show all: Ctrl+Shift+H; lock it: Ctrl+L\n"
                                    "Place source / receiver on a surface: Ctrl+1 / Ctrl+2, then click\n"
                                    "Add a point / spot / area light / sun: Ctrl+3 / Ctrl+4 / Ctrl+5 / Ctrl+6; lit view: I\n"
                                    "Record video (camera and edits) / stop: F9; play the recorded path: Shift+F9"));
    });
}


QString MainWindow::recoveryPath()
{
    const QString folder = QStandardPaths::writableLocation(QStandardPaths::AppDataLocation);
    QDir().mkpath(folder);
    return folder + "/recovery.json";
}

void MainWindow::autosave()
{
    if (!document_.isModified())
        return;
    try {
        storeView();
        document_.saveRecovery(recoveryPath().toStdString());
    } catch (const std::exception& e) {
        statusBar()->showMessage(tr("Autosave failed: %1").arg(e.what()), 10000);
    }
}

void MainWindow::storeView()
{
    nlohmann::json settings = document_.editorSettings();
    settings["camera"] = cameraToJson(controller_->camera());
    document_.setEditorSettings(settings);
}

bool MainWindow::openFile(const QString& file)
{
    if (isPvsFile(file))
        return openPvsFile(file);
    try {
        document_.open(file.toStdString());
    } catch (const std::exception& e) {
        QMessageBox::warning(this, tr("Open"),
                             QString::fromStdString(describeFailure(e, "opening " + file.toStdString())));
        return false;
    }
    addRecentFile(QFileInfo(file).absoluteFilePath());
    if (!document_.openNote().isEmpty())
        statusBar()->showMessage(document_.openNote(), 20000);
    return true;
}

bool MainWindow::saveTo(const QString& file)
{
    try {
        storeView();
        document_.save(file.toStdString());
    } catch (const std::exception& e) {
        QMessageBox::warning(this, tr("Save"),
                             QString::fromStdString(describeFailure(e, "saving " + file.toStdString())));
        return false;
    }
    QFile::remove(recoveryPath());
    addRecentFile(QFileInfo(file).absoluteFilePath());
    statusBar()->showMessage(tr("Saved %1").arg(file), 4000);
    return true;
}

bool MainWindow::screenshotTo(const QString& file)
{
    const QImage image = viewport_->grabFramebuffer();
    if (image.isNull()) {
        QMessageBox::warning(this, tr("Screenshot"), tr("Could not encode the screenshot as PNG"));
        return false;
    }
    try {
        // Atomic, keeping the old file's mode and a symlink, like every other save.
        savePng(image, file.toStdString());
    } catch (const std::exception& e) {
        QMessageBox::warning(this, tr("Screenshot"), QString::fromStdString(describeFailure(e, "saving the screenshot")));
        return false;
    }
    statusBar()->showMessage(tr("Screenshot saved to %1").arg(file), 4000);
    return true;
}

void MainWindow::open()
{
    if (!maybeSave())
        return;
    const QString filter = tr("Projects and meshes (*.json %1)").arg(QString::fromStdString(SceneFormatRegistry::builtin().importFilter()));
    const QString file = QFileDialog::getOpenFileName(this, tr("Open"), QString::fromStdString(projectFolder().string()), filter);
    if (!file.isEmpty())
        openFile(file);
}

bool MainWindow::save()
{
    if (document_.filePath().empty())
        return saveAs();
    return saveTo(QString::fromStdString(document_.filePath().string()));
}

bool MainWindow::saveAs()
{
    const std::string name = document_.filePath().empty() || isMeshFile(document_.filePath())
                                 ? "project.json"
                                 : document_.filePath().filename().string();
    const QString file = QFileDialog::getSaveFileName(this, tr("Save Project"), QString::fromStdString((projectFolder() / name).string()),
                                                      tr("Sightline projects (*.json)"));
    return !file.isEmpty() && saveTo(file);
}

bool MainWindow::maybeSave()
{
    if (!document_.isModified())
        return true;
    const auto answer = QMessageBox::warning(this, tr("Unsaved changes"),
                                             tr("%1 has unsaved changes. Save them?").arg(document_.displayName()),
                                             QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel);
    if (answer == QMessageBox::Save)
        return save();
    return answer == QMessageBox::Discard;
}

void MainWindow::closeEvent(QCloseEvent* event)
{
    if (!maybeSave()) {
        event->ignore();
        return;
    }
    QSettings settings;
    settings.setValue("window/geometry", saveGeometry());
    settings.setValue("window/state", saveState());
    QFile::remove(recoveryPath());
    event->accept();
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event)
{
    if (event->mimeData()->hasUrls())
        event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event)
{
    const QList<QUrl> urls = event->mimeData()->urls();
    if (urls.isEmpty() || !urls.front().isLocalFile())
        return;
    const QString file = urls.front().toLocalFile();
    if (isPvsFile(file))
        openPvsFile(file);   // shown over the open project: nothing to save first
    else if (maybeSave())
        openFile(file);
}

bool MainWindow::isPvsFile(const QString& file)
{
    return file.endsWith(".pvs", Qt::CaseInsensitive) || file.endsWith(".pvs.json", Qt::CaseInsensitive);
}

bool MainWindow::openPvsFile(const QString& file)
{
    try {
        pvs::PvsData baked = readBakedPvs(file.toStdString(), document_.project(), document_.scene());
        const std::size_t cells = baked.cells.size(), objects = baked.objects.size();
        viewport_->showBakedPvs(std::move(baked), QFileInfo(file).fileName());
        if (QAction* debugger = findChild<QAction*>("pvsDebugger"))
            debugger->setChecked(true);
        statusBar()->showMessage(tr("%1: %2 cells x %3 objects, shown in the PVS debugger").arg(QFileInfo(file).fileName()).arg(cells).arg(objects),
                                 8000);
        return true;
    } catch (const std::exception& e) {
        QMessageBox::warning(this, tr("Open PVS"), QString::fromStdString(describeFailure(e, "opening " + file.toStdString())));
        return false;
    }
}

void MainWindow::updateTitle()
{
    setWindowTitle(tr("%1[*] - Sightline").arg(document_.displayName()));
    setWindowModified(document_.isModified());
}

QString MainWindow::enclosedPatchNote()
{
    // Only asked when every ray is blocked (the case that otherwise has no explanation), and
    // remembered for the patches it was asked for: each pick is a brute-force pass.
    const Project& project = document_.project();
    const std::array<glm::dvec3, 2> centres{project.source.centre(), project.receiver.centre()};
    if (enclosedFor_ && *enclosedFor_ == centres)
        return enclosedNote_;
    enclosedFor_ = centres;
    enclosedNote_.clear();
    const Scene& scene = document_.scene();
    const WorldTriangles& triangles = controller_->triangles();
    const char* names[] = {"source", "receiver"};
    for (int k = 0; k < 2; ++k)
        if (const auto instance = enclosingInstance(scene, triangles, centres[std::size_t(k)]))
            enclosedNote_ += tr(" · the %1 is inside %2").arg(names[k], QString::fromStdString(scene.instances[*instance].name));
    return enclosedNote_;
}

QString MainWindow::patchWarningNote()
{
    // Each check is a few brute-force picks: found once the patches rest (not on every frame of a
    // drag), and remembered for the patches and the level it was found for.
    const Project& project = document_.project();
    const std::array<glm::dvec3, 7> key{project.source.corner,   project.source.u, project.source.v, project.receiver.corner,
                                        project.receiver.u,      project.receiver.v,
                                        glm::dvec3(document_.levelBounds().max) - glm::dvec3(document_.levelBounds().min)};
    if (warningsFor_ && *warningsFor_ == key)
        return warningNote_;
    if (warningsWanted_ != key) {
        warningsWanted_ = key;
        warningNote_.clear();
        warningTimer_.start();   // then updateStatus() asks again
        return {};
    }
    if (warningTimer_.isActive())
        return {};
    warningsFor_ = key;
    for (const std::string& warning :
         patchWarnings(controller_->triangles(), document_.levelBounds(), project.source, project.receiver))
        warningNote_ += tr(" · %1").arg(QString::fromStdString(warning));
    return warningNote_;
}

void MainWindow::updateStatus()
{
    const VisibilityResult& result = viewport_->visibility();
    QString summary = visibilitySummary(result);
    if (result.valid && result.rays > 0 && result.unblocked() == 0)
        summary += enclosedPatchNote();
    if (result.valid)
        summary += patchWarningNote();
    // A slow update (a 512x512 floor: about a second) says that a newer answer is on its way;
    // a fast one would only flicker.
    raysLabel_->setText(viewport_->resultIsStale() && result.ms > 150.0
                            ? summary + tr(" · updating (%1 ms an update)").arg(result.ms, 0, 'f', 0)
                            : summary);
    raysLabel_->setStyleSheet(result.valid ? QString() : QString("color: #e05050"));
    properties_->setPairError(result.valid ? QString() : QString::fromStdString(result.error));
    std::optional<PatchPairFix> fix;
    if (!result.valid) {
        const Project& project = document_.project();
        fix = fixPatchPair(project.source, project.receiver, document_.selection().kind == ObjectKind::Source);
    }
    if (fix) {
        QString text = QString::fromStdString(fix->description);
        text[0] = text[0].toUpper();
        fixPairButton_->setText(tr("Fix: %1").arg(text));
    }
    fixPairButton_->setVisible(fix.has_value());
    updateRateLabel();
}

bool MainWindow::setAoEnvironment(const QString& file)
{
    try {
        AoLighting lighting = viewport_->aoLighting();
        lighting.environment = std::make_shared<const AoEnvironment>(AoEnvironment::load(file.toStdString()));
        viewport_->setAoLighting(lighting);
        statusBar()->showMessage(tr("AO lit by %1").arg(QFileInfo(file).fileName()), 5000);
        return true;
    } catch (const std::exception& e) {
        QMessageBox::warning(this, tr("AO Environment"), QString::fromUtf8(e.what()));
        return false;
    }
}

void MainWindow::applySnap()
{
    const bool on = snapAction_->isChecked();
    controller_->setSnap(on ? GizmoSnap{gridStep_, std::numbers::pi / 12.0, 0.1} : GizmoSnap{});
    snapAction_->setText(tr("Snap %1 m").arg(gridStep_, 0, 'g', 4));
    statusBar()->showMessage(on ? tr("Snapping: moves to a %1 m grid, rotations by 15°, scaling by 10%").arg(gridStep_, 0, 'g', 4)
                                : tr("Snapping off (G turns it on; [ and ] change the grid)"),
                             4000);
}

void MainWindow::updateViewLabel()
{
    if (!viewLabel_ || !spaceLabel_ || !orthoAction_)
        return;
    const bool ortho = controller_->camera().orthographic;
    if (orthoAction_->isChecked() != ortho) {
        const QSignalBlocker quiet(orthoAction_);   // showing the state, not choosing it
        orthoAction_->setChecked(ortho);
    }
    viewLabel_->setText(ortho ? tr("Orthographic") : tr("Perspective"));
    spaceLabel_->setText(controller_->gizmoSpace() == GizmoSpace::Local ? tr("Local axes") : tr("World axes"));
}

void MainWindow::updateRateLabel()
{
    const double rate = viewport_->updateRate();
    const QString backend = QString::fromStdString(viewport_->backendName());
    backendLabel_->setText(rate > 0.0 ? tr("%1 · %2 Hz").arg(backend).arg(rate, 0, 'f', 0) : tr("%1 · idle").arg(backend));
}

void MainWindow::addRecentFile(const QString& file)
{
    QSettings settings;
    QStringList files = settings.value("recentFiles").toStringList();
    files.removeAll(file);
    files.prepend(file);
    while (files.size() > kMaxRecentFiles)
        files.removeLast();
    settings.setValue("recentFiles", files);
    rebuildRecentMenu();
}

void MainWindow::rebuildRecentMenu()
{
    recentMenu_->clear();
    const QStringList files = QSettings().value("recentFiles").toStringList();
    // "1 demo.json — /home/me/levels": the same name in two folders is told apart.
    int number = 0;
    for (const QString& file : files) {
        const QFileInfo info(file);
        const QString label = QString("&%1 %2 — %3").arg(++number % 10).arg(info.fileName(), QDir::toNativeSeparators(info.absolutePath()));
        recentMenu_->addAction(label, this, [this, file] {
            if (maybeSave())
                openFile(file);
        })->setToolTip(file);
    }
    recentMenu_->setEnabled(!files.isEmpty());
}

} // namespace sightline::ui
