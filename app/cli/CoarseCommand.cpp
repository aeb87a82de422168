#include "cli/CoarseCommand.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/OptionRules.h"
#include "cli/OutputLimits.h"
#include "plugins/MeshSimplification.h"
#include "project/LightingSetup.h"
#include "project/Project.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/Error.h"
#include "visibility/InnerOccluder.h"

namespace sightline::cli {

namespace {

/// The lower median of `repeat` exact samplings after one untimed (as `bench` times).
double medianSampleMs(const CpuBitmaskSampler& sampler, const Project& project, const ReceiverHeights& heights, int repeat,
                      int threads, HiddenSampleMap& map)
{
    BitmaskOptions options;
    options.threads = threads;
    options.heights = heights.empty() ? nullptr : &heights;
    map = sampler.sample(project.source, project.receiver, options);
    std::vector<double> times;
    for (int k = 0; k < std::max(repeat, 1); ++k) {
        const auto start = std::chrono::steady_clock::now();
        map = sampler.sample(project.source, project.receiver, options);
        times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(times.begin(), times.end());
    return times[(times.size() - 1) / 2];
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
    command->add_flag("--json", args.json, "Print one JSON object instead of text");
    addAllowOutsidePaths(command, args.allowOutsidePaths);
    return command;
}

int runCoarse(const CoarseArgs& args)
{
    const Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths});
    const ReceiverHeights heights = validatedPairHeights(project);
    const Scene original = buildScene(project);
    Scene coarse = original;
    std::size_t replaced = 0, skipped = 0;
    for (Mesh& mesh : coarse.meshes) {
        if (args.kind == "inner") {
            if (mesh.triangleCount() <= 12 || !closedAndOutward(mesh)) {
                skipped += mesh.triangleCount() > 12;
                continue;
            }
            mesh = innerOccluderMesh(mesh, args.resolution);
        } else {
            if (mesh.triangleCount() <= std::size_t(args.triangles))
                continue;
            mesh = simplifiedMesh(mesh, std::size_t(args.triangles));
        }
        ++replaced;
    }
    if (replaced == 0)
        throw Error(args.kind == "inner" ? "no closed mesh of more than 12 triangles to stand an inner occluder in"
                                         : "no mesh has more than --triangles " + std::to_string(args.triangles) + " triangles");

    HiddenSampleMap exact, approximate;
    const CpuBitmaskSampler originalSampler(original), coarseSampler(coarse);
    const double originalMs = medianSampleMs(originalSampler, project, heights, args.repeat, args.threads, exact);
    const double coarseMs = medianSampleMs(coarseSampler, project, heights, args.repeat, args.threads, approximate);
    std::uint64_t falseBlocked = 0, falseFree = 0;
    for (int j = 0; j < exact.receiverCount(); ++j) {
        const auto a = exact.row(j), b = approximate.row(j);
        for (int w = 0; w < exact.wordsPerRow(); ++w) {
            falseBlocked += std::uint64_t(std::popcount(b[std::size_t(w)] & ~a[std::size_t(w)]));
            falseFree += std::uint64_t(std::popcount(a[std::size_t(w)] & ~b[std::size_t(w)]));
        }
    }
    const double fraction = double(falseBlocked + falseFree) / double(exact.rayCount());
    if (args.json) {
        std::cout << dumpJson({{"kind", args.kind},
                               {"meshes_replaced", replaced},
                               {"meshes_skipped", skipped},
                               {"triangles_before", original.triangleCount()},
                               {"triangles_after", coarse.triangleCount()},
                               {"rays", exact.rayCount()},
                               {"false_blocked", falseBlocked},
                               {"false_free", falseFree},
                               {"disagreeing_fraction", fraction},
                               {"ms_original", originalMs},
                               {"ms_coarse", coarseMs},
                               {"speedup", originalMs / std::max(coarseMs, 1e-9)}})
                  << "\n";
        return 0;
    }
    std::printf("coarse     %s: %zu meshes replaced%s, %zu -> %zu triangles\n", args.kind.c_str(), replaced,
                skipped ? " (open meshes left as they are)" : "", original.triangleCount(), coarse.triangleCount());
    std::printf("rays       %llu: %llu blocked only by the coarse level, %llu only by the original (%.4f%% differ)\n",
                (unsigned long long)exact.rayCount(), (unsigned long long)falseBlocked, (unsigned long long)falseFree,
                100.0 * fraction);
    std::printf("time       %.2f ms original, %.2f ms coarse: %.2fx (exact CPU sampler, median of %d)\n", originalMs, coarseMs,
                originalMs / std::max(coarseMs, 1e-9), args.repeat);
    return 0;
}

} // namespace sightline::cli
