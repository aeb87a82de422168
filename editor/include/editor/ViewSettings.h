#pragma once
// The view a project opens with: the camera saved in the project's "editor" settings (a key the
// CLI keeps but ignores, docs/design.md §3), or a view across the shaft between the two patches.
// `sightline --screenshot` and the editor use the same rule, so a screenshot shows what the
// designer saw when saving.

#include <optional>

#include <nlohmann/json.hpp>

#include "editor/Camera.h"
#include "visibility/Patch.h"

namespace sightline::ui {

nlohmann::json cameraToJson(const Camera& camera);
/// nullopt when `value` is not a complete, finite camera.
std::optional<Camera> cameraFromJson(const nlohmann::json& value);

/// Looking at the shaft from its side, slightly from above, with both patches in view.
Camera shaftView(const Patch& source, const Patch& receiver);

/// The project's saved camera ("editor": {"camera": ...}) or the shaft view.
Camera projectView(const nlohmann::json& editorSettings, const Patch& source, const Patch& receiver);

} // namespace sightline::ui
