#pragma once
// Which files a file may name. A project (or a glTF) that names `../../home/me/.ssh/id_rsa` or a
// symlink pointing out of its folder would otherwise read whatever it likes when someone opens a
// file they were sent. The rule, shared by every reader that resolves a path written inside a file:
//  - an absolute path is taken as written (its author asked for that file explicitly);
//  - a relative path must resolve, after every symlink that exists is followed, inside the
//    folder it is relative to; otherwise it is refused unless the user allowed it for this run.

#include <filesystem>
#include <string>

namespace sightline {

/// Whether `path`, made absolute and with every existing symlink followed, lies inside `folder`
/// (itself resolved the same way). A path that cannot be resolved is not inside.
bool resolvesInside(const std::filesystem::path& path, const std::filesystem::path& folder);

/// The file a path written in a file means: `written` as is when absolute, else `folder / written`.
/// A relative path that leaves `folder` throws sightline::Error unless `allowOutside`:
/// "<what>: <key> '<written>' leaves the project's folder; pass --allow-outside-paths to allow it".
/// `key` names where the path was written ("scene", "occluders[2].mesh").
std::filesystem::path resolveWrittenPath(const std::string& written, const std::filesystem::path& folder,
                                         bool allowOutside, const std::string& what, const std::string& key);

} // namespace sightline
