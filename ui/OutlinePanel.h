#pragma once
// The scene outline: the two patches, the placed occluders and the scene file's objects, in
// three groups, with a search field above. Selecting here selects in the viewport and the other
// way round. Objects that share a name are told apart by a number ("pillar #3 of 12"); placed
// occluders are renamed in place (F2 or a double click), undoably.

#include <QWidget>

#include <vector>

#include "ObjectEdits.h"

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

private:
    void rebuild();
    void showSelection(ObjectRef selection);
    QTreeWidgetItem* itemFor(ObjectRef object) const;

    EditorDocument& document_;
    QLineEdit* search_ = nullptr;
    QTreeWidget* tree_ = nullptr;
    QTreeWidgetItem* patches_ = nullptr;
    QTreeWidgetItem* occluders_ = nullptr;
    QTreeWidgetItem* sceneFile_ = nullptr;
    bool updating_ = false;
};

} // namespace sightline::ui
