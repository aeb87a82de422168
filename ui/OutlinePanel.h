#pragma once
// The scene outline: the two patches, the placed occluders and the scene file's objects, in
// three groups, with a search field above. Selecting here selects in the viewport and the other
// way round. Objects that share a name are told apart by a number ("pillar #3 of 12"); placed
// occluders are renamed in place (F2 or a double click), undoably. Two columns of check boxes
// show and hide each object and lock it (ObjectFlags.h), undoably; hidden rows are grey and
// italic ("still blocks rays"), rows isolation hides are grey.

#include <QWidget>

#include <vector>

#include "editor/ObjectEdits.h"

class QAction;
class QLineEdit;
class QTreeWidget;
class QTreeWidgetItem;

namespace sightline::ui {

class EditorDocument;

/// `names` with every name that occurs more than once numbered in order: "pillar #3 of 12".
std::vector<QString> distinctNames(const std::vector<QString>& names);

class OutlinePanel : public QWidget {
    Q_OBJECT
public:
    explicit OutlinePanel(EditorDocument& document, QWidget* parent = nullptr);

    QTreeWidget* tree() const { return tree_; }
    QLineEdit* searchField() const { return search_; }
    /// Shows only the objects whose name contains `text` (any case); the groups stay.
    void setFilter(const QString& text);
    /// The row of an object (nullptr for None or out of range).
    QTreeWidgetItem* itemFor(ObjectRef object) const;
    /// The columns: the name, then the Show and Lock check boxes.
    enum Column { NameColumn = 0, ShowColumn = 1, LockColumn = 2 };
    /// Actions offered on a right click (hide, isolate, lock...), acting on the selection.
    void setContextActions(const QList<QAction*>& actions);

private:
    void rebuild();
    void showSelection(ObjectRef selection);
    /// The check boxes, greying and tooltips from the document's flags.
    void refreshFlags();

    EditorDocument& document_;
    QLineEdit* search_ = nullptr;
    QTreeWidget* tree_ = nullptr;
    QTreeWidgetItem* patches_ = nullptr;
    QTreeWidgetItem* occluders_ = nullptr;
    QTreeWidgetItem* lights_ = nullptr;
    QTreeWidgetItem* sceneFile_ = nullptr;
    bool updating_ = false;
};

} // namespace sightline::ui
