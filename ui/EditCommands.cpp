#include "EditCommands.h"

#include <QObject>

#include "EditorDocument.h"

namespace sightline::ui {

SetStateCommand::SetStateCommand(EditorDocument& document, ObjectRef object, ObjectState before, ObjectState after,
                                 const QString& text)
    : QUndoCommand(text), document_(document), object_(object), before_(std::move(before)), after_(std::move(after))
{
}

void SetStateCommand::undo() { document_.applyState(object_, before_); }
void SetStateCommand::redo() { document_.applyState(object_, after_); }

OccluderListCommand::OccluderListCommand(EditorDocument& document, std::size_t index, OccluderSpec spec, bool remove,
                                         const QString& text)
    : QUndoCommand(text), document_(document), index_(index), spec_(std::move(spec)), remove_(remove)
{
}

void OccluderListCommand::insert()
{
    document_.insertOccluder(index_, spec_);
    document_.select({ObjectKind::Occluder, index_});
}

void OccluderListCommand::erase()
{
    document_.select({});
    document_.eraseOccluder(index_);
}

void OccluderListCommand::undo() { remove_ ? insert() : erase(); }
void OccluderListCommand::redo() { remove_ ? erase() : insert(); }

SetProjectKeyCommand::SetProjectKeyCommand(EditorDocument& document, std::string key, nlohmann::json before, nlohmann::json after,
                                           const QString& text)
    : QUndoCommand(text), document_(document), key_(std::move(key)), before_(std::move(before)), after_(std::move(after))
{
}

void SetProjectKeyCommand::undo() { document_.applyProjectKey(key_, before_); }
void SetProjectKeyCommand::redo() { document_.applyProjectKey(key_, after_); }

RenameOccluderCommand::RenameOccluderCommand(EditorDocument& document, std::size_t index, std::string before, std::string after)
    : QUndoCommand(QObject::tr("Rename %1").arg(QString::fromStdString(after))), document_(document), index_(index),
      before_(std::move(before)), after_(std::move(after))
{
}

void RenameOccluderCommand::undo() { document_.applyOccluderName(index_, before_); }
void RenameOccluderCommand::redo() { document_.applyOccluderName(index_, after_); }

SetFlagsCommand::SetFlagsCommand(EditorDocument& document, ObjectRef object, ObjectFlags before, ObjectFlags after,
                                 const QString& text)
    : QUndoCommand(text), document_(document), object_(object), before_(before), after_(after)
{
}

void SetFlagsCommand::undo() { document_.applyFlags(object_, before_); }
void SetFlagsCommand::redo() { document_.applyFlags(object_, after_); }

} // namespace sightline::ui
