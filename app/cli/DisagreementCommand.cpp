#include "cli/DisagreementCommand.h"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/AoFiles.h"
#include "cli/OptionRules.h"
#include "cli/OutputLimits.h"
#include "cli/OutputPaths.h"
#include "project/Approximation.h"
#include "project/CoarseOccluders.h"
#include "project/LightingSetup.h"
#include "project/Project.h"
#include "report/PngFile.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"
#include "visibility/RayDisagreement.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::cli {

namespace {

double msSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

CLI::App* addDisagreementCommand(CLI::App& app, DisagreementArgs& args)
{
    CLI::App* command = app.add_subcommand(
        "disagreement", "Where a fast or coarse mode answers the project's pair differently from the exact sampler: "
                        "false-blocked and false-free rays (ties apart, by the exact judge), as counts and a picture "
                        "(docs/cli.md)");
    command->add_option("project", args.project, "Project file (JSON)")->required();
    command->add_option("--approximation", args.approximation,
                        "table[-WxH] (Hough table, CPU), gl-table[-WxH] (Hough table, GPU pass), gl (GPU pass, exact "
                        "masks), samples-K (1/K of the samples each side), coarse[-N] (meshes decimated to N "
                        "triangles), inner[-R] (conservative inner occluders)")
        ->capture_default_str();
    command->add_option("--image", args.image,
                        "PNG of every ray: a tile per receiver sample, a pixel per source sample; false-blocked red, "
                        "false-free blue, ties amber")
        ->check(outputFile());
    command->add_option("--gl-backend", args.glBackend, "OpenGL context for gl and gl-table: osmesa or egl")
        ->capture_default_str()
        ->check(CLI::IsMember({"osmesa", "egl"}));
    command->add_option("--threads", args.threads, "Sampling threads (0: all cores)")->check(CLI::Range(0, 1024));
    command->add_flag("--json", args.json, "Print one JSON object instead of text");
    addAllowOutsidePaths(command, args.allowOutsidePaths);
    return command;
}

int runDisagreement(const DisagreementArgs& args)
{
    const Approximation approximation = parseApproximation(args.approximation);   // before anything is loaded
    const Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths});
    checkOutputs({{"--image", args.image}}, projectInputs(args.project, project));
    const ReceiverHeights heights = validatedPairHeights(project);
    const Scene level = buildRayScene(project);

    auto start = std::chrono::steady_clock::now();
    BitmaskOptions exactOptions;
    exactOptions.threads = args.threads;
    exactOptions.heights = heights.empty() ? nullptr : &heights;
    const HiddenSampleMap exact = CpuBitmaskSampler(level).sample(project.source, project.receiver, exactOptions);
    const double exactMs = msSince(start);

    std::unique_ptr<gl::HeadlessContext> context;
    if (approximation.needsGl())
        context = gl::HeadlessContext::create(gl::parseBackend(args.glBackend));
    start = std::chrono::steady_clock::now();
    ApproximateSampler sampler(approximation, level);
    const double prepareMs = msSince(start);
    const JudgedDisagreement judged = judgedDisagreement(sampler, level, project.source, project.receiver, &heights,
                                                         exact, args.threads, context ? &context->functions() : nullptr);
    const RayDisagreement& d = judged.disagreement;

    if (!args.image.empty()) {
        const DisagreementImage image = disagreementImage(exact, d, project.source.na, project.source.nb);
        saveRgbPng(image.width, image.height, image.rgb, args.image);
    }
    if (args.json) {
        nlohmann::json out = {{"approximation", approximationName(approximation)},
                              {"rays", d.rays},
                              {"blocked_exact", exact.blockedCount()},
                              {"blocked_approximate", judged.approximateBlocked},
                              {"false_blocked", d.falseBlockedCount},
                              {"false_free", d.falseFreeCount},
                              {"ties", d.tieCount},
                              {"judged", d.judged},
                              {"exact_errors", d.exactErrors},
                              {"disagreeing_fraction", d.errorFraction()},
                              {"triangles_exact", level.triangleCount()},
                              {"triangles_approximate", sampler.scene().triangleCount()},
                              {"meshes_replaced", sampler.meshesReplaced()},
                              {"ms_exact", exactMs},
                              {"ms_approximate", judged.approximateMs},
                              {"prepare_ms", prepareMs},
                              {"judge_ms", judged.judgeMs}};
        if (!args.image.empty())
            out["image"] = args.image;
        std::cout << dumpJson(out) << "\n";
        return 0;
    }
    std::printf("approximation %s: %s\n", approximationName(approximation).c_str(), describeApproximation(approximation).c_str());
    std::printf("rays          %llu: %llu false-blocked, %llu false-free (%.4f%% differ), %llu ties%s\n",
                (unsigned long long)d.rays, (unsigned long long)d.falseBlockedCount, (unsigned long long)d.falseFreeCount,
                100.0 * d.errorFraction(), (unsigned long long)d.tieCount,
                d.judged ? "" : " (too many differences to judge: each counts as an error)");
    std::printf("time          exact %.1f ms, approximate %.1f ms (%.1f ms to prepare), judging %.1f ms\n", exactMs,
                judged.approximateMs, prepareMs, judged.judgeMs);
    if (d.exactErrors)
        std::printf("warning       the judge sided with the approximation on %llu rays: a bug in the exact sampler\n",
                    (unsigned long long)d.exactErrors);
    if (!args.image.empty())
        std::printf("image         %s\n", args.image.c_str());
    return 0;
}

} // namespace sightline::cli
