#include "OutlinePanel.h"

#include "EditorDocument.h"

namespace sightline::ui {

namespace {
constexpr int kKindRole = Qt::UserRole;
constexpr int kIndexRole = Qt::UserRole + 1;
} // namespace

OutlinePanel::OutlinePanel(EditorDocument& document, QWidget* parent) : QTreeWidget(parent), document_(document)
{
    setHeaderHidden(true);
    setSelectionMode(QAbstractItemView::SingleSelection);
    connect(&document_, &EditorDocument::changed, this, [this](unsigned changes) {
        if (changes & (OccludersChanged | DocumentReset))
            rebuild();
    });
    connect(&document_, &EditorDocument::selectionChanged, this, &OutlinePanel::showSelection);
    connect(this, &QTreeWidget::itemSelectionChanged, this, [this] {
        if (updating_)
            return;
        const auto items = selectedItems();
        if (items.isEmpty() || items.front()->data(0, kKindRole).toInt() == int(ObjectKind::None)) {
            document_.select({});
            return;
        }
        document_.select({ObjectKind(items.front()->data(0, kKindRole).toInt()),
                          std::size_t(items.front()->data(0, kIndexRole).toULongLong())});
    });
    rebuild();
}

void OutlinePanel::rebuild()
{
    updating_ = true;
    clear();
    auto group = [this](const QString& name) {
        auto* item = new QTreeWidgetItem(this, {name});
        item->setData(0, kKindRole, int(ObjectKind::None));
        item->setFlags(Qt::ItemIsEnabled);
        item->setExpanded(true);
        return item;
    };
    auto add = [this](QTreeWidgetItem* parent, ObjectRef object) {
        auto* item = new QTreeWidgetItem(parent, {document_.objectName(object)});
        item->setData(0, kKindRole, int(object.kind));
        item->setData(0, kIndexRole, qulonglong(object.index));
    };
    patches_ = group(tr("Patches"));
    add(patches_, {ObjectKind::Source, 0});
    add(patches_, {ObjectKind::Receiver, 0});
    occluders_ = group(tr("Occluders (%1)").arg(document_.project().occluders.size()));
    for (std::size_t i = 0; i < document_.project().occluders.size(); ++i)
        add(occluders_, {ObjectKind::Occluder, i});
    const std::size_t objects = document_.sceneFile().instances.size();
    sceneFile_ = group(tr("Scene (%1 objects)").arg(objects));
    sceneFile_->setExpanded(objects <= 200);
    for (std::size_t i = 0; i < objects; ++i)
        add(sceneFile_, {ObjectKind::SceneObject, i});
    updating_ = false;
    showSelection(document_.selection());
}

QTreeWidgetItem* OutlinePanel::itemFor(ObjectRef object) const
{
    QTreeWidgetItem* parent = object.isPatch() ? patches_ : object.kind == ObjectKind::Occluder ? occluders_ : sceneFile_;
    const int row = object.kind == ObjectKind::Receiver ? 1 : object.isPatch() ? 0 : int(object.index);
    return parent && row < parent->childCount() ? parent->child(row) : nullptr;
}

void OutlinePanel::showSelection(ObjectRef selection)
{
    updating_ = true;
    clearSelection();
    if (selection)
        if (QTreeWidgetItem* item = itemFor(selection)) {
            item->setSelected(true);
            scrollToItem(item);
        }
    updating_ = false;
}

} // namespace sightline::ui
