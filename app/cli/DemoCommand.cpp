#include "cli/DemoCommand.h"

#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "demo/BenchScenes.h"
#include "demo/DemoLevel.h"
#include "demo/DemoLights.h"
#include "plugins/SceneFormats.h"
#include "project/Project.h"
#include "project/ProjectLights.h"
#include "base/Error.h"

namespace sightline::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// Writes `scene` as SCENE.glb and a project PROJECT.json looking through it.
void writeDemoProject(const fs::path& folder, const std::string& sceneName, const std::string& projectName,
                      const Scene* scene, const Patch& source, const Patch& receiver, const std::string& description,
                      const json& extra = json::object())
{
    const fs::path sceneFile = folder / (sceneName + ".glb");
    if (scene)
        saveScene(*scene, sceneFile);
    Project project;
    project.folder = fs::absolute(folder);
    project.scene = sceneFile.filename().string();
    project.source = source;
    project.receiver = receiver;
    project.extra = extra;
    project.extra["description"] = description;
    const fs::path projectFile = folder / (projectName + ".json");
    saveProject(project, projectFile);
    if (scene)
        std::printf("wrote %s (%zu triangles) and %s\n", sceneFile.c_str(), scene->triangleCount(), projectFile.c_str());
    else
        std::printf("wrote %s\n", projectFile.c_str());
}

int writeDemo(const std::string& folder, int firstSeed, int lastSeed)
{
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec)
        throw Error(folder + ": cannot create folder (" + ec.message() + ")");
    const demo::DemoView view = demo::demoView();
    const Scene level = demo::makeDemoLevel();
    // The receiver walks 1.5 m along the conservatory wall and back: `importance --frames` and the
    // editor's Accumulate Animation have something to accumulate out of the box.
    const json walk = {{"frames", 40},
                       {"tracks", {{{"target", "receiver"}, {"interpolation", "linear"}, {"loop", true},
                                    {"keys", {{{"frame", 0}, {"translate", {0, 0, 0}}},
                                              {{"frame", 20}, {"translate", {0, 0, -1.5}}},
                                              {{"frame", 39}, {"translate", {0, 0, 0}}}}}}}}};
    writeDemoProject(folder, "demo_level", "demo", &level, view.source, view.receiver,
                     "Sightline demo: two patches looking through a doorway past plants and furniture",
                     {{"animation", walk},
                      // 1.5 m view cells over the floors: 255 cells x 175 objects (docs/pvs.md)
                      {"pvs", {{"cell_size", 1.5}}}});
    // Which parts of the conservatory floor the gallery's guard post overlooks (an importance map
    // over a large receiver, paper §9).
    Patch floor;
    floor.corner = {10.2, 0.02, 0.2};
    floor.u = {0.0, 0.0, 9.6};
    floor.v = {11.6, 0.0, 0.0};
    floor.na = floor.nb = 128;
    writeDemoProject(folder, "demo_level", "demo_floor", nullptr, view.source, floor,
                     "Sightline demo: the conservatory floor (128x128 samples) seen from the gallery's source patch");
    // The level lit by 300 light samples (demo/DemoLights.h) over its whole floor at 256x256:
    // `sightline-cli lights build/demo/demo_lights.json --compare` (docs/lights.md).
    json lights = json::array();
    for (const Light& light : demo::demoLights())
        lights.push_back(lightJson(light));
    writeDemoProject(folder, "demo_level", "demo_lights", nullptr, view.source, demo::demoFloor(256),
                     "Sightline demo lit: 10 ceiling panels, 100 lamps, 39 spots and the sun over the floor",
                     {{"lights", lights}});
    for (const demo::BenchScene& bench : {demo::makeFewOccludersScene(), demo::makeDenseMeshScene()})
        writeDemoProject(folder, bench.name, bench.name, &bench.scene, bench.source, bench.receiver,
                         "Sightline benchmark scene '" + bench.name + "' (levelgen/demo/DemoLevel.h)");
    // Seeds of every generated kind (1-3 by default): the CPU sampler's strategy choice is tuned on
    // those and checked on others (--seeds); `bench` takes any seed's project the same way.
    const fs::path benchFolder = fs::path(folder) / "bench";
    fs::create_directories(benchFolder, ec);
    if (ec)
        throw Error(benchFolder.string() + ": cannot create folder (" + ec.message() + ")");
    for (const demo::BenchKind kind : demo::kBenchKinds)
        for (int seed = firstSeed; seed <= lastSeed; ++seed) {
            const demo::BenchScene bench = demo::makeBenchScene(kind, std::uint64_t(seed));
            writeDemoProject(benchFolder, bench.name, bench.name, &bench.scene, bench.source, bench.receiver,
                             "Sightline benchmark scene '" + bench.name + "', layout '" + bench.layout +
                                 "' (levelgen/demo/BenchScenes.h)",
                             {{"bench", {{"kind", demo::benchKindName(kind)}, {"seed", seed}, {"layout", bench.layout}}}});
        }
    return 0;
}

} // namespace

CLI::App* addDemoCommand(CLI::App& app, DemoArgs& args)
{
    CLI::App* demoCmd = app.add_subcommand("demo", "Write the built-in demo level and project (demo_level.glb, demo.json), the benchmark scenes (few-occluders, dense-mesh) and seeds 1-3 of each generated bench kind (bench/KIND-SEED.glb + .json)");
    demoCmd->add_option("folder", args.folder, "Output folder (created if missing)")->required();
    demoCmd->add_option("--seeds", args.seeds, "Seeds of each generated bench kind, FIRST-LAST (1-3; at most 100 of them)");
    return demoCmd;
}

int runDemo(const DemoArgs& args)
{
    int first = 0, last = 0;
    char dash = 0, extra = 0;
    if (std::sscanf(args.seeds.c_str(), "%d%c%d%c", &first, &dash, &last, &extra) != 3 || dash != '-' || first < 0 ||
        last < first || last - first >= 100)
        throw Error("demo --seeds: expected FIRST-LAST with 0 <= FIRST <= LAST, at most 100 seeds, not '" + args.seeds + "'");
    return writeDemo(args.folder, first, last);
}

} // namespace sightline::cli
