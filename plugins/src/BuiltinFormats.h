#pragma once
// Factories for the built-in formats; SceneFormatRegistry::builtin() is their only caller.

#include <memory>

#include "plugins/SceneFormats.h"

namespace sightline {

std::unique_ptr<SceneImporter> makeGltfImporter();
std::unique_ptr<SceneExporter> makeGltfExporter();
std::unique_ptr<SceneImporter> makeMeshFileImporter();
std::unique_ptr<SceneImporter> makeQuakeBspImporter();
std::unique_ptr<SceneImporter> makeQuakeMapImporter();

} // namespace sightline
