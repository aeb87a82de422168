#include "cli/SuggestCommand.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/OptionRules.h"
#include "cli/OutputLimits.h"
#include "cli/OutputPaths.h"
#include "plugins/SceneFormats.h"
#include "project/CoarseOccluders.h"
#include "project/LightingSetup.h"
#include "project/Project.h"
#include "project/SuggestedOccluder.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"
#include "visibility/suggest/ViewGaps.h"

namespace sightline::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// "OUT-occluder.glb" beside the project to be written, or "OUT-occluder-2.glb", ...: a file that
/// does not exist yet, so a suggestion never replaces a file (an earlier suggestion's included).
fs::path freshMeshFile(const fs::path& projectOut)
{
    const fs::path folder = projectOut.parent_path();
    const std::string stem = projectOut.stem().string() + "-occluder";
    for (int k = 1;; ++k) {
        const fs::path candidate = folder / (stem + (k == 1 ? "" : "-" + std::to_string(k)) + ".glb");
        std::error_code ec;
        if (!fs::exists(fs::symlink_status(candidate, ec)))
            return candidate;
    }
}

json pointJson(const glm::dvec3& p)
{
    return json::array({p.x, p.y, p.z});
}

/// The plane, share and shape `suggest` asks for, checked before the level is loaded.
suggest::Request requestFromArgs(const SuggestArgs& args, bool onSurface)
{
    suggest::Request request;
    if (onSurface == !std::isnan(args.depth))
        throw Error(onSurface ? "give the plane one way: --depth T, or --at X Y Z with --normal NX NY NZ, not both"
                              : "where should the occluder lie? give --depth T (between the patches), or --at X Y Z with "
                                "--normal NX NY NZ (a surface the rays cross)");
    if (onSurface) {
        if (args.at.size() != 3 || args.normal.size() != 3)
            throw Error("--at and --normal go together, three numbers each");
        request.surface = suggest::PickedSurface{{args.at[0], args.at[1], args.at[2]}, {args.normal[0], args.normal[1], args.normal[2]}};
    } else {
        request.depth = args.depth;
    }
    request.share = args.share;
    request.shape = suggest::parseShape(args.shape);
    suggest::validateRequest(request);   // before the level is loaded and sampled
    return request;
}

/// Saves a copy of the project at --write with the suggested occluder added (and its mesh, if any).
void writeWithOccluder(const SuggestArgs& args, const Project& project, const SuggestedOccluder& suggested,
                       const fs::path& meshOut)
{
    const fs::path folder = fs::absolute(args.write).parent_path();
    Project out = rebasedProject(project, folder, false);
    out.occluders.push_back(suggested.spec);
    if (!meshOut.empty())
        saveScene(suggested.mesh, meshOut);
    saveProject(out, args.write);
}

/// `suggest --json`: the suggestion, its check and what was written, as one object.
void printSuggestionJson(const SuggestArgs& args, const Project& project, const SuggestedOccluder& suggested,
                         const fs::path& meshOut, bool onSurface)
{
    const suggest::Suggestion& s = suggested.suggestion;
    json corners = json::array();
    for (const glm::dvec3& p : s.worldPolygon())
        corners.push_back(pointJson(p));
    json out = {{"area", s.area},
                {"unblocked_before", s.unblockedBefore},
                {"unblocked_after", suggested.unblockedAfter},
                {"promised", s.promised},
                {"required", s.required},
                {"crossing", s.crossing},
                {"rays", std::uint64_t(project.source.sampleCount()) * std::uint64_t(project.receiver.sampleCount())},
                {"shape", suggest::shapeName(s.shape)},
                {"depth", onSurface ? json(nullptr) : json(args.depth)},
                {"share", args.share},
                {"plane", {{"origin", pointJson(s.plane.origin)}, {"normal", pointJson(s.plane.normal)}}},
                {"weighted", s.weighted},
                {"corners", corners},
                {"margin", s.margin},
                {"attempts", suggested.attempts},
                {"ms", suggested.sampleMs + suggested.suggestMs + suggested.checkMs},
                {"sample_ms", suggested.sampleMs},
                {"suggest_ms", suggested.suggestMs},
                {"check_ms", suggested.checkMs}};
    if (s.weighted) {
        out["light_before"] = s.lightBefore;
        out["light_required"] = s.lightRequired;
        out["light_after"] = suggested.lightAfter;
    }
    if (!args.write.empty()) {
        out["written"] = args.write;
        out["occluder"] = {{"name", suggested.spec.name}, {"mesh", suggested.spec.mesh}};
        if (!meshOut.empty())
            out["mesh_file"] = meshOut.string();
    }
    std::cout << dumpJson(out) << "\n";
}

/// `suggest` as text: the plane, the occluder, the rays before and after, the time, what was written.
void printSuggestionText(const SuggestArgs& args, const SuggestedOccluder& suggested, const fs::path& meshOut,
                         bool onSurface)
{
    const suggest::Suggestion& s = suggested.suggestion;
    std::printf("plane      %s: through [%.4f, %.4f, %.4f], normal [%.4f, %.4f, %.4f]\n",
                onSurface ? "the picked surface's" : ("depth " + std::to_string(args.depth)).c_str(), s.plane.origin.x,
                s.plane.origin.y, s.plane.origin.z, s.plane.normal.x, s.plane.normal.y, s.plane.normal.z);
    std::printf("occluder   %s, %zu corners, %.6g m² (margin %.2g m)\n", suggest::shapeName(s.shape), s.polygon.size(), s.area,
                s.margin);
    std::printf("rays       %llu unblocked before, %llu cross the plane; must block %llu (share %.6g)\n",
                (unsigned long long)s.unblockedBefore, (unsigned long long)s.crossing, (unsigned long long)s.required, args.share);
    std::printf("after      %llu unblocked by the exact sampler (promised at most %llu)\n",
                (unsigned long long)suggested.unblockedAfter, (unsigned long long)s.promised);
    if (s.weighted)
        std::printf("light      %.6g before, at least %.6g to block, %.6g left after\n", s.lightBefore, s.lightRequired,
                    suggested.lightAfter);
    std::printf("time       %.1f ms (sample %.1f, suggest %.1f, check %.1f)\n",
                suggested.sampleMs + suggested.suggestMs + suggested.checkMs, suggested.sampleMs, suggested.suggestMs,
                suggested.checkMs);
    if (!args.write.empty())
        std::printf("wrote      %s (occluder '%s'%s%s)\n", args.write.c_str(), suggested.spec.name.c_str(),
                    meshOut.empty() ? "" : ", mesh ", meshOut.empty() ? "" : meshOut.string().c_str());
}

} // namespace

CLI::App* addSuggestCommand(CLI::App& app, SuggestArgs& args)
{
    CLI::App* command = app.add_subcommand(
        "suggest", "The smallest occluder on a plane between the patches that blocks a share of the rays now unblocked, "
                   "checked by the exact sampler with it inserted (docs/cli.md)");
    command->add_option("project", args.project, "Project file (JSON)")->required();
    command->add_option("--depth", args.depth,
                        "Where the plane lies: at this fraction of the way from the source's centre to the receiver's, "
                        "perpendicular to that line, in (0, 1)");
    command->add_option("--at", args.at, "Or on a surface the rays cross, such as a doorway's frame: a point X Y Z on it (with --normal)")
        ->expected(3);
    command->add_option("--normal", args.normal, "The picked surface's normal NX NY NZ (either way round)")->expected(3);
    command->add_option("--share", args.share, "The share of the unblocked rays to block, in (0, 1]")->capture_default_str();
    command->add_flag("--weighted", args.weighted,
                      "Below share 1: the share of the light the unblocked rays carry (each weighted by its source sample's "
                      "colour in the project's light texture), not of their count");
    command->add_option("--shape", args.shape, "convex (a convex polygon) or rect (a rectangle free in the plane)")
        ->capture_default_str()
        ->check(CLI::IsMember({"convex", "rect"}));
    command->add_option("--write", args.write,
                        "Save a copy of the project with the occluder added (a convex one's mesh as OUT-occluder.glb "
                        "beside it; a rectangle as the built-in plane)")
        ->check(outputFile());
    command->add_flag("--json", args.json, "Print one JSON object instead of text");
    command->add_option("--threads", args.threads, "Sampling threads (0: all cores)")->check(CLI::Range(0, 1024));
    addAllowOutsidePaths(command, args.allowOutsidePaths);
    return command;
}

int runSuggest(const SuggestArgs& args)
{
    const bool onSurface = !args.at.empty() || !args.normal.empty();
    suggest::Request request = requestFromArgs(args, onSurface);
    std::error_code ec;
    if (!args.write.empty() && fs::is_directory(args.write, ec))
        throw Error("--write " + args.write + " is a folder: name the project file to write");
    const Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths});
    fs::path meshOut;
    if (!args.write.empty()) {
        if (request.shape == suggest::Shape::Convex)
            meshOut = freshMeshFile(args.write);
        checkOutputs({{"--write", args.write}, {"the occluder's mesh", meshOut}}, projectInputs(args.project, project));
    }
    if (args.weighted)
        request.sourceWeights = sourceLightWeights(project);
    const SuggestedOccluder suggested =
        suggestForProject(project, request, meshOut.empty() ? "suggested-occluder.glb" : meshOut.filename().string(), args.threads);

    if (!args.write.empty())
        writeWithOccluder(args, project, suggested, meshOut);

    if (args.json) {
        printSuggestionJson(args, project, suggested, meshOut, onSurface);
        return 0;
    }
    printSuggestionText(args, suggested, meshOut, onSurface);
    return 0;
}

CLI::App* addGapsCommand(CLI::App& app, GapsArgs& args)
{
    CLI::App* command = app.add_subcommand(
        "gaps", "The openings the view leaks through: the unblocked rays grouped by where they pass closest to the "
                "level's geometry, most rays first (docs/cli.md)");
    command->add_option("project", args.project, "Project file (JSON)")->required();
    command->add_flag("--json", args.json, "Print one JSON object instead of text");
    command->add_option("--threads", args.threads, "Sampling threads (0: all cores)")->check(CLI::Range(0, 1024));
    addAllowOutsidePaths(command, args.allowOutsidePaths);
    return command;
}

int runGaps(const GapsArgs& args)
{
    const Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths});
    const ReceiverHeights heights = validatedPairHeights(project);
    const Scene scene = buildRayScene(project);
    const auto start = std::chrono::steady_clock::now();
    BitmaskOptions options;
    options.threads = args.threads;
    options.heights = heights.empty() ? nullptr : &heights;
    const HiddenSampleMap map = CpuBitmaskSampler(scene).sample(project.source, project.receiver, options);
    const auto sampled = std::chrono::steady_clock::now();
    const std::vector<suggest::Opening> gaps = suggest::findViewGaps(worldTriangles(scene), project.source, project.receiver, heights, map);
    const auto ms = [](auto from, auto to) { return std::chrono::duration<double, std::milli>(to - from).count(); };
    const double sampleMs = ms(start, sampled), gapsMs = ms(sampled, std::chrono::steady_clock::now());
    const std::uint64_t unblocked = map.rayCount() - map.blockedCount();
    if (args.json) {
        json list = json::array();
        for (const suggest::Opening& gap : gaps)
            list.push_back(openingJson(gap));
        std::cout << dumpJson({{"rays", map.rayCount()}, {"unblocked", unblocked}, {"gaps", list}, {"sample_ms", sampleMs},
                               {"gaps_ms", gapsMs}})
                  << "\n";
        return 0;
    }
    std::printf("rays       %llu unblocked of %llu, through %zu openings (sampled %.1f ms, grouped %.1f ms)\n",
                (unsigned long long)unblocked, (unsigned long long)map.rayCount(), gaps.size(), sampleMs, gapsMs);
    for (std::size_t k = 0; k < gaps.size(); ++k) {
        const suggest::Opening& g = gaps[k];
        const glm::dvec3 size = g.max - g.min;
        std::printf("  %2zu  %9llu rays (%5.1f%%)  at [%.2f, %.2f, %.2f]  %.2f x %.2f x %.2f m  clearance %.2f m\n", k + 1,
                    (unsigned long long)g.rays, 100.0 * double(g.rays) / double(unblocked), g.centre.x, g.centre.y, g.centre.z,
                    size.x, size.y, size.z, g.clearance);
    }
    return 0;
}

json openingJson(const suggest::Opening& opening)
{
    return {{"rays", opening.rays}, {"centre", pointJson(opening.centre)}, {"min", pointJson(opening.min)},
            {"max", pointJson(opening.max)}, {"clearance", opening.clearance}};
}

} // namespace sightline::cli
