#include "cli/LightingCommands.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <numeric>
#include <regex>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/OptionRules.h"
#include "cli/OutputLimits.h"
#include "cli/Timing.h"
#include "cli/OutputPaths.h"
#include "lighting/SoftShadow.h"
#include "project/Animation.h"
#include "project/CoarseOccluders.h"
#include "project/ImportanceRun.h"
#include "project/LightingSetup.h"
#include "project/ProjectMotion.h"
#include "project/ProjectSampler.h"
#include "report/MapImage.h"
#include "report/OffscreenApplication.h"
#include "report/PngFile.h"
#include "base/Error.h"
#include "visibility/HeckbertHerfSampler.h"
#include "base/NpyFile.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::cli {

using nlohmann::json;

namespace {

/// "32x16" -> (32, 16), "64" -> (64, 64); throws sightline::Error.
void applyGrid(const std::string& text, const char* option, int limit, Patch& patch)
{
    if (text.empty())
        return;
    static const std::regex gridRe(R"((\d{1,5})(?:x(\d{1,5}))?)");
    std::smatch m;
    if (!std::regex_match(text, m, gridRe))
        throw Error(std::string(option) + " must be NAxNB or N, got '" + text + "'");
    const int na = std::stoi(m[1]);
    const int nb = m[2].matched ? std::stoi(m[2]) : na;
    if (na < 1 || nb < 1 || na > limit || nb > limit)
        throw Error(std::string(option) + " " + text + ": each side must be in [1, " + std::to_string(limit) + "]");
    patch.na = na;
    patch.nb = nb;
}

void applyGrids(const GridOverrides& grids, Project& project)
{
    applyGrid(grids.sourceSamples, "--source-samples", kMaxSourceSamples, project.source);
    applyGrid(grids.receiverSamples, "--receiver-samples", kMaxReceiverSide, project.receiver);
    validatePatch(project.source, "source");   // e.g. 64x32 = 2048 source samples
}

void addGridOptions(CLI::App* command, GridOverrides& grids)
{
    command->add_option("--source-samples", grids.sourceSamples,
                        "Source grid NAxNB (at most 1024 samples); default: the project's");
    command->add_option("--receiver-samples", grids.receiverSamples,
                        "Receiver grid NAxNB (each side up to 1024, e.g. 512x512 for a floor); default: the project's");
}

} // namespace

void checkImportanceOptions(const CLI::App& command, const ImportanceArgs& args)
{
    requireMethod(command, "--gl-backend", args.method, {"gl"});
    requireMethod(command, "--threads", args.method, {"cpu", "raycast"});
}

void checkShadowOptions(const CLI::App& command, const ShadowArgs& args)
{
    requireMethod(command, "--gl-backend", args.method, {"gl", "hh"});
    requireMethod(command, "--threads", args.method, {"cpu", "raycast"});
}

CLI::App* addImportanceCommand(CLI::App& app, ImportanceArgs& args)
{
    CLI::App* command = app.add_subcommand(
        "importance", "Importance map (paper §9): per sample of a patch, the fraction of the other patch it sees, "
                      "accumulated over the project's animation (or, with --path, its recorded path)");
    command->add_option("project", args.project, "Project file (JSON, docs/design.md §3; optional \"animation\" key)")->required();
    command->add_option("--out", args.out, "PNG: the map in the viridis colour map with a legend")->required()->check(outputFile());
    command->add_option("--npy", args.npy, "Also write the raw values as float32 .npy, shape (nb, na), in [0, 1]")->check(outputFile());
    command->add_option("--frames", args.frames,
                        "Frames to accumulate (default: the animation's \"frames\", else its last key frame + 1, "
                        "or 1 without an animation; with --path, the path's length)")
        ->check(CLI::Range(1, kMaxAnimationFrames));
    command->add_flag("--path", args.path,
                      "Accumulate over the project's recorded path (\"recorded_path\", recorded in the editor: "
                      "one frame per recorded frame, its edits applied) instead of its animation");
    command->add_option("--of", args.of, "Which patch the map is over: receiver (fraction of the source each "
                                         "receiver sample sees) or source (fraction of receiver samples seeing it)")
        ->check(CLI::IsMember({"receiver", "source"}))
        ->capture_default_str();
    command->add_option("--stat", args.statistic, "Accumulated statistic: mean, max, or ever (1 where any frame saw anything)")
        ->check(CLI::IsMember({"mean", "max", "ever"}))
        ->capture_default_str();
    command->add_option("--method", args.method,
                        "Sampler: cpu (exact bitmask), raycast (Embree reference) or gl (bitmask in OpenGL)")
        ->check(CLI::IsMember({"cpu", "raycast", "gl"}))
        ->capture_default_str();
    command->add_option("--gl-backend", args.glBackend, "gl: osmesa (software) or egl (GPU)")
        ->check(CLI::IsMember({"osmesa", "egl"}))
        ->capture_default_str();
    command->add_option("--jitter", args.jitter, "Decorrelated sampling seed (paper §6.2), 0 = off")
        ->check(CLI::Range(0u, 0xffffffffu));
    command->add_option("--threads", args.threads, "cpu, raycast: worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
    command->add_flag("--progress", args.progress, "Print progress on stderr (default when stderr is a terminal)");
    command->add_flag("--json", args.json, "Print one JSON object instead of text");
    addGridOptions(command, args.grids);
    addAllowOutsidePaths(command, args.allowOutsidePaths);
    return command;
}

int runImportance(const ImportanceArgs& args)
{
    const auto start = std::chrono::steady_clock::now();
    Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths});
    checkOutputs({{"--out", args.out}, {"--npy", args.npy}}, projectInputs(args.project, project));
    applyGrids(args.grids, project);
    const std::string what = std::filesystem::path(args.project).filename().string();
    const ProjectMotion motion =
        parseProjectMotion(project, args.path ? ProjectMotion::Kind::RecordedPath : ProjectMotion::Kind::Animation, what);
    if (args.path && motion.empty())
        throw Error(what + " has no recorded path (\"recorded_path\"): record one in the editor (Record > Record Video, F9)");
    const int frames = args.frames > 0 ? args.frames : motion.defaultFrames();
    if (frames > 1 && motion.empty())
        std::cerr << "sightline-cli: warning: the project has no animation; all " << frames << " frames are the same\n";
    // Refuse an invalid pair at any frame before the expensive work (never a wrong answer).
    const Project base = withoutMotionKeys(project);
    validateMotionFrames(base, motion, frames);

    std::vector<std::string> warnings;
    SamplerSettings settings;
    settings.method = args.method;
    settings.glContext = gl::contextFactory(gl::parseBackend(args.glBackend));
    settings.threads = args.threads;
    settings.jitter = SourceJitter{.seed = args.jitter};
    settings.heights = projectReceiverHeights(project, project.receiver, what);
    ProjectSampler sampler(motion.at(base, 0), loadProjectMeshes(project, &warnings), settings);
    printWarnings(warnings);

    const ImportanceSide side = args.of == "source" ? ImportanceSide::Source : ImportanceSide::Receiver;
    const bool showProgress = (args.progress || ::isatty(2)) && frames > 1;
    const ImportanceRunResult run = accumulateImportance(sampler, base, motion, frames, side, [&](int done, int total) {
        if (showProgress)
            std::fprintf(stderr, "\rsightline-cli: frame %d/%d", done, total);
        return true;
    });
    if (showProgress)
        std::fprintf(stderr, "\n");

    const ImportanceStatistic statistic = parseImportanceStatistic(args.statistic);
    const ImportanceMap map = run.accumulator.result(statistic);
    const auto [lo, hi] = std::minmax_element(map.values.begin(), map.values.end());
    const Patch& patch = side == ImportanceSide::Receiver ? project.receiver : project.source;
    const std::string statisticText = statistic == ImportanceStatistic::Mean      ? "mean"
                                      : statistic == ImportanceStatistic::Maximum ? "maximum"
                                                                                  : "ever visible";
    {
        const auto application = ensureApplication();
        const QString title = QString::fromStdString(args.of + " importance, " + statisticText + " over " +
                                                     std::to_string(run.framesDone) + (run.framesDone == 1 ? " frame" : " frames") +
                                                     (args.path ? " of the recorded path" : "") + " (" + std::to_string(patch.na) + "x" + std::to_string(patch.nb) + "): " + what);
        const QString caption = side == ImportanceSide::Receiver ? "fraction of the source seen" : "fraction of the receiver seeing it";
        savePng(renderMapImage(map, title, caption), args.out);
    }
    if (!args.npy.empty())
        writeFloatNpy(map.values, map.nb, map.na, args.npy);

    // Per frame sampled (a path's frames without an edit repeat the frame before, unsampled).
    const double perFrame = run.sampleMs / std::max(run.framesSampled, 1);
    if (args.json) {
        json out = {{"of", args.of},
                    {"statistic", args.statistic},
                    {"method", args.method},
                    {"frames", run.framesDone},
                    {"frames_sampled", run.framesSampled},
                    {"motion", motion.name()},
                    {"samples", json::array({map.na, map.nb})},
                    {"other_samples", json::array({side == ImportanceSide::Receiver ? project.source.na : project.receiver.na,
                                                   side == ImportanceSide::Receiver ? project.source.nb : project.receiver.nb})},
                    {"mean", map.mean()},
                    {"min", *lo},
                    {"max", *hi},
                    {"ms_per_frame", perFrame},
                    {"total_ms", millisecondsSince(start)},
                    {"triangles", sampler.triangleCount()},
                    {"out", args.out}};
        if (!args.npy.empty())
            out["npy"] = args.npy;
        std::cout << dumpJson(out) << "\n";
    } else {
        std::printf("importance %s, %s over %d frame%s, %dx%d samples (%s)\n", args.of.c_str(), statisticText.c_str(),
                    run.framesDone, run.framesDone == 1 ? "" : "s", map.na, map.nb, args.method.c_str());
        if (motion.kind == ProjectMotion::Kind::RecordedPath)
            std::printf("frames     of the recorded path (%d fps), %d sampled (the others change nothing)\n",
                        int(std::lround(motion.path.fps)), run.framesSampled);
        std::printf("values     mean %.4f, min %.4f, max %.4f\n", map.mean(), double(*lo), double(*hi));
        std::printf("time       %.2f ms a frame sampling, %.0f ms in all\n", perFrame, millisecondsSince(start));
        std::printf("image      %s\n", args.out.c_str());
        if (!args.npy.empty())
            std::printf("values     %s (float32, shape (%d, %d))\n", args.npy.c_str(), map.nb, map.na);
    }
    return 0;
}

CLI::App* addShadowCommand(CLI::App& app, ShadowArgs& args)
{
    CLI::App* command = app.add_subcommand(
        "shadow", "Soft shadow (paper §8): the light the source patch, as an area light, casts on the receiver");
    command->add_option("project", args.project,
                        "Project file (optional \"light\" texture and \"receiver_heights\", see README)")->required();
    command->add_option("--out", args.out, "PNG of the light on the receiver, one pixel per receiver sample (v up)")->required()->check(outputFile());
    command->add_option("--npy", args.npy, "Also write the light fraction (mean over colours) as float32 .npy, shape (nb, na)")->check(outputFile());
    command->add_flag("--intensity", args.intensity, "Write the shadow intensity (1 - light, grey) instead of the light");
    command->add_option("--scale", args.scale, "Enlarge the PNG N times (nearest)")->check(CLI::Range(1, 64));
    command->add_option("--method", args.method,
                        "Sampler: cpu (exact bitmask), raycast (Embree reference), gl (bitmask in OpenGL), "
                        "hh (Heckbert-Herf; white light, flat receiver)")
        ->check(CLI::IsMember({"cpu", "raycast", "gl", "hh"}))
        ->capture_default_str();
    command->add_option("--gl-backend", args.glBackend, "gl, hh: osmesa (software) or egl (GPU)")
        ->check(CLI::IsMember({"osmesa", "egl"}))
        ->capture_default_str();
    command->add_option("--jitter", args.jitter,
                        "Decorrelated sampling seed (paper §6.2): trades the banding of few light samples for noise")
        ->check(CLI::Range(0u, 0xffffffffu));
    command->add_option("--threads", args.threads, "cpu, raycast: worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
    command->add_flag("--json", args.json, "Print one JSON object instead of text");
    addGridOptions(command, args.grids);
    addAllowOutsidePaths(command, args.allowOutsidePaths);
    return command;
}

int runShadow(const ShadowArgs& args)
{
    const auto start = std::chrono::steady_clock::now();
    Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths});
    checkOutputs({{"--out", args.out}, {"--npy", args.npy}}, projectInputs(args.project, project));
    applyGrids(args.grids, project);
    validatePatchPair(project.source, project.receiver);
    // The PNG is the receiver grid times --scale a side: both in range can still be too big.
    checkImageSize(project.receiver.na * args.scale, project.receiver.nb * args.scale,
                   "--scale " + std::to_string(args.scale) + " of the " + std::to_string(project.receiver.na) + "x" +
                       std::to_string(project.receiver.nb) + " receiver",
                   8);
    const std::string what = std::filesystem::path(args.project).filename().string();
    const AreaLight light = projectLight(project, project.source, what);
    const ReceiverHeights heights = projectReceiverHeights(project, project.receiver, what);
    const SourceJitter jitter{.seed = args.jitter};

    std::vector<std::string> warnings;
    HiddenSampleMap map;
    ImportanceMap counted;   // hh: light fractions from counts, no map
    double ms = 0.0;
    if (args.method != "hh") {
        SamplerSettings settings{
            .method = args.method, .glContext = gl::contextFactory(gl::parseBackend(args.glBackend)), .threads = args.threads, .jitter = jitter, .heights = heights};
        ProjectSampler sampler(project, loadProjectMeshes(project, &warnings), settings);
        map = sampler.sample(project);
        ms = sampler.lastSampleMs();
    } else {
        if (!heights.empty())
            throw Error("--method hh: a height-field receiver needs cpu or raycast");
        if (jitter.enabled() || light.groups.size() != 1 || light.groups[0].count != light.sourceCount)
            throw Error("--method hh counts blocked samples only: white light and no --jitter (use cpu, raycast or gl)");
        const Scene scene = buildRayScene(project, &warnings);
        const auto context = gl::HeadlessContext::create(gl::parseBackend(args.glBackend));
        const auto sampleStart = std::chrono::steady_clock::now();
        HeckbertHerfSampler sampler(context->functions(), worldTriangles(scene));
        const std::vector<std::uint32_t> counts = sampler.blockedCounts(project.source, project.receiver);
        counted = ImportanceMap(project.receiver.na, project.receiver.nb);
        for (std::size_t j = 0; j < counts.size(); ++j)
            counted.values[j] = 1.0f - float(counts[j]) / float(project.source.sampleCount());
        ms = millisecondsSince(sampleStart);
    }
    printWarnings(warnings);

    LightImage image;
    if (counted.values.empty()) {
        image = shadeReceiver(map, light);
    } else {
        image = {counted.na, counted.nb, {}};
        for (float f : counted.values)
            image.rgb.emplace_back(f);
    }
    ImportanceMap fraction(image.na, image.nb);
    for (std::size_t j = 0; j < image.rgb.size(); ++j)
        fraction.values[j] = (image.rgb[j].r + image.rgb[j].g + image.rgb[j].b) / 3.0f;
    {
        const auto application = ensureApplication();
        savePng(renderLightImage(image, args.scale, args.intensity), args.out);
    }
    if (!args.npy.empty())
        writeFloatNpy(fraction.values, fraction.nb, fraction.na, args.npy);

    const glm::vec3 full = light.unoccluded();
    if (args.json) {
        json out = {{"method", args.method},
                    {"samples", json::array({project.receiver.na, project.receiver.nb})},
                    {"light_samples", json::array({project.source.na, project.source.nb})},
                    {"light_groups", light.groups.size()},
                    {"unoccluded", json::array({full.r, full.g, full.b})},
                    {"mean_light", fraction.mean()},
                    {"height_field", !heights.empty()},
                    {"jitter_seed", args.jitter},
                    {"ms", ms},
                    {"total_ms", millisecondsSince(start)},
                    {"out", args.out}};
        if (!args.npy.empty())
            out["npy"] = args.npy;
        std::cout << dumpJson(out) << "\n";
    } else {
        std::printf("shadow     %dx%d receiver samples, %dx%d light samples in %zu colour group%s%s (%s)\n",
                    project.receiver.na, project.receiver.nb, project.source.na, project.source.nb, light.groups.size(),
                    light.groups.size() == 1 ? "" : "s", heights.empty() ? "" : ", height field", args.method.c_str());
        std::printf("light      mean %.4f of full light\n", fraction.mean());
        std::printf("time       %.2f ms sampling, %.0f ms in all\n", ms, millisecondsSince(start));
        std::printf("image      %s\n", args.out.c_str());
    }
    return 0;
}

} // namespace sightline::cli
