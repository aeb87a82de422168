// sightline-cli: headless batch front end (docs/design.md §4, a contract).
//
//   sightline-cli shaft PROJECT.json [--method raycast|cpu|gl] [--mode exact|table] [--mask OUT.npy] [--json]
//   sightline-cli info SCENE_OR_PROJECT [--json]
//   sightline-cli demo OUTDIR
//   sightline-cli importance PROJECT.json --out MAP.png [--npy MAP.npy] [--frames N]   (cli/LightingCommands)
//   sightline-cli shadow PROJECT.json --out SHADOW.png
//   sightline-cli ao MESH_OR_PROJECT [--k 258] [--npy OUT.npy] [--json] ...             (cli/AoCommand, docs/ao.md)
//   sightline-cli lights PROJECT.json [--points P.npy] [--npy OUT.npy] [--json]   (cli/LightsCommand, docs/lights.md)
//   sightline-cli suggest PROJECT.json --depth T|--at X Y Z --normal N N N [--share F] [--shape convex|rect] [--write OUT.json] [--json]
//                                                                                 (cli/SuggestCommand)
//   sightline-cli gaps PROJECT.json [--json]                                      (cli/SuggestCommand)
//   sightline-cli coarse PROJECT.json [--kind closest|inner] [--triangles N] [--json] (cli/CoarseCommand)
//   sightline-cli pvs bake|merge|check|level ...   (cli/PvsCommands, docs/pvs.md)
//
// Success returns 0; any failure prints one line "sightline-cli: error: ..." on stderr and
// returns non-zero.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench/Bench.h"
#include "bench/BenchChart.h"
#include "cli/AoCommand.h"
#include "cli/CoarseCommand.h"
#include "cli/DisagreementCommand.h"
#include "cli/LightingCommands.h"
#include "cli/LightsCommand.h"
#include "cli/OptionRules.h"
#include "cli/OutputLimits.h"
#include "cli/OutputPaths.h"
#include "cli/PvsCommands.h"
#include "cli/SuggestCommand.h"
#include "demo/BenchScenes.h"
#include "demo/DemoLevel.h"
#include "demo/DemoLights.h"
#include "plugins/SceneFormats.h"
#include "project/CoarseOccluders.h"
#include "project/LightingSetup.h"
#include "project/Project.h"
#include "project/ProjectLights.h"
#include "visibility/AtomicFile.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/Error.h"
#include "visibility/GlBitmaskSampler.h"
#include "visibility/HeckbertHerfSampler.h"
#include "visibility/HoughMaskTable.h"
#include "visibility/gl/HeadlessContext.h"
#include "visibility/NpyWriter.h"
#include "visibility/RayCastSampler.h"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace sightline;

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void printWarnings(const std::vector<std::string>& warnings)
{
    for (const std::string& w : warnings)
        std::cerr << "sightline-cli: warning: " << w << "\n";
}

struct ShaftArgs {
    std::string project;
    std::string method = "raycast";
    std::string mask;
    bool json = false;
    int threads = 0;
    bool singleRays = false;
    bool scalar = false;
    std::uint32_t jitter = 0;
    int repeat = 0;   ///< 0: --repeat not given, one cold run
    std::string strategy = "auto";
    bool strategyGiven = false;   ///< --strategy on the command line (else --scalar implies bitmask)
    std::string glBackend = "osmesa";
    std::string mode = "exact";
    std::vector<int> table = {256, 128};
    bool allowOutsidePaths = false;
};

/// Without --repeat (`repeat` 0), runs `sample` once and returns its time in milliseconds: what
/// one call costs cold, as a script calling the CLI once sees it. With --repeat N, runs it once to
/// warm up (thread pools, page faults, shader compilation), then N timed times, and returns their
/// lower median, as `bench` does.
template <typename Sample>
double timeSampling(int repeat, Sample&& sample)
{
    if (repeat > 0)
        sample();
    std::vector<double> times;
    for (int k = 0; k < std::max(repeat, 1); ++k) {
        const auto start = std::chrono::steady_clock::now();
        sample();
        times.push_back(millisecondsSince(start));
    }
    std::sort(times.begin(), times.end());
    return times[(times.size() - 1) / 2];
}

/// Refuses options that `--method` (and `--mode`) would ignore (cli/OptionRules.h).
void checkShaftOptions(const CLI::App& command, const ShaftArgs& args)
{
    const std::string& method = args.method;
    cli::requireMethod(command, "--strategy", method, {"cpu"});
    cli::requireMethod(command, "--scalar", method, {"cpu"});
    cli::requireMethod(command, "--single-rays", method, {"raycast"});
    cli::requireMethod(command, "--threads", method, {"raycast", "cpu"});
    cli::requireMethod(command, "--mode", method, {"cpu", "gl"});
    cli::requireMethod(command, "--gl-backend", method, {"gl", "hh"});
    if (cli::given(command, "--table") && args.mode != "table")
        throw Error("--table sets the Hough table's resolution and applies to --mode table only; add --mode table");
    // The table mode is the paper's method as published: every triangle by bitmask, in double.
    for (const char* option : {"--strategy", "--scalar"})
        if (cli::given(command, option) && args.mode == "table")
            throw Error(std::string(option) + " applies to --mode exact only (table mode backprojects every triangle "
                                              "through the Hough table)");
}

int runShaft(const ShaftArgs& args)
{
    const Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths});
    cli::checkOutputs({{"--mask", args.mask}}, cli::projectInputs(args.project, project));
    validatePatchPair(project.source, project.receiver);   // refuse before the expensive scene load
    if (args.mode == "table") {
        try {
            HoughMaskTable::checkBudget(project.source.sampleCount(), args.table[0], args.table[1]);
        } catch (const Error& e) {
            throw Error("--table " + std::to_string(args.table[0]) + " " + std::to_string(args.table[1]) + ": " + e.what());
        }
    }
    const std::string what = fs::path(args.project).filename().string();
    // Refused before the heights file is read: whatever it holds, these samplers would answer
    // for the flat receiver, which is not the project's question.
    if ((args.method == "gl" || args.method == "hh") && project.extra.contains("receiver_heights"))
        throw Error("--method " + args.method + ": " + what +
                    " has receiver_heights (a bumpy receiver), which only --method cpu or raycast sample");
    const ReceiverHeights heights = projectReceiverHeights(project, project.receiver, what);

    std::vector<std::string> warnings;
    const auto loadStart = std::chrono::steady_clock::now();
    const Scene scene = buildRayScene(project, &warnings);
    const double loadMs = millisecondsSince(loadStart);
    printWarnings(warnings);

    HiddenSampleMap map;
    std::optional<std::uint64_t> countedBlocked;   // hh: counts only, no map
    double ms = 0.0, setupMs = 0.0;
    std::string strategy;
    json split = json::object();   // method-specific time split and counts
    const SourceJitter jitter{.seed = args.jitter};
    if (args.method == "hh") {
        if (jitter.enabled())
            throw Error("--jitter: method hh (Heckbert-Herf) renders one source sample set for all receiver samples; "
                        "use gl, cpu or raycast");
        if (!args.mask.empty())
            throw Error("--mask: method hh (Heckbert-Herf) counts blocked rays per receiver sample but not which; "
                        "use gl, cpu or raycast for a mask");
        const auto context = gl::HeadlessContext::create(gl::parseBackend(args.glBackend));
        HeckbertHerfSampler sampler(context->functions(), worldTriangles(scene));
        HeckbertHerfStats stats;
        std::vector<std::uint32_t> counts;
        ms = timeSampling(args.repeat, [&] { counts = sampler.blockedCounts(project.source, project.receiver, &stats); });
        countedBlocked = std::accumulate(counts.begin(), counts.end(), std::uint64_t(0));
        setupMs = stats.setupMs;
        strategy = "heckbert-herf: one render per source sample (" + args.glBackend + ": " + context->renderer() + ")";
        split = {{"draw_ms", stats.drawMs}, {"readback_ms", stats.readbackMs}, {"triangles_drawn", stats.trianglesDrawn},
                 {"renders", project.source.sampleCount()}};
    } else if (args.method == "raycast") {
        const RayCastScene rayCaster(scene);
        RayCastOptions options;
        options.packets = !args.singleRays;
        options.threads = args.threads;
        options.jitter = jitter;
        options.heights = heights.empty() ? nullptr : &heights;
        ms = timeSampling(args.repeat, [&] { map = rayCaster.sample(project.source, project.receiver, options); });
        setupMs = rayCaster.buildMilliseconds();
        strategy = options.packets ? "embree-packets-16" : "embree-single-rays";
    } else if (args.method == "gl") {
        const auto context = gl::HeadlessContext::create(gl::parseBackend(args.glBackend));
        GlBitmaskSampler sampler(context->functions(), scene);
        GlBitmaskStats stats;
        const GlBitmaskOptions options{.jitter = jitter,
                                       .mode = args.mode == "table" ? MaskMode::Table : MaskMode::Exact,
                                       .tableWidth = args.table[0],
                                       .tableHeight = args.table[1]};
        double tableMs = 0.0;   // the first call builds and uploads the table; later ones reuse it
        ms = timeSampling(args.repeat, [&] {
            map = sampler.sample(project.source, project.receiver, options, &stats);
            tableMs = std::max(tableMs, stats.tableMs);
        });
        setupMs = stats.setupMs;
        const std::string masks = options.mode == MaskMode::Table ? "gl-bitmask-hough-table-" + std::to_string(args.table[0]) +
                                                                        "x" + std::to_string(args.table[1])
                                                                  : std::string("gl-bitmask-exact-rows");
        strategy = masks + " (" + args.glBackend + ": " + context->renderer() + ")";
        split = {{"draw_ms", stats.drawMs}, {"readback_ms", stats.readbackMs}, {"table_ms", tableMs},
                 {"cpu_ms", stats.cpuMs}, {"gpu_occluders", stats.gpuOccluders}, {"cpu_occluders", stats.cpuOccluders},
                 {"flagged_samples", stats.flaggedSamples}};
    } else {
        const CpuBitmaskSampler sampler(scene);
        BitmaskStats stats;
        BitmaskOptions options;
        options.threads = args.threads;
        options.mode = args.mode == "table" ? MaskMode::Table : MaskMode::Exact;
        options.tableWidth = args.table[0];
        options.tableHeight = args.table[1];
        options.simd = !args.scalar;
        options.jitter = jitter;
        options.heights = heights.empty() ? nullptr : &heights;
        // --scalar asks for the double kernel's answer: without a strategy named, the bitmask.
        const std::string named = args.strategy == "auto" && args.scalar && !args.strategyGiven ? "bitmask" : args.strategy;
        options.strategy = named == "bitmask"   ? CpuStrategy::Bitmask
                           : named == "hybrid"  ? CpuStrategy::Hybrid
                           : named == "raycast" ? CpuStrategy::RayCast
                                                : CpuStrategy::Auto;
        ms = timeSampling(args.repeat, [&] { map = sampler.sample(project.source, project.receiver, options, &stats); });
        setupMs = stats.setupMs;
        const std::string masks = options.mode == MaskMode::Table
                                      ? "bitmask-hough-table-" + std::to_string(args.table[0]) + "x" + std::to_string(args.table[1])
                                      : std::string("bitmask-exact-rows");
        const std::string used = stats.strategy;
        const bool forced = options.strategy != CpuStrategy::Auto;
        strategy = used == "mixed"     ? "mixed: " + masks + " or embree float rays, per receiver tile"
                   : used == "hybrid"  ? "hybrid: " + masks + " + embree-packets-16"
                   : used == "raycast" ? std::string("raycast: embree float rays, hits proven, free rays confirmed") +
                                             (forced ? " (forced by --strategy)" : " (cheaper than the bitmask here)")
                                       : masks;
        if (stats.proxyBlocked > 0)
            strategy += " (inner proxies of meshes answered " + std::to_string(stats.proxyBlocked) + " rays first)";
        if (stats.receiverTiles > 1)
            strategy += " (receiver in " + std::to_string(stats.receiverTiles) + " tiles)";
        if (stats.swappedRoles)
            strategy += " (patches' roles swapped: backprojected onto the receiver's finer grid)";
        if (stats.probed)
            strategy += " (chosen by timing both on a few tiles)";
        if (stats.reusedTimedChoice)
            strategy += " (chosen by timing both on an earlier call)";
        else if (stats.reusedChoice)
            strategy += " (chosen from the estimate on an earlier call)";
        split = {{"bitmask_ms", stats.sampleMs}, {"ray_ms", stats.rayMs}, {"triangles_in_shaft", stats.trianglesInShaft},
                 {"small_triangles", stats.smallTriangles}, {"pairs", stats.pairs}, {"float_pairs", stats.floatPairs},
                 {"rays_cast", stats.raysCast}, {"proven_hits", stats.provenHits}, {"exact_hit_tests", stats.exactHitTests},
                 {"rays_confirmed", stats.raysConfirmed}, {"ray_float_ms", stats.rayFloatMs},
                 {"ray_confirm_ms", stats.rayConfirmMs}, {"ray_packets", stats.rayPackets},
                 {"float_fallbacks", stats.floatFallbacks},
                 {"culled_front_faces", stats.culledFrontFaces}, {"narrowed_away", stats.narrowedAway},
                 {"proxy_faces", stats.proxyFaces}, {"proxy_blocked", stats.proxyBlocked}, {"proxy_ms", stats.proxyMs},
                 {"proxies_built", stats.proxiesBuilt}, {"swapped_roles", stats.swappedRoles}, {"receiver_tiles", stats.receiverTiles},
                 {"estimated_pairs", stats.estimatedPairs}, {"estimated_triangles", stats.estimatedTriangles}, {"predicted_bitmask_ms", stats.predictedBitmaskMs}, {"predicted_ray_ms", stats.predictedRayMs}, {"probed", stats.probed}, {"probe_ray_ms", stats.probeRayMs}, {"probe_bitmask_ms", stats.probeBitmaskMs},
                 {"reused_timed_choice", stats.reusedTimedChoice}, {"reused_choice", stats.reusedChoice}};
    }

    const std::uint64_t rays = std::uint64_t(project.source.sampleCount()) * std::uint64_t(project.receiver.sampleCount());
    const std::uint64_t blocked = countedBlocked ? *countedBlocked : map.blockedCount();
    const double visible = rays ? double(rays - blocked) / double(rays) : 0.0;
    const int threads = args.threads > 0 ? args.threads : int(std::thread::hardware_concurrency());
    if (args.json) {
        json out = {
            {"method", args.method},
            {"strategy", strategy},
            {"rays", rays},
            {"blocked", blocked},
            {"unblocked", rays - blocked},
            {"visible_fraction", visible},
            {"ms", ms},
            {"setup_ms", setupMs},
            {"load_ms", loadMs},
            {"triangles", scene.triangleCount()},
            {"coarse_occluders", coarseOccluders(project).size()},
            {"source_samples", json::array({project.source.na, project.source.nb})},
            {"receiver_samples", json::array({project.receiver.na, project.receiver.nb})},
            {"threads", threads},
            {"repeat", std::max(args.repeat, 1)},   // timed runs
            {"warm_up", args.repeat > 0},
            {"jitter_seed", args.jitter},
            {"height_field", !heights.empty()},
        };
        if (!args.mask.empty())
            out["mask"] = args.mask;
        out.update(split);
        // Everything that can refuse happens before the mask is written: a failed run leaves
        // no side file behind.
        const std::string text = cli::dumpJson(out);
        if (!args.mask.empty())
            writeMaskNpy(map, args.mask);
        std::cout << text << "\n";
    } else {
        if (!args.mask.empty())
            writeMaskNpy(map, args.mask);
        std::printf("method     %s (%s, %d threads)\n", args.method.c_str(), strategy.c_str(), threads);
        std::printf("scene      %zu triangles (setup %.1f ms)\n", scene.triangleCount(), setupMs);
        if (const std::size_t standIns = coarseOccluders(project).size())
            std::printf("coarse     %zu objects answered by their coarse stand-ins (the project's coarse_occluders)\n", standIns);
        std::printf("patches    %dx%d source x %dx%d receiver samples%s\n", project.source.na, project.source.nb,
                    project.receiver.na, project.receiver.nb, heights.empty() ? "" : " (receiver height field)");
        std::printf("rays       %llu: %llu blocked, %llu unblocked (%.2f%% visible)\n", (unsigned long long)rays,
                    (unsigned long long)blocked, (unsigned long long)(rays - blocked), 100.0 * visible);
        std::printf("time       %.2f ms\n", ms);
        if (!args.mask.empty())
            std::printf("mask       %s\n", args.mask.c_str());
    }
    return 0;
}

struct BenchArgs {
    bench::Settings settings;
    std::string methods = "raycast,cpu,cpu-bitmask,cpu-table-256x128";
    std::string csv, chart;
    std::string glBackend = "osmesa";
    bool glBackendGiven = false;
    bool shadow = false;
};

int runBench(BenchArgs& args)
{
    args.settings.methods = bench::parseMethods(args.methods);
    const bool anyGl = std::any_of(args.settings.methods.begin(), args.settings.methods.end(), [](const std::string& m) {
        return m == "gl" || m == "hh" || m.starts_with("gl-");
    });
    if (args.glBackendGiven && !anyGl)
        throw Error("--gl-backend applies to the GL methods (gl, gl-table-WxH, gl-jitter, hh), and --methods names none");
    args.settings.glBackend = gl::parseBackend(args.glBackend);
    if (args.shadow && args.settings.denseSide == 0)
        args.settings.denseSide = 128;
    if (args.settings.denseSide % 32 != 0)
        throw Error("--dense must be a multiple of 32, got " + std::to_string(args.settings.denseSide));
    // Before the runs, which may take minutes: the CSV or chart must not replace what is benchmarked.
    std::vector<cli::FileRole> inputs;
    for (const std::string& file : args.settings.projects) {
        std::vector<cli::FileRole> read{{"the project", file}};
        try {
            read = cli::projectInputs(file, loadProject(file, {.allowOutsidePaths = args.settings.allowOutsidePaths}));
        } catch (const std::exception&) {
            // An unreadable project is refused by the run itself, with its own message.
        }
        inputs.insert(inputs.end(), read.begin(), read.end());
    }
    cli::checkOutputs({{"--csv", args.csv}, {"--chart", args.chart}}, inputs);
    std::printf("%-28s %-18s %7s %9s %10s %10s %12s %12s %8s %10s %10s %10s  %s\n", "project", "method", "sources", "receiver",
                "ms", "thread-ms", "wrong-block", "wrong-free", "ties", "error", "light-mae", "dense-mae", "variant");
    std::uint64_t referenceErrors = 0;
    const auto rows = bench::run(args.settings, [&](const bench::Row& r) {
        const std::string name = fs::path(r.project).filename().string();
        const std::string ties = r.judged ? std::to_string(r.ties) : "-";
        std::printf("%-28s %-18s %7d %5dx%-4d %10.2f %10.2f %12llu %12llu %8s %10.6f %10.6f ", name.c_str(),
                    r.method.c_str(), r.sourceSamples, r.receiverSide, r.receiverSide, r.ms, r.threadMs,
                    (unsigned long long)r.wronglyBlocked, (unsigned long long)r.wronglyFree, ties.c_str(), r.errorFraction(),
                    r.lightMae);
        if (r.denseMae >= 0.0)
            std::printf("%10.6f", r.denseMae);
        else
            std::printf("%10s", "-");
        std::printf("  %s\n", r.variant.c_str());
        std::fflush(stdout);
        referenceErrors += r.referenceErrors;
    });
    if (referenceErrors > 0)
        std::fprintf(stderr, "warning: the raycast reference disagreed with the exact judge on %llu rays (a bug: please report it)\n",
                     (unsigned long long)referenceErrors);
    if (!args.csv.empty()) {
        writeFileAtomically(args.csv, bench::toCsv(rows));
        std::printf("wrote %s\n", args.csv.c_str());
    }
    if (!args.chart.empty()) {
        bench::writeChart(rows, args.chart, args.shadow ? bench::ChartKind::ShadowError : bench::ChartKind::RayErrors);
        std::printf("wrote %s\n", args.chart.c_str());
    }
    return 0;
}

int runInfo(const std::string& path, bool asJson, bool allowOutsidePaths)
{
    std::vector<std::string> warnings;
    Scene scene;
    const bool isProject = fs::path(path).extension() == ".json";
    if (isProject)
        scene = buildScene(loadProject(path, {.allowOutsidePaths = allowOutsidePaths}), &warnings);
    else
        scene = loadScene(path, &warnings);
    printWarnings(warnings);
    const Bounds box = scene.bounds();
    std::size_t vertices = 0;
    for (const Mesh& mesh : scene.meshes)
        vertices += mesh.positions.size();

    if (asJson) {
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
        std::cout << cli::dumpJson(out) << "\n";
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

int runDemo(const std::string& folder, int firstSeed, int lastSeed)
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
                         "Sightline benchmark scene '" + bench.name + "' (data/demo/DemoLevel.h)");
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
                                 "' (data/demo/BenchScenes.h)",
                             {{"bench", {{"kind", demo::benchKindName(kind)}, {"seed", seed}, {"layout", bench.layout}}}});
        }
    return 0;
}

} // namespace

int main(int argc, char** argv)
{
    CLI::App app{"Sightline: which rays between two patches are blocked, for level designers.\n"
                 "See docs/cli.md (README.md links every page); file formats and conventions: docs/design.md."};
    app.name("sightline-cli");
    app.set_version_flag("--version", "sightline-cli 0.1.0");
    app.require_subcommand(1);

    ShaftArgs shaft;
    CLI::App* shaftCmd = app.add_subcommand("shaft", "Compute the hidden-samples map between the project's patches");
    shaftCmd->add_option("project", shaft.project, "Project file (JSON, docs/design.md §3)")->required();
    shaftCmd->add_option("--method", shaft.method,
                         "Sampler: raycast (Embree reference), cpu (exact bitmask, CPU), gl (exact bitmask, OpenGL 4.5), "
                         "hh (Heckbert-Herf baseline, counts only: no --mask)")
        ->check(CLI::IsMember({"raycast", "cpu", "gl", "hh"}))
        ->capture_default_str();
    shaftCmd->add_option("--mask", shaft.mask, "Write the hidden-samples map as .npy (docs/design.md §4)")->check(cli::outputFile());
    shaftCmd->add_flag("--json", shaft.json, "Print one JSON object instead of text");
    shaftCmd->add_option("--threads", shaft.threads, "raycast, cpu: worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
    shaftCmd->add_flag("--single-rays", shaft.singleRays, "raycast: cast single rays instead of packets of 16");
    shaftCmd->add_option("--jitter", shaft.jitter,
                         "Decorrelated sampling (paper §6.2): shift each receiver sample's source grid by a hashed "
                         "offset under half a cell; SEED > 0, same offsets in every method (not hh)")
        ->check(CLI::Range(0u, 0xffffffffu));
    shaftCmd->add_flag("--scalar", shaft.scalar,
                       "cpu, exact mode: the bitmask in double precision everywhere, no SIMD kernel (with it, "
                       "--strategy defaults to bitmask: the answer is the double kernel's)");
    shaftCmd->add_option("--strategy", shaft.strategy,
                         "cpu, exact mode: auto, bitmask (every triangle backprojected), hybrid (small triangles ray "
                         "cast) or raycast (all rays)")
        ->check(CLI::IsMember({"auto", "bitmask", "hybrid", "raycast"}))
        ->capture_default_str();
    shaftCmd->add_option("--mode", shaft.mode, "cpu, gl: exact (per-row masks) or table (the paper's Hough table, §5)")
        ->check(CLI::IsMember({"exact", "table"}))
        ->capture_default_str();
    shaftCmd->add_option("--table", shaft.table, "--mode table: Hough table resolution, angles and distances")
        ->expected(2)
        ->check(CLI::Range(4, 8192))
        ->capture_default_str();
    shaftCmd->add_option("--gl-backend", shaft.glBackend, "gl, hh: headless context, osmesa (software) or egl (GPU)")
        ->check(CLI::IsMember({"osmesa", "egl"}))
        ->capture_default_str();
    shaftCmd->add_option("--repeat", shaft.repeat,
                         "Run once to warm up, then time N runs and report their median ms (without --repeat: "
                         "one cold run, no warm-up)")
        ->check(CLI::Range(1, 1000));
    cli::addAllowOutsidePaths(shaftCmd, shaft.allowOutsidePaths);

    std::string infoPath;
    bool infoJson = false;
    bool infoAllowOutside = false;
    CLI::App* infoCmd = app.add_subcommand("info", "Print counts, bounds and instances of a scene or project");
    infoCmd->add_option("file", infoPath, "Scene file (glTF, GLB, OBJ, PLY, OFF, STL) or project (.json)")->required();
    infoCmd->add_flag("--json", infoJson, "Print one JSON object instead of text");
    cli::addAllowOutsidePaths(infoCmd, infoAllowOutside);

    BenchArgs benchArgs;
    CLI::App* benchCmd = app.add_subcommand("bench", "Time every method against the raycast reference; CSV and chart");
    benchCmd->add_option("projects", benchArgs.settings.projects, "Project files")->required();
    benchCmd->add_option("--methods", benchArgs.methods,
                         "Comma-separated: embree-tuned (the baseline: a float Embree tracer, the fastest of its four "
                         "traversals), raycast, cpu, cpu-bitmask, cpu-hybrid, cpu-raycast, cpu-scalar (cpu without SIMD), "
                         "cpu-table-WxH, gl, gl-table-WxH (gl with the Hough table), hh (Heckbert-Herf, counts only), "
                         "raycast-jitter, cpu-jitter, gl-jitter (decorrelated sampling, §6.2)")
        ->capture_default_str();
    benchCmd->add_option("--sources", benchArgs.settings.sourceCounts, "Source sample counts (1..1024)")
        ->delimiter(',')
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    benchCmd->add_option("--receivers", benchArgs.settings.receiverSides, "Receiver grid sides (NxN)")
        ->delimiter(',')
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    benchCmd->add_option("--repeat", benchArgs.settings.repeat, "Rounds: each method runs once untimed, then timed (--min-time); methods interleaved (median reported)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    benchCmd->add_option("--min-time", benchArgs.settings.minBatchMs,
                         "In each round, a method's timed runs go on until they took MS milliseconds (at most 100 runs)")
        ->check(CLI::Range(0.0, 600000.0))
        ->capture_default_str();
    benchCmd->add_option("--threads", benchArgs.settings.threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
    benchCmd->add_option("--gl-backend", benchArgs.glBackend, "gl, gl-table-WxH, hh: headless context, osmesa (software) or egl (GPU)")
        ->check(CLI::IsMember({"osmesa", "egl"}))
        ->capture_default_str();
    benchCmd->add_flag("--shadow", benchArgs.shadow,
                       "Soft shadows (paper §8): also compare each method's light fraction with a dense reference "
                       "(--dense), and chart time against that error");
    benchCmd->add_option("--dense", benchArgs.settings.denseSide,
                         "Dense reference: N x N regular source samples (multiple of 32; --shadow default 128)")
        ->check(CLI::Range(0, 1024));
    benchCmd->add_option("--csv", benchArgs.csv, "Write all rows as CSV")->check(cli::outputFile());
    benchCmd->add_option("--chart", benchArgs.chart, "Write a PNG chart of time against error")->check(cli::outputFile());
    cli::addAllowOutsidePaths(benchCmd, benchArgs.settings.allowOutsidePaths);

    cli::ImportanceArgs importance;
    CLI::App* importanceCmd = cli::addImportanceCommand(app, importance);
    cli::ShadowArgs shadow;
    CLI::App* shadowCmd = cli::addShadowCommand(app, shadow);
    cli::AoArgs ao;
    CLI::App* aoCmd = cli::addAoCommand(app, ao);
    cli::LightsArgs lights;
    CLI::App* lightsCmd = cli::addLightsCommand(app, lights);

    cli::SuggestArgs suggestArgs;
    CLI::App* suggestCmd = cli::addSuggestCommand(app, suggestArgs);
    cli::GapsArgs gapsArgs;
    cli::CoarseArgs coarseArgs;
    CLI::App* coarseCmd = cli::addCoarseCommand(app, coarseArgs);
    CLI::App* gapsCmd = cli::addGapsCommand(app, gapsArgs);
    cli::DisagreementArgs disagreementArgs;
    CLI::App* disagreementCmd = cli::addDisagreementCommand(app, disagreementArgs);

    cli::PvsArgs pvsArgs;
    CLI::App* pvsCmd = cli::addPvsCommand(app, pvsArgs);

    std::string demoFolder;
    CLI::App* demoCmd = app.add_subcommand("demo", "Write the built-in demo level and project (demo_level.glb, demo.json), the benchmark scenes (few-occluders, dense-mesh) and seeds 1-3 of each generated bench kind (bench/KIND-SEED.glb + .json)");
    demoCmd->add_option("folder", demoFolder, "Output folder (created if missing)")->required();
    std::string demoSeeds = "1-3";
    demoCmd->add_option("--seeds", demoSeeds, "Seeds of each generated bench kind, FIRST-LAST (1-3; at most 100 of them)");

    // CLI11 answers a misspelt subcommand ("sightline-cli shaf p.json") with "A subcommand is
    // required", as if none were given: name it and the ones there are.
    if (argc > 1 && argv[1][0] != '-') {
        std::string names;
        bool known = false;
        for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
            known = known || sub->get_name() == argv[1];
            names += (names.empty() ? "" : ", ") + sub->get_name();
        }
        if (!known) {
            std::cerr << "sightline-cli: error: unknown subcommand '" << argv[1] << "' (" << names << "; see --help)\n";
            return 2;
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "sightline-cli: error: " << e.what() << " (see --help)\n";
        return 2;
    }

    try {
        if (*shaftCmd) {
            checkShaftOptions(*shaftCmd, shaft);
            shaft.strategyGiven = cli::given(*shaftCmd, "--strategy");
            return runShaft(shaft);
        }
        if (*infoCmd)
            return runInfo(infoPath, infoJson, infoAllowOutside);
        if (*demoCmd) {
            int first = 0, last = 0;
            char dash = 0, extra = 0;
            if (std::sscanf(demoSeeds.c_str(), "%d%c%d%c", &first, &dash, &last, &extra) != 3 || dash != '-' || first < 0 ||
                last < first || last - first >= 100)
                throw Error("demo --seeds: expected FIRST-LAST with 0 <= FIRST <= LAST, at most 100 seeds, not '" +
                            demoSeeds + "'");
            return runDemo(demoFolder, first, last);
        }
        if (*benchCmd) {
            benchArgs.glBackendGiven = cli::given(*benchCmd, "--gl-backend");
            return runBench(benchArgs);
        }
        if (*importanceCmd) {
            cli::checkImportanceOptions(*importanceCmd, importance);
            return cli::runImportance(importance);
        }
        if (*shadowCmd) {
            cli::checkShadowOptions(*shadowCmd, shadow);
            return cli::runShadow(shadow);
        }
        if (*aoCmd) {
            cli::checkAoOptions(*aoCmd, ao);
            return cli::runAo(ao);
        }
        if (*lightsCmd) {
            cli::checkLightsOptions(*lightsCmd, lights);
            return cli::runLights(lights);
        }
        if (*suggestCmd)
            return cli::runSuggest(suggestArgs);
        if (*gapsCmd)
            return cli::runGaps(gapsArgs);
        if (*coarseCmd)
            return cli::runCoarse(coarseArgs);
        if (*disagreementCmd)
            return cli::runDisagreement(disagreementArgs);
        if (*pvsCmd)
            return cli::runPvs(pvsArgs, argc, argv);
    } catch (const std::exception& e) {
        const CLI::App* command = app.get_subcommands().front();
        std::cerr << "sightline-cli: error: " << describeFailure(e, "running '" + command->get_name() + "'") << "\n";
        return 1;
    }
    return 1;
}
