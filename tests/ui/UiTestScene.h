#pragma once
// A small level for the editor's tests, written as an OBJ file: a 20 x 20 m floor at y = 0, and
// the demo project copied to a temporary folder.

#include <filesystem>
#include <fstream>
#include <string>

#include "visibility/Patch.h"

namespace sightline::test {

/// Writes floor.obj into `folder` and returns its path.
inline std::filesystem::path writeFloorObj(const std::filesystem::path& folder)
{
    std::filesystem::create_directories(folder);
    const auto path = folder / "floor.obj";
    std::ofstream out(path);
    out << "v -10 0 -10\nv 10 0 -10\nv 10 0 10\nv -10 0 10\nf 1 3 2\nf 1 4 3\n";
    return path;
}

/// A source at x = 0 facing +x and a receiver at x = 6 facing -x, 1 m squares 1 m above the
/// floor, 16 x 16 samples each.
inline std::pair<Patch, Patch> floorPatches()
{
    Patch source, receiver;
    source.corner = {0.0, 1.0, 0.5};
    source.u = {0.0, 0.0, -1.0};
    source.v = {0.0, 1.0, 0.0};
    receiver.corner = {6.0, 1.0, -0.5};
    receiver.u = {0.0, 0.0, 1.0};
    receiver.v = {0.0, 1.0, 0.0};
    source.na = source.nb = receiver.na = receiver.nb = 16;
    return {source, receiver};
}

/// A fresh folder under the system's temporary directory.
inline std::filesystem::path freshFolder(const std::string& name)
{
    const auto folder = std::filesystem::temp_directory_path() / ("sightline-" + name);
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder;
}

/// Copies the demo project and level (generated at build time) into `folder`.
inline std::filesystem::path copyDemoProject(const std::filesystem::path& folder)
{
    const std::filesystem::path demo(SIGHTLINE_DEMO_PROJECT);
    std::filesystem::copy_file(demo, folder / "demo.json", std::filesystem::copy_options::overwrite_existing);
    std::filesystem::copy_file(demo.parent_path() / "demo_level.glb", folder / "demo_level.glb",
                               std::filesystem::copy_options::overwrite_existing);
    return folder / "demo.json";
}

} // namespace sightline::test
