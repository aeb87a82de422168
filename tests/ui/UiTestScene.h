#pragma once
// A small level for the editor's tests, written as an OBJ file: a 20 x 20 m floor at y = 0, and
// the demo project copied to a temporary folder.

#include <cmath>
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

/// Writes terrain.obj into `folder`: 200 x 100 m of rolling ground (6 m hills) rising 10 m along
/// x, wound to face up, and returns its path.
inline std::filesystem::path writeTerrainObj(const std::filesystem::path& folder)
{
    std::filesystem::create_directories(folder);
    const auto path = folder / "terrain.obj";
    std::ofstream out(path);
    const int n = 40;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = -100.0 + 200.0 * i / n, z = -50.0 + 100.0 * j / n;
            out << "v " << x << " " << 6.0 * std::sin(x / 15.0) * std::cos(z / 12.0) + 0.05 * x << " " << z << "\n";
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 1, d = c + 1;
            out << "f " << a << " " << c << " " << b << "\nf " << b << " " << c << " " << d << "\n";
        }
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
