// The format registry keyed by lower-case file extension, and the loadScene()/saveScene() entry points.

#include <algorithm>
#include <cctype>

#include "BuiltinFormats.h"
#include "plugins/SceneFormats.h"
#include "base/Error.h"

namespace sightline {

namespace {

std::string lowerExtension(const std::filesystem::path& file)
{
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

template <class Format>
const Format* findFor(const std::vector<std::unique_ptr<Format>>& formats, const std::filesystem::path& file)
{
    const std::string ext = lowerExtension(file);
    for (const auto& format : formats) {
        const auto exts = format->extensions();
        if (std::find(exts.begin(), exts.end(), ext) != exts.end())
            return format.get();
    }
    return nullptr;
}

template <class Format>
std::string patterns(const std::vector<std::unique_ptr<Format>>& formats)
{
    std::string out;
    for (const auto& format : formats)
        for (const std::string& ext : format->extensions())
            out += (out.empty() ? "*" : " *") + ext;
    return out;
}

} // namespace

const SceneFormatRegistry& SceneFormatRegistry::builtin()
{
    static const SceneFormatRegistry registry = [] {
        SceneFormatRegistry r;
        r.add(makeGltfImporter());
        r.add(makeGltfExporter());
        r.add(makeMeshFileImporter());
        r.add(makeQuakeBspImporter());
        r.add(makeQuakeMapImporter());
        return r;
    }();
    return registry;
}

void SceneFormatRegistry::add(std::unique_ptr<SceneImporter> importer) { importers_.push_back(std::move(importer)); }
void SceneFormatRegistry::add(std::unique_ptr<SceneExporter> exporter) { exporters_.push_back(std::move(exporter)); }

const SceneImporter* SceneFormatRegistry::importerFor(const std::filesystem::path& file) const
{
    return findFor(importers_, file);
}

const SceneExporter* SceneFormatRegistry::exporterFor(const std::filesystem::path& file) const
{
    return findFor(exporters_, file);
}

std::string SceneFormatRegistry::importFilter() const { return patterns(importers_); }

Scene loadScene(const std::filesystem::path& file, std::vector<std::string>* warnings, const SceneLoadOptions& options)
{
    std::error_code ec;
    if (!std::filesystem::exists(file, ec))
        throw Error(file.string() + ": no such file");
    if (std::filesystem::is_directory(file, ec))
        throw Error(file.string() + ": is a folder, not a scene file");
    const SceneFormatRegistry& registry = SceneFormatRegistry::builtin();
    const SceneImporter* importer = registry.importerFor(file);
    if (!importer)
        throw Error(file.string() + ": unknown scene format '" + lowerExtension(file) + "' (supported: " +
                    registry.importFilter() + ")");
    std::vector<std::string> ignored;
    return importer->load(file, warnings ? *warnings : ignored, options);
}

void saveScene(const Scene& scene, const std::filesystem::path& file)
{
    const SceneExporter* exporter = SceneFormatRegistry::builtin().exporterFor(file);
    if (!exporter)
        throw Error(file.string() + ": cannot save scenes as '" + lowerExtension(file) + "' (supported: *.gltf *.glb)");
    exporter->save(scene, file);
}

} // namespace sightline
