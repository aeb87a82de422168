#include "cli/CoarseCommand.h"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "CoarseSweepChart.h"
#include "cli/OptionRules.h"
#include "cli/OutputLimits.h"
#include "cli/OutputPaths.h"
#include "project/CoarseOccluders.h"
#include "project/CoarseSweep.h"
#include "project/LightingSetup.h"
#include "project/Project.h"
#include "project/SceneImport.h"
#include "report/CoarseChart.h"
#include "base/Error.h"

namespace fs = std::filesystem;

namespace sightline::cli {

namespace {

using nlohmann::json;

/// "500,1000,2000" or "auto" (halving from half the largest mesh: defaultSweepCounts).
std::vector<std::size_t> sweepCounts(const std::string& text, const Scene& level)
{
    if (text == "auto") {
        std::size_t largest = 0;
        for (const Mesh& mesh : level.meshes)
            largest = std::max(largest, mesh.triangleCount());
        std::vector<std::size_t> counts = defaultSweepCounts(largest);
        if (counts.empty())
            throw Error("--sweep auto: no mesh has more than 8 triangles to simplify");
        return counts;
    }
    std::vector<std::size_t> counts;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        std::size_t used = 0;
        unsigned long long value = 0;
        try {
            value = std::stoull(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != item.size() || item.front() == '-' || value < 4 || value > 100'000'000)
            throw Error("--sweep: '" + item + "' is not a triangle count in [4, 100000000] (give e.g. 500,1000,2000 or auto)");
        counts.push_back(std::size_t(value));
    }
    if (counts.empty() || counts.size() > 32)
        throw Error("--sweep: give 1 to 32 triangle counts, e.g. 500,1000,2000, or auto");
    return counts;
}

/// The level's instances the single run gives a stand-in (those `runOnce` replaces), as the
/// project's "coarse_occluders".
std::vector<CoarseOccluder> standInsFor(const Scene& level, const CoarseOccluder& spec)
{
    std::vector<CoarseOccluder> list;
    for (std::size_t i = 0; i < level.instances.size(); ++i)
        if (standInApplies(level.meshes.at(level.instances[i].mesh), spec)) {
            list.push_back(spec);
            list.back().instance = i;
        }
    return list;
}

int runSweep(const CoarseArgs& args, const Project& project, const Scene& original, const ReceiverHeights& heights)
{
    if (args.kind != "closest")
        throw Error("--sweep measures the closest kind at several triangle counts; the inner kind has none (drop --kind inner)");
    CoarseSweepRequest request;
    request.counts = sweepCounts(args.sweep, original);
    request.threads = args.threads;
    request.repeat = args.repeat;
    const CoarseSweep sweep =
        sweepCoarseOccluders(original, project.source, project.receiver, heights.empty() ? nullptr : &heights, request);
    if (!args.chart.empty())
        writeCoarseChart(ui::coarseChartData(sweep),
                         QString::fromStdString("Coarse occluders on " + fs::path(args.project).filename().string() +
                                                ": rays answered differently and exact sampling time"),
                         args.chart);
    if (args.json) {
        json points = json::array();
        for (const CoarseSweepPoint& p : sweep.points)
            points.push_back({{"asked", p.asked},
                              {"triangles", p.triangles},
                              {"ms", p.ms},
                              {"false_blocked", p.falseBlocked},
                              {"false_free", p.falseFree},
                              {"disagreeing_fraction", double(p.disagreeing()) / double(sweep.rays)},
                              {"speedup", sweep.ms / std::max(p.ms, 1e-9)}});
        json out = {{"kind", "closest"}, {"triangles_before", sweep.triangles}, {"ms_original", sweep.ms},
                    {"rays", sweep.rays}, {"sweep", std::move(points)}};
        if (!args.chart.empty())
            out["chart"] = args.chart;
        std::cout << dumpJson(out) << "\n";
        return 0;
    }
    std::printf("original   %zu triangles, %.2f ms (exact CPU sampler, median of %d), %llu rays\n", sweep.triangles,
                sweep.ms, args.repeat, (unsigned long long)sweep.rays);
    std::printf("%10s %10s %10s %8s %12s %12s %10s\n", "asked", "triangles", "ms", "speedup", "false_blk", "false_free",
                "differ %");
    for (const CoarseSweepPoint& p : sweep.points)
        std::printf("%10zu %10zu %10.2f %7.2fx %12llu %12llu %10.4f\n", p.asked, p.triangles, p.ms,
                    sweep.ms / std::max(p.ms, 1e-9), (unsigned long long)p.falseBlocked, (unsigned long long)p.falseFree,
                    100.0 * double(p.disagreeing()) / double(sweep.rays));
    if (!args.chart.empty())
        std::printf("chart      %s\n", args.chart.c_str());
    return 0;
}

int runOnce(const CoarseArgs& args, const Project& project, const Scene& original, const ReceiverHeights& heights,
            const CoarseToleranceFit* fit = nullptr)
{
    CoarseOccluder spec;
    spec.kind = args.kind == "inner" ? CoarseKind::Inner : CoarseKind::Closest;
    spec.triangles = std::size_t(args.triangles);
    spec.resolution = args.resolution;
    Scene coarse = original;
    const auto [replaced, skipped] = replaceDenseMeshes(coarse, spec);
    if (replaced == 0)
        throw Error(args.kind == "inner" ? "no closed mesh of more than 12 triangles to stand an inner occluder in"
                                         : "no mesh has more than --triangles " + std::to_string(args.triangles) + " triangles");

    const CoarseComparison p = compareCoarseLevel(original, coarse, project.source, project.receiver,
                                                  heights.empty() ? nullptr : &heights, args.threads, args.repeat);
    const double originalMs = p.originalMs;
    const double fraction = double(p.disagreeing()) / double(p.rays);

    if (!args.write.empty()) {
        Scene level = loadLevel(project);
        applySceneTransforms(project, level);
        const std::vector<CoarseOccluder> standIns = standInsFor(level, spec);
        if (standIns.empty())
            throw Error("--write: no object of the level has a mesh to replace (only placed occluders do)");
        Project out = rebasedProject(project, fs::absolute(args.write).parent_path(), false);
        out.extra[kCoarseOccludersKey] = coarseOccludersJson(standIns);
        saveProject(out, args.write);
    }
    if (args.json) {
        json out = {{"kind", args.kind},
                    {"meshes_replaced", replaced},
                    {"meshes_skipped", skipped},
                    {"triangles_before", original.triangleCount()},
                    {"triangles_after", coarse.triangleCount()},
                    {"rays", p.rays},
                    {"false_blocked", p.falseBlocked},
                    {"false_free", p.falseFree},
                    {"disagreeing_fraction", fraction},
                    {"ms_original", originalMs},
                    {"ms_coarse", p.ms},
                    {"speedup", originalMs / std::max(p.ms, 1e-9)}};
        if (!args.write.empty())
            out["written"] = args.write;
        if (fit) {
            json tried = json::array();
            for (const CoarseSweepPoint& point : fit->tried.points)
                tried.push_back({{"asked", point.asked}, {"false_blocked", point.falseBlocked}, {"false_free", point.falseFree}});
            out["tolerance"] = args.tolerance;
            out["triangles"] = args.triangles;
            out["tried"] = std::move(tried);
        }
        std::cout << dumpJson(out) << "\n";
        return 0;
    }
    std::printf("coarse     %s: %zu meshes replaced%s, %zu -> %zu triangles\n", args.kind.c_str(), replaced,
                skipped ? " (open meshes left as they are)" : "", original.triangleCount(), coarse.triangleCount());
    std::printf("rays       %llu: %llu blocked only by the coarse level, %llu only by the original (%.4f%% differ)\n",
                (unsigned long long)p.rays, (unsigned long long)p.falseBlocked, (unsigned long long)p.falseFree,
                100.0 * fraction);
    std::printf("time       %.2f ms original, %.2f ms coarse: %.2fx (exact CPU sampler, median of %d)\n", originalMs, p.ms,
                originalMs / std::max(p.ms, 1e-9), args.repeat);
    if (!args.write.empty())
        std::printf("wrote      %s (the stand-ins in coarse_occluders)\n", args.write.c_str());
    return 0;
}

/// --tolerance: the fewest triangles within it (the bisection's steps listed), then as one run at
/// that count, timed and written like --triangles.
int runTolerance(const CoarseArgs& args, const Project& project, const Scene& original, const ReceiverHeights& heights)
{
    CoarseToleranceRequest request;
    request.tolerance = args.tolerance;
    request.threads = args.threads;
    const CoarseToleranceFit fit =
        fitCoarseToTolerance(original, project.source, project.receiver, heights.empty() ? nullptr : &heights, request);
    if (!fit.chosen) {
        const auto best = std::min_element(fit.tried.points.begin(), fit.tried.points.end(),
                                           [](const auto& a, const auto& b) { return a.disagreeing() < b.disagreeing(); });
        throw Error("--tolerance " + std::to_string(args.tolerance) + ": only the full meshes answer so few rays differently (the "
                    "closest tried, " + std::to_string(best->asked) + " triangles, differs on " +
                    std::to_string(best->disagreeing()) + " of " + std::to_string(fit.tried.rays) + " rays); loosen it");
    }
    if (!args.json) {
        std::printf("tolerance  %.4f%% of %llu rays: %zu counts tried\n", 100.0 * args.tolerance,
                    (unsigned long long)fit.tried.rays, fit.tried.points.size());
        for (const CoarseSweepPoint& p : fit.tried.points)
            std::printf("  %9zu triangles a mesh: %8.4f%% differ%s\n", p.asked, 100.0 * double(p.disagreeing()) / double(fit.tried.rays),
                        p.asked == fit.chosen->asked ? "  <- kept" : "");
    }
    CoarseArgs once = args;
    once.triangles = int(fit.chosen->asked);
    return runOnce(once, project, original, heights, &fit);
}

} // namespace

CLI::App* addCoarseCommand(CLI::App& app, CoarseArgs& args)
{
    CLI::App* command = app.add_subcommand(
        "coarse", "Replace the level's dense meshes by coarse occluders and measure, exactly, what that costs and saves: "
                  "triangles, sampling time, rays answered differently (docs/cli.md)");
    command->add_option("project", args.project, "Project file (JSON)")->required();
    command->add_option("--kind", args.kind,
                        "closest (OpenMesh's decimater, quadric error: fewest differences) or inner (faces strictly inside "
                        "each closed mesh: never blocks a ray the mesh lets through)")
        ->capture_default_str()
        ->check(CLI::IsMember({"closest", "inner"}));
    command->add_option("--triangles", args.triangles, "closest: meshes with more triangles are simplified to this many")
        ->capture_default_str()
        ->check(CLI::Range(4, 100000000));
    command->add_option("--resolution", args.resolution, "inner: voxels along each mesh's longest side")
        ->capture_default_str()
        ->check(CLI::Range(4, 256));
    command->add_option("--repeat", args.repeat, "Timed samplings of each level (their median)")->capture_default_str()->check(CLI::Range(1, 100));
    command->add_option("--threads", args.threads, "Sampling threads (0: all cores)")->check(CLI::Range(0, 1024));
    command->add_option("--sweep", args.sweep,
                        "Measure several triangle counts in one run (closest kind): e.g. 500,1000,2000, or auto (halving "
                        "from half the largest mesh)");
    command->add_option("--tolerance", args.tolerance,
                        "closest: the fewest triangles a mesh whose level answers at most this fraction of the pair's rays "
                        "differently (e.g. 0.001), found by bisection and checked by the exact sampler")
        ->check(CLI::Range(0.0, 1.0))
        ->excludes("--sweep")
        ->excludes("--triangles");
    command->add_option("--chart", args.chart, "With --sweep: a PNG chart of rays answered differently and sampling time "
                                               "against triangles")
        ->check(outputFile());
    command->add_option("--write", args.write,
                        "Save a copy of the project whose level objects keep these stand-ins (its coarse_occluders): the "
                        "rays between its patches are then answered by them")
        ->check(outputFile());
    command->add_flag("--json", args.json, "Print one JSON object instead of text");
    addAllowOutsidePaths(command, args.allowOutsidePaths);
    return command;
}

int runCoarse(const CoarseArgs& args)
{
    if (!args.chart.empty() && args.sweep.empty())
        throw Error("--chart draws a sweep: add --sweep COUNTS (e.g. --sweep auto)");
    if (!args.write.empty() && !args.sweep.empty())
        throw Error("--write keeps one stand-in per object: give --triangles N (or --kind inner) instead of --sweep");
    std::error_code ec;
    if (!args.write.empty() && fs::is_directory(args.write, ec))
        throw Error("--write " + args.write + " is a folder: name the project file to write");
    const Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths});
    checkOutputs({{"--write", args.write}, {"--chart", args.chart}}, projectInputs(args.project, project));
    const ReceiverHeights heights = validatedPairHeights(project);
    const Scene original = buildScene(project);   // the full meshes, whatever stand-ins the project keeps
    if (args.tolerance >= 0.0) {
        if (args.kind == "inner")
            throw Error("--tolerance picks the closest kind's triangle count; the inner kind has none (drop --kind inner)");
        return runTolerance(args, project, original, heights);
    }
    return args.sweep.empty() ? runOnce(args, project, original, heights) : runSweep(args, project, original, heights);
}

} // namespace sightline::cli
