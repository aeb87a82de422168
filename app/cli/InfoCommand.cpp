#include "cli/InfoCommand.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/OptionRules.h"
#include "cli/OutputLimits.h"
#include "plugins/SceneFormats.h"
#include "project/Project.h"

namespace sightline::cli {

namespace fs = std::filesystem;
using nlohmann::json;

CLI::App* addInfoCommand(CLI::App& app, InfoArgs& args)
{
    CLI::App* infoCmd = app.add_subcommand("info", "Print counts, bounds and instances of a scene or project");
    infoCmd->add_option("file", args.file, "Scene file (glTF, GLB, OBJ, PLY, OFF, STL) or project (.json)")->required();
    infoCmd->add_flag("--json", args.json, "Print one JSON object instead of text");
    addAllowOutsidePaths(infoCmd, args.allowOutsidePaths);
    return infoCmd;
}

int runInfo(const InfoArgs& args)
{
    const std::string& path = args.file;
    std::vector<std::string> warnings;
    Scene scene;
    const bool isProject = fs::path(path).extension() == ".json";
    if (isProject)
        scene = buildScene(loadProject(path, {.allowOutsidePaths = args.allowOutsidePaths}), &warnings);
    else
        scene = loadScene(path, &warnings);
    printWarnings(warnings);
    const Bounds box = scene.bounds();
    std::size_t vertices = 0;
    for (const Mesh& mesh : scene.meshes)
        vertices += mesh.positions.size();

    if (args.json) {
        json instances = json::array();
        for (const Instance& instance : scene.instances)
            instances.push_back({{"name", instance.name},
                                 {"mesh", scene.meshes[instance.mesh].name},
                                 {"triangles", scene.meshes[instance.mesh].triangleCount()}});
        json out = {{"file", path},
                    {"meshes", scene.meshes.size()},
                    {"instances", scene.instances.size()},
                    {"vertices", vertices},
                    {"triangles", scene.triangleCount()},
                    {"unique_triangles", scene.uniqueTriangleCount()},
                    {"instance_list", instances}};
        if (!box.empty())
            out["bounds"] = {{"min", {box.min.x, box.min.y, box.min.z}}, {"max", {box.max.x, box.max.y, box.max.z}}};
        std::cout << dumpJson(out) << "\n";
        return 0;
    }
    std::printf("file       %s\n", path.c_str());
    std::printf("meshes     %zu (%zu vertices, %zu triangles stored)\n", scene.meshes.size(), vertices,
                scene.uniqueTriangleCount());
    std::printf("instances  %zu (%zu triangles in the world)\n", scene.instances.size(), scene.triangleCount());
    if (box.empty())
        std::printf("bounds     empty\n");
    else
        std::printf("bounds     [%.3f, %.3f, %.3f] .. [%.3f, %.3f, %.3f] m\n", box.min.x, box.min.y, box.min.z,
                    box.max.x, box.max.y, box.max.z);
    const std::size_t shown = std::min<std::size_t>(scene.instances.size(), 20);
    for (std::size_t i = 0; i < shown; ++i) {
        const Instance& instance = scene.instances[i];
        std::printf("  %-24s mesh %-20s %zu triangles\n", instance.name.c_str(),
                    scene.meshes[instance.mesh].name.c_str(), scene.meshes[instance.mesh].triangleCount());
    }
    if (shown < scene.instances.size())
        std::printf("  ... and %zu more instances (use --json for all)\n", scene.instances.size() - shown);
    return 0;
}

} // namespace sightline::cli
