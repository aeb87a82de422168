#include "cli/ShaftCommand.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <optional>
#include <thread>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/OptionRules.h"
#include "cli/OutputLimits.h"
#include "cli/OutputPaths.h"
#include "cli/Timing.h"
#include "project/CoarseOccluders.h"
#include "project/LightingSetup.h"
#include "project/Project.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"
#include "visibility/GlBitmaskSampler.h"
#include "visibility/HeckbertHerfSampler.h"
#include "visibility/HoughMaskTable.h"
#include "visibility/MaskNpy.h"
#include "visibility/RayCastSampler.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// Refuses options that `--method` (and `--mode`) would ignore (cli/OptionRules.h).
void checkShaftOptions(const CLI::App& command, const ShaftArgs& args)
{
    const std::string& method = args.method;
    requireMethod(command, "--strategy", method, {"cpu"});
    requireMethod(command, "--scalar", method, {"cpu"});
    requireMethod(command, "--single-rays", method, {"raycast"});
    requireMethod(command, "--threads", method, {"raycast", "cpu"});
    requireMethod(command, "--mode", method, {"cpu", "gl"});
    requireMethod(command, "--gl-backend", method, {"gl", "hh"});
    if (given(command, "--table") && args.mode != "table")
        throw Error("--table sets the Hough table's resolution and applies to --mode table only; add --mode table");
    // The table mode is the paper's method as published: every triangle by bitmask, in double.
    for (const char* option : {"--strategy", "--scalar"})
        if (given(command, option) && args.mode == "table")
            throw Error(std::string(option) + " applies to --mode exact only (table mode backprojects every triangle "
                                              "through the Hough table)");
}

/// What one sampler answered, and how.
struct ShaftRun {
    HiddenSampleMap map;
    std::optional<std::uint64_t> countedBlocked;   ///< hh: counts only, no map
    double ms = 0.0, setupMs = 0.0;
    std::string strategy;
    json split = json::object();   ///< method-specific time split and counts
};

/// The project and what it takes to sample it.
struct ShaftInput {
    const Project& project;
    const Scene& scene;
    const ReceiverHeights& heights;
    SourceJitter jitter;
};

ShaftRun sampleHeckbertHerf(const ShaftArgs& args, const ShaftInput& in)
{
    if (in.jitter.enabled())
        throw Error("--jitter: method hh (Heckbert-Herf) renders one source sample set for all receiver samples; "
                    "use gl, cpu or raycast");
    if (!args.mask.empty())
        throw Error("--mask: method hh (Heckbert-Herf) counts blocked rays per receiver sample but not which; "
                    "use gl, cpu or raycast for a mask");
    const auto context = gl::HeadlessContext::create(gl::parseBackend(args.glBackend));
    HeckbertHerfSampler sampler(context->functions(), worldTriangles(in.scene));
    HeckbertHerfStats stats;
    std::vector<std::uint32_t> counts;
    ShaftRun run;
    run.ms = timeSampling(args.repeat, [&] { counts = sampler.blockedCounts(in.project.source, in.project.receiver, &stats); });
    run.countedBlocked = std::accumulate(counts.begin(), counts.end(), std::uint64_t(0));
    run.setupMs = stats.setupMs;
    run.strategy = "heckbert-herf: one render per source sample (" + args.glBackend + ": " + context->renderer() + ")";
    run.split = {{"draw_ms", stats.drawMs}, {"readback_ms", stats.readbackMs}, {"triangles_drawn", stats.trianglesDrawn},
                 {"renders", in.project.source.sampleCount()}};
    return run;
}

ShaftRun sampleRayCast(const ShaftArgs& args, const ShaftInput& in)
{
    const RayCastScene rayCaster(in.scene);
    RayCastOptions options;
    options.packets = !args.singleRays;
    options.threads = args.threads;
    options.jitter = in.jitter;
    options.heights = in.heights.empty() ? nullptr : &in.heights;
    ShaftRun run;
    run.ms = timeSampling(args.repeat, [&] { run.map = rayCaster.sample(in.project.source, in.project.receiver, options); });
    run.setupMs = rayCaster.buildMilliseconds();
    run.strategy = options.packets ? "embree-packets-16" : "embree-single-rays";
    return run;
}

std::string tableName(const char* prefix, const std::vector<int>& table)
{
    return prefix + std::to_string(table[0]) + "x" + std::to_string(table[1]);
}

ShaftRun sampleGl(const ShaftArgs& args, const ShaftInput& in)
{
    const auto context = gl::HeadlessContext::create(gl::parseBackend(args.glBackend));
    GlBitmaskSampler sampler(context->functions(), in.scene);
    GlBitmaskStats stats;
    const GlBitmaskOptions options{.jitter = in.jitter,
                                   .mode = args.mode == "table" ? MaskMode::Table : MaskMode::Exact,
                                   .tableWidth = args.table[0],
                                   .tableHeight = args.table[1]};
    double tableMs = 0.0;   // the first call builds and uploads the table; later ones reuse it
    ShaftRun run;
    run.ms = timeSampling(args.repeat, [&] {
        run.map = sampler.sample(in.project.source, in.project.receiver, options, &stats);
        tableMs = std::max(tableMs, stats.tableMs);
    });
    run.setupMs = stats.setupMs;
    const std::string masks =
        options.mode == MaskMode::Table ? tableName("gl-bitmask-hough-table-", args.table) : std::string("gl-bitmask-exact-rows");
    run.strategy = masks + " (" + args.glBackend + ": " + context->renderer() + ")";
    run.split = {{"draw_ms", stats.drawMs}, {"readback_ms", stats.readbackMs}, {"table_ms", tableMs},
                 {"cpu_ms", stats.cpuMs}, {"gpu_occluders", stats.gpuOccluders}, {"cpu_occluders", stats.cpuOccluders},
                 {"flagged_samples", stats.flaggedSamples}};
    return run;
}

/// How the CPU sampler went about it, in words.
std::string cpuStrategy(const BitmaskStats& stats, const std::string& masks, bool forced)
{
    const std::string& used = stats.strategy;
    std::string strategy = used == "mixed"     ? "mixed: " + masks + " or embree float rays, per receiver tile"
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
    if (stats.debug.probed)
        strategy += " (chosen by timing both on a few tiles)";
    if (stats.debug.reusedTimedChoice)
        strategy += " (chosen by timing both on an earlier call)";
    else if (stats.debug.reusedChoice)
        strategy += " (chosen from the estimate on an earlier call)";
    return strategy;
}

ShaftRun sampleCpu(const ShaftArgs& args, const ShaftInput& in)
{
    const CpuBitmaskSampler sampler(in.scene);
    BitmaskStats stats;
    BitmaskOptions options;
    options.threads = args.threads;
    options.mode = args.mode == "table" ? MaskMode::Table : MaskMode::Exact;
    options.tableWidth = args.table[0];
    options.tableHeight = args.table[1];
    options.simd = !args.scalar;
    options.jitter = in.jitter;
    options.heights = in.heights.empty() ? nullptr : &in.heights;
    // --scalar asks for the double kernel's answer: without a strategy named, the bitmask.
    const std::string named = args.strategy == "auto" && args.scalar && !args.strategyGiven ? "bitmask" : args.strategy;
    options.strategy = named == "bitmask"   ? CpuStrategy::Bitmask
                       : named == "hybrid"  ? CpuStrategy::Hybrid
                       : named == "raycast" ? CpuStrategy::RayCast
                                            : CpuStrategy::Auto;
    ShaftRun run;
    run.ms = timeSampling(args.repeat, [&] { run.map = sampler.sample(in.project.source, in.project.receiver, options, &stats); });
    run.setupMs = stats.setupMs;
    const std::string masks =
        options.mode == MaskMode::Table ? tableName("bitmask-hough-table-", args.table) : std::string("bitmask-exact-rows");
    run.strategy = cpuStrategy(stats, masks, options.strategy != CpuStrategy::Auto);
    run.split = {{"bitmask_ms", stats.sampleMs}, {"ray_ms", stats.rayMs}, {"triangles_in_shaft", stats.trianglesInShaft},
                 {"small_triangles", stats.debug.smallTriangles}, {"pairs", stats.pairs}, {"float_pairs", stats.debug.floatPairs},
                 {"rays_cast", stats.raysCast}, {"proven_hits", stats.debug.provenHits}, {"exact_hit_tests", stats.debug.exactHitTests},
                 {"rays_confirmed", stats.debug.raysConfirmed}, {"ray_float_ms", stats.debug.rayFloatMs},
                 {"ray_confirm_ms", stats.debug.rayConfirmMs}, {"ray_packets", stats.debug.rayPackets},
                 {"float_fallbacks", stats.debug.floatFallbacks},
                 {"culled_front_faces", stats.debug.culledFrontFaces}, {"narrowed_away", stats.debug.narrowedAway},
                 {"proxy_faces", stats.debug.proxyFaces}, {"proxy_blocked", stats.proxyBlocked}, {"proxy_ms", stats.debug.proxyMs},
                 {"proxies_built", stats.debug.proxiesBuilt}, {"swapped_roles", stats.swappedRoles}, {"receiver_tiles", stats.receiverTiles},
                 {"estimated_pairs", stats.debug.estimatedPairs}, {"estimated_triangles", stats.debug.estimatedTriangles},
                 {"predicted_bitmask_ms", stats.debug.predictedBitmaskMs}, {"predicted_ray_ms", stats.debug.predictedRayMs},
                 {"probed", stats.debug.probed}, {"probe_ray_ms", stats.debug.probeRayMs}, {"probe_bitmask_ms", stats.debug.probeBitmaskMs},
                 {"reused_timed_choice", stats.debug.reusedTimedChoice}, {"reused_choice", stats.debug.reusedChoice}};
    return run;
}

/// The project, refused early where it cannot be the question asked: a table over budget, a
/// bumpy receiver for a sampler of flat ones.
void checkShaftProject(const ShaftArgs& args, const Project& project, const std::string& what)
{
    checkOutputs({{"--mask", args.mask}}, projectInputs(args.project, project));
    validatePatchPair(project.source, project.receiver);   // refuse before the expensive scene load
    if (args.mode == "table") {
        try {
            HoughMaskTable::checkBudget(project.source.sampleCount(), args.table[0], args.table[1]);
        } catch (const Error& e) {
            throw Error("--table " + std::to_string(args.table[0]) + " " + std::to_string(args.table[1]) + ": " + e.what());
        }
    }
    // Refused before the heights file is read: whatever it holds, these samplers would answer
    // for the flat receiver, which is not the project's question.
    if ((args.method == "gl" || args.method == "hh") && project.extra.contains("receiver_heights"))
        throw Error("--method " + args.method + ": " + what +
                    " has receiver_heights (a bumpy receiver), which only --method cpu or raycast sample");
}

void reportShaft(const ShaftArgs& args, const ShaftInput& in, const ShaftRun& run, double loadMs)
{
    const Project& project = in.project;
    const std::uint64_t rays = std::uint64_t(project.source.sampleCount()) * std::uint64_t(project.receiver.sampleCount());
    const std::uint64_t blocked = run.countedBlocked ? *run.countedBlocked : run.map.blockedCount();
    const double visible = rays ? double(rays - blocked) / double(rays) : 0.0;
    const int threads = args.threads > 0 ? args.threads : int(std::thread::hardware_concurrency());
    if (args.json) {
        json out = {
            {"method", args.method},
            {"strategy", run.strategy},
            {"rays", rays},
            {"blocked", blocked},
            {"unblocked", rays - blocked},
            {"visible_fraction", visible},
            {"ms", run.ms},
            {"setup_ms", run.setupMs},
            {"load_ms", loadMs},
            {"triangles", in.scene.triangleCount()},
            {"coarse_occluders", coarseOccluders(project).size()},
            {"source_samples", json::array({project.source.na, project.source.nb})},
            {"receiver_samples", json::array({project.receiver.na, project.receiver.nb})},
            {"threads", threads},
            {"repeat", std::max(args.repeat, 1)},   // timed runs
            {"warm_up", args.repeat > 0},
            {"jitter_seed", args.jitter},
            {"height_field", !in.heights.empty()},
        };
        if (!args.mask.empty())
            out["mask"] = args.mask;
        out.update(run.split);
        // Everything that can refuse happens before the mask is written: a failed run leaves
        // no side file behind.
        const std::string text = dumpJson(out);
        if (!args.mask.empty())
            writeMaskNpy(run.map, args.mask);
        std::cout << text << "\n";
        return;
    }
    if (!args.mask.empty())
        writeMaskNpy(run.map, args.mask);
    std::printf("method     %s (%s, %d threads)\n", args.method.c_str(), run.strategy.c_str(), threads);
    std::printf("scene      %zu triangles (setup %.1f ms)\n", in.scene.triangleCount(), run.setupMs);
    if (const std::size_t standIns = coarseOccluders(project).size())
        std::printf("coarse     %zu objects answered by their coarse stand-ins (the project's coarse_occluders)\n", standIns);
    std::printf("patches    %dx%d source x %dx%d receiver samples%s\n", project.source.na, project.source.nb,
                project.receiver.na, project.receiver.nb, in.heights.empty() ? "" : " (receiver height field)");
    std::printf("rays       %llu: %llu blocked, %llu unblocked (%.2f%% visible)\n", (unsigned long long)rays,
                (unsigned long long)blocked, (unsigned long long)(rays - blocked), 100.0 * visible);
    std::printf("time       %.2f ms\n", run.ms);
    if (!args.mask.empty())
        std::printf("mask       %s\n", args.mask.c_str());
}

} // namespace

CLI::App* addShaftCommand(CLI::App& app, ShaftArgs& shaft)
{
    CLI::App* shaftCmd = app.add_subcommand("shaft", "Compute the hidden-samples map between the project's patches");
    shaftCmd->add_option("project", shaft.project, "Project file (JSON, docs/design.md §3)")->required();
    shaftCmd->add_option("--method", shaft.method,
                         "Sampler: raycast (Embree reference), cpu (exact bitmask, CPU), gl (exact bitmask, OpenGL 4.5), "
                         "hh (Heckbert-Herf baseline, counts only: no --mask)")
        ->check(CLI::IsMember({"raycast", "cpu", "gl", "hh"}))
        ->capture_default_str();
    shaftCmd->add_option("--mask", shaft.mask, "Write the hidden-samples map as .npy (docs/design.md §4)")->check(outputFile());
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
    addAllowOutsidePaths(shaftCmd, shaft.allowOutsidePaths);
    return shaftCmd;
}

int runShaft(const CLI::App& command, ShaftArgs& args)
{
    checkShaftOptions(command, args);
    args.strategyGiven = given(command, "--strategy");
    const Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths});
    const std::string what = fs::path(args.project).filename().string();
    checkShaftProject(args, project, what);
    const ReceiverHeights heights = projectReceiverHeights(project, project.receiver, what);

    std::vector<std::string> warnings;
    const auto loadStart = std::chrono::steady_clock::now();
    const Scene scene = buildRayScene(project, &warnings);
    const double loadMs = millisecondsSince(loadStart);
    printWarnings(warnings);

    const ShaftInput in{project, scene, heights, SourceJitter{.seed = args.jitter}};
    const ShaftRun run = args.method == "hh"        ? sampleHeckbertHerf(args, in)
                         : args.method == "raycast" ? sampleRayCast(args, in)
                         : args.method == "gl"      ? sampleGl(args, in)
                                                    : sampleCpu(args, in);
    reportShaft(args, in, run, loadMs);
    return 0;
}

} // namespace sightline::cli
