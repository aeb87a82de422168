#pragma once
// Options that only some methods read. An option the chosen method would ignore is refused rather
// than dropped: a user who asks for `--threads 1` on the GL sampler, or `--strategy bitmask` on
// the reference, would otherwise time or trust a run that is not the one they asked for.

#include <algorithm>
#include <initializer_list>
#include <string>

#include <CLI/CLI.hpp>

#include "base/Error.h"

namespace sightline::cli {

/// Whether the user gave `name` (e.g. "--threads") on `command`'s command line, as opposed to
/// leaving its default.
inline bool given(const CLI::App& command, const std::string& name)
{
    return command.get_option(name)->count() > 0;
}

/// --allow-outside-paths, on every subcommand that loads a project (base/PathRule.h).
inline void addAllowOutsidePaths(CLI::App* command, bool& allow)
{
    command->add_flag("--allow-outside-paths", allow,
                      "Read files the project names by a relative path that leaves its folder ('../x.glb', or a "
                      "symlink out of it); refused without this flag. Absolute paths are always read");
}

/// Throws sightline::Error when `option` was given with a `method` outside `methods`:
/// "--threads applies to --method raycast or cpu, not gl".
inline void requireMethod(const CLI::App& command, const std::string& option, const std::string& method,
                          std::initializer_list<const char*> methods)
{
    if (!given(command, option) || std::find(methods.begin(), methods.end(), method) != methods.end())
        return;
    std::string list;
    std::size_t k = 0;
    for (const char* m : methods) {
        if (k > 0)
            list += k + 1 == methods.size() ? " or " : ", ";
        list += m;
        ++k;
    }
    throw Error(option + " applies to --method " + list + ", not " + method +
                (given(command, "--method") ? "" : " (the default method)"));
}

} // namespace sightline::cli
