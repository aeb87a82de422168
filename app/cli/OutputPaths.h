#pragma once
// Files a command writes never replace the files it reads, nor each other. Without this check
// `shaft p.json --mask p.json` replaced the project with the mask, `importance p.json --out
// level.obj` the level with a PNG, and `--out m.png --npy m.png` kept only the .npy: each a silent
// success that destroys the user's work. A refusal names both roles:
// "--mask p.json would replace the project p.json, which this command reads; choose another file".

#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace sightline {
struct Project;
}

namespace sightline::cli {

/// A file and what it is to the command: an option ("--mask") or an input ("the scene").
struct FileRole {
    std::string role;
    std::filesystem::path path;
};

/// What a project reads: the project file, its scene, occluder mesh files, the light texture and
/// the receiver heights. A path the project cannot resolve is left out (reading it fails anyway,
/// with its own message).
std::vector<FileRole> projectInputs(const std::filesystem::path& projectFile, const Project& project);

/// Throws sightline::Error when an output names one of the inputs or another output. The same
/// file is recognised through symlinks, hard links and "./" spellings. Outputs with an empty path
/// (options not given) are skipped.
void checkOutputs(const std::vector<FileRole>& outputs, const std::vector<FileRole>& inputs);

/// A CLI11 check for options that name a file to write: an empty name ("--mask ''") is refused
/// instead of being taken for "not given".
CLI::Validator outputFile();

} // namespace sightline::cli
