#include "OutlinePanel.h"

#include <QAction>
#include <QHeaderView>
#include <QLineEdit>
#include <QStyledItemDelegate>
#include <QTreeWidget>
#include <QVBoxLayout>

#include <map>

#include "EditorDocument.h"

namespace sightline::ui {

namespace {
constexpr int kKindRole = Qt::UserRole;
constexpr int kIndexRole = Qt::UserRole + 1;

/// The check-box columns are not text to edit (an occluder's row is editable for its name).
class NoEditor : public QStyledItemDelegate {
public:
    using QStyledItemDelegate::QStyledItemDelegate;
    QWidget* createEditor(QWidget*, const QStyleOptionViewItem&, const QModelIndex&) const override { return nullptr; }
};
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
    tree_->setColumnCount(3);
    tree_->setHeaderLabels({tr("Object"), tr("Show"), tr("Lock")});
    tree_->header()->setStretchLastSection(false);
    tree_->header()->setSectionResizeMode(NameColumn, QHeaderView::Stretch);
    tree_->header()->setSectionResizeMode(ShowColumn, QHeaderView::ResizeToContents);
    tree_->header()->setSectionResizeMode(LockColumn, QHeaderView::ResizeToContents);
    tree_->setItemDelegateForColumn(ShowColumn, new NoEditor(tree_));
    tree_->setItemDelegateForColumn(LockColumn, new NoEditor(tree_));
    tree_->headerItem()->setToolTip(ShowColumn, tr("Shown in the view (hidden objects still block rays)"));
    tree_->headerItem()->setToolTip(LockColumn, tr("Locked: clicks pass through it, and it cannot be moved"));
    tree_->setSelectionMode(QAbstractItemView::SingleSelection);
    tree_->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed);
    connect(search_, &QLineEdit::textChanged, this, &OutlinePanel::setFilter);
    connect(&document_, &EditorDocument::changed, this, [this](unsigned changes) {
        if (changes & (OccludersChanged | DocumentReset | NamesChanged | LightsChanged | CoarseOccludersChanged))
            rebuild();
        else if (changes & FlagsChanged)
            refreshFlags();
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
    connect(tree_, &QTreeWidget::itemChanged, this, [this](QTreeWidgetItem* item, int column) {
        if (updating_ || item->data(0, kKindRole).toInt() == int(ObjectKind::None))
            return;
        const ObjectRef object{ObjectKind(item->data(0, kKindRole).toInt()), std::size_t(item->data(0, kIndexRole).toULongLong())};
        if (column == ShowColumn || column == LockColumn) {
            ObjectFlags flags = document_.flags(object);
            const bool checked = item->checkState(column) == Qt::Checked;
            if (column == ShowColumn)
                flags.hidden = !checked;
            else
                flags.locked = checked;
            const QString name = document_.objectName(object);
            document_.setFlags(object, flags,
                               column == ShowColumn ? (checked ? tr("Show %1") : tr("Hide %1")).arg(name)
                                                    : (checked ? tr("Lock %1") : tr("Unlock %1")).arg(name));
            return;
        }
        if (object.kind != ObjectKind::Occluder)
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
    const auto checkable = [](QTreeWidgetItem* item) {
        item->setFlags(item->flags() | Qt::ItemIsUserCheckable);
        item->setCheckState(ShowColumn, Qt::Checked);
        item->setCheckState(LockColumn, Qt::Unchecked);
    };
    std::map<std::size_t, CoarseOccluder> standIns;
    for (const CoarseOccluder& standIn : document_.coarseOccluders())
        standIns[standIn.instance] = standIn;
    auto addAll = [this, checkable, &standIns](QTreeWidgetItem* parent, ObjectKind kind, std::size_t count) {
        std::vector<QString> names;
        for (std::size_t i = 0; i < count; ++i)
            names.push_back(document_.objectName({kind, i}));
        const std::vector<QString> shown = distinctNames(names);
        for (std::size_t i = 0; i < count; ++i) {
            auto* item = new QTreeWidgetItem(parent, {shown[i]});
            item->setData(0, kKindRole, int(kind));
            item->setData(0, kIndexRole, qulonglong(i));
            if (kind != ObjectKind::Light)   // lights are neither hidden nor locked
                checkable(item);
            if (kind == ObjectKind::Occluder) {
                item->setText(0, names[i]);   // edited as the name itself; numbered in the tooltip
                item->setFlags(item->flags() | Qt::ItemIsEditable);
                item->setToolTip(0, tr("%1 (F2 or double click to rename)").arg(shown[i]));
            } else if (kind == ObjectKind::SceneObject) {
                item->setToolTip(0, tr("%1: instance %2 of the level").arg(shown[i]).arg(i));
                if (const auto standIn = standIns.find(i); standIn != standIns.end()) {
                    // Its rays are answered by a stand-in (Edit > Coarse Occluder): said where it is listed.
                    item->setText(0, tr("%1 · coarse").arg(shown[i]));
                    item->setToolTip(0, tr("%1: instance %2 of the level; its rays answered by a coarse stand-in (%3)")
                                            .arg(shown[i])
                                            .arg(i)
                                            .arg(QString::fromStdString(describeCoarse(standIn->second))));
                }
            }
        }
    };
    patches_ = group(tr("Patches"));
    for (ObjectKind kind : {ObjectKind::Source, ObjectKind::Receiver}) {
        auto* item = new QTreeWidgetItem(patches_, {document_.objectName({kind, 0})});
        item->setData(0, kKindRole, int(kind));
        item->setData(0, kIndexRole, qulonglong(0));
        checkable(item);
    }
    occluders_ = group(tr("Occluders (%1)").arg(document_.project().occluders.size()));
    addAll(occluders_, ObjectKind::Occluder, document_.project().occluders.size());
    lights_ = group(tr("Lights (%1)").arg(document_.lights().size()));
    addAll(lights_, ObjectKind::Light, document_.lights().size());
    const std::size_t objects = document_.sceneFile().instances.size();
    sceneFile_ = group(tr("Scene (%1 objects)").arg(objects));
    sceneFile_->setExpanded(objects <= 200);
    addAll(sceneFile_, ObjectKind::SceneObject, objects);
    updating_ = false;
    refreshFlags();
    setFilter(search_->text());
    showSelection(document_.selection());
}

void OutlinePanel::refreshFlags()
{
    updating_ = true;
    const ObjectRef isolated = document_.isolated();
    for (QTreeWidgetItem* group : {patches_, occluders_, sceneFile_}) {
        if (!group)
            continue;
        for (int i = 0; i < group->childCount(); ++i) {
            QTreeWidgetItem* item = group->child(i);
            const ObjectRef object{ObjectKind(item->data(0, kKindRole).toInt()), std::size_t(item->data(0, kIndexRole).toULongLong())};
            const ObjectFlags flags = document_.flags(object);
            const Qt::CheckState show = flags.hidden ? Qt::Unchecked : Qt::Checked, lock = flags.locked ? Qt::Checked : Qt::Unchecked;
            if (item->checkState(ShowColumn) != show)
                item->setCheckState(ShowColumn, show);
            if (item->checkState(LockColumn) != lock)
                item->setCheckState(LockColumn, lock);
            const bool shown = document_.isShown(object);
            QFont font = item->font(NameColumn);
            font.setItalic(flags.hidden);
            item->setFont(NameColumn, font);
            item->setForeground(NameColumn, shown ? tree_->palette().brush(QPalette::Text) : tree_->palette().brush(QPalette::Disabled, QPalette::Text));
            QString note;
            if (flags.hidden)
                note = tr("hidden: not drawn, not picked; it still blocks rays");
            else if (!shown)
                note = tr("hidden while another object is isolated (Shift+H ends it)");
            if (flags.locked)
                note += (note.isEmpty() ? QString() : QString("; ")) + tr("locked: clicks pass through it, it cannot be moved");
            item->setToolTip(ShowColumn, note.isEmpty() ? tr("Shown") : note);
            item->setToolTip(LockColumn, flags.locked ? tr("Locked") : tr("Not locked"));
            item->setData(NameColumn, Qt::StatusTipRole, note);
        }
    }
    if (patches_)
        patches_->setText(NameColumn, isolated ? tr("Patches (isolating %1)").arg(document_.objectName(isolated)) : tr("Patches"));
    updating_ = false;
}

void OutlinePanel::setContextActions(const QList<QAction*>& actions)
{
    tree_->setContextMenuPolicy(Qt::ActionsContextMenu);
    tree_->addActions(actions);
}

void OutlinePanel::setFilter(const QString& text)
{
    const QString needle = text.trimmed();
    for (QTreeWidgetItem* group : {patches_, occluders_, lights_, sceneFile_}) {
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
    QTreeWidgetItem* parent = object.isPatch()                       ? patches_
                              : object.kind == ObjectKind::Occluder ? occluders_
                              : object.kind == ObjectKind::Light    ? lights_
                                                                    : sceneFile_;
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
