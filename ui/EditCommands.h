#pragma once
// Undo commands (QUndoStack) for every edit of the document. They store values, not pointers:
// an object's state before and after, or the occluder added or removed, so any order of undo and
// redo restores exactly what was there.

#include <QUndoCommand>

#include "editor/ObjectEdits.h"
#include "editor/ObjectFlags.h"
#include "project/Project.h"

namespace sightline::ui {

class EditorDocument;

/// Moves, rotates, resizes or re-samples one object.
class SetStateCommand : public QUndoCommand {
public:
    SetStateCommand(EditorDocument& document, ObjectRef object, ObjectState before, ObjectState after, const QString& text);
    void undo() override;
    void redo() override;

private:
    EditorDocument& document_;
    ObjectRef object_;
    ObjectState before_, after_;
};

/// Adds (or, with `remove`, deletes) the occluder at `index`.
class OccluderListCommand : public QUndoCommand {
public:
    OccluderListCommand(EditorDocument& document, std::size_t index, OccluderSpec spec, bool remove, const QString& text);
    void undo() override;
    void redo() override;

private:
    void insert();
    void erase();

    EditorDocument& document_;
    std::size_t index_;
    OccluderSpec spec_;
    bool remove_;
};

/// Sets or removes (null) one top-level project key ("recorded_path", "pvs"), undoably.
class SetProjectKeyCommand : public QUndoCommand {
public:
    SetProjectKeyCommand(EditorDocument& document, std::string key, nlohmann::json before, nlohmann::json after, const QString& text);
    void undo() override;
    void redo() override;

private:
    EditorDocument& document_;
    std::string key_;
    nlohmann::json before_, after_;
};

/// Renames the occluder at `index`.
class RenameOccluderCommand : public QUndoCommand {
public:
    RenameOccluderCommand(EditorDocument& document, std::size_t index, std::string before, std::string after);
    void undo() override;
    void redo() override;

private:
    EditorDocument& document_;
    std::size_t index_;
    std::string before_, after_;
};

/// Hides, shows, locks or unlocks one object.
class SetFlagsCommand : public QUndoCommand {
public:
    SetFlagsCommand(EditorDocument& document, ObjectRef object, ObjectFlags before, ObjectFlags after, const QString& text);
    void undo() override;
    void redo() override;

private:
    EditorDocument& document_;
    ObjectRef object_;
    ObjectFlags before_, after_;
};

} // namespace sightline::ui
