#include "OutlinePanel.h"

#include <QLineEdit>
#include <QTreeWidget>
#include <QVBoxLayout>

#include <map>

#include "EditorDocument.h"

namespace sightline::ui {

namespace {
constexpr int kKindRole = Qt::UserRole;
constexpr int kIndexRole = Qt::UserRole + 1;
} // namespace

std::vector<QString> distinctNames(const std::vector<QString>& names)
{
    std::map<QString, int> total, seen;
    for (const QString& name : names)
        ++total[name];
    std::vector<QString> out;
    out.reserve(names.size());
    for (const QString& name : names) {
        const int of = total[name];
        out.push_back(of > 1 ? QString("%1 #%2 of %3").arg(name).arg(++seen[name]).arg(of) : name);
    }
    return out;
}

OutlinePanel::OutlinePanel(EditorDocument& document, QWidget* parent) : QWidget(parent), document_(document)
{
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    search_ = new QLineEdit(this);
    search_->setPlaceholderText(tr("Search objects"));
    search_->setClearButtonEnabled(true);
    layout->addWidget(search_);
    tree_ = new QTreeWidget(this);
    layout->addWidget(tree_);
    tree_->setHeaderHidden(true);
    tree_->setSelectionMode(QAbstractItemView::SingleSelection);
    tree_->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed);
    connect(search_, &QLineEdit::textChanged, this, &OutlinePanel::setFilter);
    connect(&document_, &EditorDocument::changed, this, [this](unsigned changes) {
        if (changes & (OccludersChanged | DocumentReset | NamesChanged))
            rebuild();
    });
    connect(&document_, &EditorDocument::selectionChanged, this, &OutlinePanel::showSelection);
    connect(tree_, &QTreeWidget::itemSelectionChanged, this, [this] {
        if (updating_)
            return;
        const auto items = tree_->selectedItems();
        if (items.isEmpty() || items.front()->data(0, kKindRole).toInt() == int(ObjectKind::None)) {
            document_.select({});
            return;
        }
        document_.select({ObjectKind(items.front()->data(0, kKindRole).toInt()),
                          std::size_t(items.front()->data(0, kIndexRole).toULongLong())});
    });
    // An occluder's name edited in place: one undoable rename (the rebuild shows the result).
    connect(tree_, &QTreeWidget::itemChanged, this, [this](QTreeWidgetItem* item, int) {
        if (updating_ || item->data(0, kKindRole).toInt() != int(ObjectKind::Occluder))
            return;
        const std::size_t index = std::size_t(item->data(0, kIndexRole).toULongLong());
        const QString name = item->text(0).trimmed();
        if (name.isEmpty()) {
            rebuild();   // an empty name is not a name: the old one stays
            return;
        }
        document_.renameOccluder(index, name.toStdString());
    });
    rebuild();
}

void OutlinePanel::rebuild()
{
    updating_ = true;
    tree_->clear();
    auto group = [this](const QString& name) {
        auto* item = new QTreeWidgetItem(tree_, {name});
        item->setData(0, kKindRole, int(ObjectKind::None));
        item->setFlags(Qt::ItemIsEnabled);
        item->setExpanded(true);
        return item;
    };
    auto addAll = [this](QTreeWidgetItem* parent, ObjectKind kind, std::size_t count) {
        std::vector<QString> names;
        for (std::size_t i = 0; i < count; ++i)
            names.push_back(document_.objectName({kind, i}));
        const std::vector<QString> shown = distinctNames(names);
        for (std::size_t i = 0; i < count; ++i) {
            auto* item = new QTreeWidgetItem(parent, {shown[i]});
            item->setData(0, kKindRole, int(kind));
            item->setData(0, kIndexRole, qulonglong(i));
            if (kind == ObjectKind::Occluder) {
                item->setText(0, names[i]);   // edited as the name itself; numbered in the tooltip
                item->setFlags(item->flags() | Qt::ItemIsEditable);
                item->setToolTip(0, tr("%1 (F2 or double click to rename)").arg(shown[i]));
            } else if (kind == ObjectKind::SceneObject) {
                item->setToolTip(0, tr("%1: instance %2 of the level").arg(shown[i]).arg(i));
            }
        }
    };
    patches_ = group(tr("Patches"));
    for (ObjectKind kind : {ObjectKind::Source, ObjectKind::Receiver}) {
        auto* item = new QTreeWidgetItem(patches_, {document_.objectName({kind, 0})});
        item->setData(0, kKindRole, int(kind));
        item->setData(0, kIndexRole, qulonglong(0));
    }
    occluders_ = group(tr("Occluders (%1)").arg(document_.project().occluders.size()));
    addAll(occluders_, ObjectKind::Occluder, document_.project().occluders.size());
    const std::size_t objects = document_.sceneFile().instances.size();
    sceneFile_ = group(tr("Scene (%1 objects)").arg(objects));
    sceneFile_->setExpanded(objects <= 200);
    addAll(sceneFile_, ObjectKind::SceneObject, objects);
    updating_ = false;
    setFilter(search_->text());
    showSelection(document_.selection());
}

void OutlinePanel::setFilter(const QString& text)
{
    const QString needle = text.trimmed();
    for (QTreeWidgetItem* group : {patches_, occluders_, sceneFile_}) {
        if (!group)
            continue;
        int shown = 0;
        for (int i = 0; i < group->childCount(); ++i) {
            QTreeWidgetItem* item = group->child(i);
            const bool match = needle.isEmpty() || item->text(0).contains(needle, Qt::CaseInsensitive);
            item->setHidden(!match);
            shown += match;
        }
        if (!needle.isEmpty() && shown > 0)
            group->setExpanded(true);   // a match inside a collapsed group of 10,000 objects is shown
    }
    if (search_->text() != text)
        search_->setText(text);
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
    tree_->clearSelection();
    if (selection)
        if (QTreeWidgetItem* item = itemFor(selection)) {
            item->setSelected(true);
            tree_->scrollToItem(item);
        }
    updating_ = false;
}

} // namespace sightline::ui
