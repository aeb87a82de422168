#include "cli/OutputPaths.h"

#include <system_error>

#include "project/Project.h"
#include "base/Error.h"

namespace sightline::cli {

namespace fs = std::filesystem;

namespace {

/// Whether a and b name one file: the same inode where both exist, else the same normalised
/// absolute path (an output not written yet cannot be a hard link of anything).
bool sameFile(const fs::path& a, const fs::path& b)
{
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) {
        const bool same = fs::equivalent(a, b, ec);
        if (!ec)
            return same;
    }
    const fs::path ca = fs::weakly_canonical(fs::absolute(a), ec);
    const fs::path cb = fs::weakly_canonical(fs::absolute(b), ec);
    return (ca.empty() ? fs::absolute(a).lexically_normal() : ca) == (cb.empty() ? fs::absolute(b).lexically_normal() : cb);
}

/// A path the project names, resolved as its reader will; nothing when it does not resolve.
void addResolved(std::vector<FileRole>& files, const Project& project, const std::string& path, const std::string& key,
                 const std::string& role)
{
    if (path.empty())
        return;
    try {
        files.push_back({role, project.resolve(path, key)});
    } catch (const std::exception&) {
        // Refused by the path rule: the reader says so when it gets there.
    }
}

void addStringKey(std::vector<FileRole>& files, const Project& project, const nlohmann::json& object,
                  const std::string& parent, const std::string& key, const std::string& role)
{
    if (object.is_object() && object.contains(key) && object.at(key).is_string())
        addResolved(files, project, object.at(key).get<std::string>(), parent + "." + key, role);
}

} // namespace

std::vector<FileRole> projectInputs(const fs::path& projectFile, const Project& project)
{
    std::vector<FileRole> files{{"the project", projectFile}};
    addResolved(files, project, project.scene, "scene", "the scene");
    for (const OccluderSpec& spec : project.occluders)
        if (!isBuiltinMesh(spec.mesh))
            addResolved(files, project, spec.mesh, "occluders", "the occluder mesh");
    if (project.extra.contains("light"))
        addStringKey(files, project, project.extra.at("light"), "light", "texture", "the light texture");
    if (project.extra.contains("receiver_heights")) {
        const nlohmann::json& heights = project.extra.at("receiver_heights");
        addStringKey(files, project, heights, "receiver_heights", "image", "the receiver heights");
        addStringKey(files, project, heights, "receiver_heights", "npy", "the receiver heights");
    }
    return files;
}

void checkOutputs(const std::vector<FileRole>& outputs, const std::vector<FileRole>& inputs)
{
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const FileRole& out = outputs[i];
        if (out.path.empty())
            continue;
        for (const FileRole& in : inputs)
            if (!in.path.empty() && sameFile(out.path, in.path))
                throw Error(out.role + " " + out.path.string() + " would replace " + in.role + " " + in.path.string() +
                            ", which this command reads; choose another file");
        for (std::size_t j = 0; j < i; ++j)
            if (!outputs[j].path.empty() && sameFile(out.path, outputs[j].path))
                throw Error(outputs[j].role + " and " + out.role + " both name " + out.path.string() +
                            "; the second would replace the first");
    }
}

CLI::Validator outputFile()
{
    return CLI::Validator(
        [](std::string& value) { return value.empty() ? std::string("an empty file name; name the file to write") : std::string(); },
        "FILE");
}

} // namespace sightline::cli
