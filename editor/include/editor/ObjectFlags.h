#pragma once
// Hide and lock, the outline's switches, and where a project keeps them.
//
// What they mean (docs/editor.md):
//   - hidden: not drawn and not picked (clicks and placement go through it). It still blocks rays:
//     hiding changes the view, not the level, so the counts, the overlays and the CLI give the
//     same answer (rays stop at a hidden object, their white stop dots in what looks like thin air;
//     the outline shows the object greyed, "hidden, still blocks rays").
//   - locked: drawn, but a click passes through it to what lies behind (Unity's "not pickable"),
//     no gizmo and no edit (properties greyed, Delete refused, a locked patch is not placed again).
//     Patches are still placed on it: locking a floor is how to keep it still while placing on it.
//   - isolated (the editor's view state, not kept): everything but the isolated object and the two
//     patches hidden.
//
// Both are kept in the project, as keys the CLI ignores and keeps (docs/design.md §3): a placed
// occluder's own entry gets "editor": {"hidden": true, "locked": true}, so the flags travel with it
// when others are added or deleted; the level's objects (by instance index, as scene_transforms)
// and the patches are listed in the project's "editor" settings:
//   "editor": {"hidden": {"instances": [3, 7], "patches": ["receiver"]}, "locked": {"instances": [0]}}
// Values of another shape read as no flag and are replaced when written; other keys are kept.

#include <nlohmann/json.hpp>

#include "editor/ObjectEdits.h"
#include "project/Project.h"

namespace sightline::ui {

struct ObjectFlags {
    bool hidden = false;
    bool locked = false;
    bool operator==(const ObjectFlags&) const = default;
};

ObjectFlags occluderFlags(const OccluderSpec& occluder);
void setOccluderFlags(OccluderSpec& occluder, ObjectFlags flags);

/// A patch's or a level object's flags in the project's "editor" settings (`object` is a patch or
/// a SceneObject; anything else has none).
ObjectFlags settingsFlags(const nlohmann::json& editor, ObjectRef object);
void setSettingsFlags(nlohmann::json& editor, ObjectRef object, ObjectFlags flags);

} // namespace sightline::ui
