#pragma once
// The scene outline: the two patches, the placed occluders and the scene file's objects, in
// three groups. Selecting here selects in the viewport and the other way round.

#include <QTreeWidget>

#include "ObjectEdits.h"

namespace sightline::ui {

class EditorDocument;

class OutlinePanel : public QTreeWidget {
    Q_OBJECT
public:
    explicit OutlinePanel(EditorDocument& document, QWidget* parent = nullptr);

private:
    void rebuild();
    void showSelection(ObjectRef selection);
    QTreeWidgetItem* itemFor(ObjectRef object) const;

    EditorDocument& document_;
    QTreeWidgetItem* patches_ = nullptr;
    QTreeWidgetItem* occluders_ = nullptr;
    QTreeWidgetItem* sceneFile_ = nullptr;
    bool updating_ = false;
};

} // namespace sightline::ui
