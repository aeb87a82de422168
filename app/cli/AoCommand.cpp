#include "cli/AoCommand.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/AoFiles.h"
#include "cli/OptionRules.h"
#include "cli/OutputLimits.h"
#include "cli/OutputPaths.h"
#include "lighting/ao/AoBinnedCaster.h"
#include "lighting/ao/AoComputation.h"
#include "lighting/ao/AoEmbree.h"
#include "lighting/ao/AoEnvironment.h"
#include "lighting/ao/AoGlCaster.h"
#include "lighting/ao/AoShading.h"
#include "lighting/ao/AoTexels.h"
#include "plugins/SceneFormats.h"
#include "project/Project.h"
#include "base/Error.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::cli {

using nlohmann::json;

namespace {

double msSince(std::chrono::steady_clock::time_point t)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

bool isProject(const std::string& path)
{
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".json";
}

} // namespace

CLI::App* addAoCommand(CLI::App& app, AoArgs& args)
{
    CLI::App* command = app.add_subcommand(
        "ao", "Ambient occlusion (Sattler et al. 2004): per-vertex, or per light-map texel with --texel, from a "
              "visibility matrix over k light directions; uniform sky or an HDR environment (docs/ao.md)");
    command->add_option("input", args.input, "Mesh file (glTF, GLB, OBJ, PLY, OFF, STL) or project (.json)")->required();
    command->add_option("--k", args.k, "Light directions: 6, 18, 66, 258 or 1026 (subdivided octahedron)")->capture_default_str();
    command->add_option("--npy", args.npy,
                        "AO as float32 .npy: shape (V,) in the file's vertex order, NaN for a vertex of no face; with "
                        "--texel the atlas, shape (H, W), NaN in the gutter")->check(outputFile());
    command->add_flag("--json", args.json, "Print one JSON object (k, vertices, ms, ...) instead of text");
    command->add_option("--method", args.method,
                        "Fill the matrix with cpu (exact, binned per direction), embree (single rays, the baseline) or "
                        "gl (depth map per direction, the paper's way)")
        ->check(CLI::IsMember({"cpu", "embree", "gl"}))
        ->capture_default_str();
    command->add_option("--weights", args.weights,
                        "solid-angle (each direction weighs its cell's cosine lobe) or count (the paper's n.l, cells "
                        "counted alike)")
        ->check(CLI::IsMember({"solid-angle", "count"}))
        ->capture_default_str();
    command->add_option("--gl-backend", args.glBackend, "gl: osmesa (software) or egl (GPU)")
        ->check(CLI::IsMember({"osmesa", "egl"}))
        ->capture_default_str();
    command->add_option("--gl-resolution", args.glResolution, "gl: depth map side in pixels")
        ->check(CLI::Range(64, 8192))
        ->capture_default_str();
    command->add_option("--gl-simplify", args.glSimplify,
                        "gl: draw the depth maps from the occluders simplified within T texels (0: every triangle)")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    command->add_option("--env", args.env, "Light from a Radiance .hdr latitude-longitude environment (colours only; "
                                           "--npy stays the uniform-sky AO)");
    command->add_option("--rotate", args.rotate, "--env: turn the environment about +Y by DEG degrees");
    command->add_option("--exposure", args.exposure, "--env: scale its radiance by 2^EV");
    command->add_option("--texel", args.texel,
                        "Texel mode: sample points on a grid of M texels per metre over each triangle (light maps; "
                        "M in (0, 1000])");
    command->add_option("--lightmap", args.lightmap, "Texel mode: write the light-map atlas PNG (sRGB)")->check(outputFile());
    command->add_option("--gltf", args.gltf,
                        "Write glTF (.glb/.gltf): AO (or --env colour) in COLOR_0; with --texel, TEXCOORD_1 and an "
                        "occlusionTexture naming the --lightmap PNG")->check(outputFile());
    command->add_option("--ply", args.ply, "Write a binary PLY with sRGB vertex colours (vertex mode)")->check(outputFile());
    command->add_option("--threads", args.threads, "cpu, embree: worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
    addAllowOutsidePaths(command, args.allowOutsidePaths);
    return command;
}

void checkAoOptions(const CLI::App& command, const AoArgs& args)
{
    aoLevelOf(args.k);   // "k 100: the light sphere has 6, 18, 66, 258 or 1026 directions"
    requireMethod(command, "--gl-backend", args.method, {"gl"});
    requireMethod(command, "--gl-resolution", args.method, {"gl"});
    requireMethod(command, "--gl-simplify", args.method, {"gl"});
    requireMethod(command, "--threads", args.method, {"cpu", "embree"});
    for (const char* option : {"--rotate", "--exposure"})
        if (given(command, option) && args.env.empty())
            throw Error(std::string(option) + " applies to an environment; add --env FILE.hdr");
    if (given(command, "--texel"))
        checkTexelDensity(args.texel);   // before the mode is chosen by it: NaN is not "no --texel"
    if (args.texel > 0.0 && !args.ply.empty())
        throw Error("--ply writes vertex colours; in texel mode (--texel) write --lightmap PNG and --gltf instead");
    if (args.texel <= 0.0 && !args.lightmap.empty())
        throw Error("--lightmap applies to the texel mode; add --texel M (texels per metre)");
    if (args.texel > 0.0 && !args.gltf.empty() && args.lightmap.empty())
        throw Error("--gltf in texel mode refers to the light map; add --lightmap OUT.png");
    if (!std::isfinite(args.rotate) || !std::isfinite(args.exposure) || std::abs(args.exposure) > 64.0)
        throw Error("--rotate and --exposure must be finite (exposure within +-64 EV)");
}

namespace {

/// The caster --method names, and what keeps it alive (a GL context).
struct AoCasterChoice {
    std::unique_ptr<gl::HeadlessContext> context;
    std::unique_ptr<AoFiller> filler;
    std::string renderer;              ///< the GL renderer, for --method gl
    const AoGlCaster* gl = nullptr;    ///< `filler`, for --method gl
};

AoCasterChoice chooseCaster(const AoArgs& args, const AoOccluders& occluders)
{
    AoCasterChoice choice;
    if (args.method == "cpu") {
        choice.filler = std::make_unique<AoBinnedCaster>(occluders, AoBinnedOptions{.threads = args.threads});
    } else if (args.method == "embree") {
        choice.filler = std::make_unique<AoEmbreeCaster>(occluders, args.threads);
    } else {
        choice.context = gl::HeadlessContext::create(gl::parseBackend(args.glBackend));
        choice.renderer = choice.context->renderer();
        auto caster = std::make_unique<AoGlCaster>(choice.context->functions(), occluders,
                                                   AoGlOptions{.resolution = args.glResolution, .simplifyTexels = args.glSimplify});
        choice.gl = caster.get();
        choice.filler = std::move(caster);
    }
    return choice;
}

/// --npy (per vertex, or the texel atlas with NaN between tiles), --ply, --lightmap and --gltf.
/// `layout`: the texel atlas in texel mode, else null.
void writeAoOutputs(const AoArgs& args, const AoOccluders& occluders, const AoTexelLayout* layout, const std::vector<float>& ao,
                    const std::vector<glm::vec3>& colours)
{
    if (!args.npy.empty()) {
        if (layout) {
            std::vector<float> atlas(std::size_t(layout->width) * std::size_t(layout->height), std::nanf(""));
            for (const AoTexelTile& tile : layout->tiles)
                for (int t = 0; t < tile.height; ++t)
                    for (int s = 0; s < tile.width; ++s)
                        atlas[std::size_t(tile.y + t) * std::size_t(layout->width) + std::size_t(tile.x + s)] =
                            ao[tile.firstPoint + std::size_t(t) * std::size_t(tile.width) + std::size_t(s)];
            writeAoNpy(atlas, args.npy, layout->width);
        } else {
            writeAoNpy(ao, args.npy);
        }
    }
    if (!args.ply.empty())
        writeColouredPly(occluders, colours, args.ply);
    if (layout && !args.lightmap.empty())
        writeLightmapPng(*layout, colours, args.lightmap);
    if (!args.gltf.empty()) {
        if (layout) {
            const std::filesystem::path gltfFolder = std::filesystem::absolute(args.gltf).parent_path();
            const std::filesystem::path png = std::filesystem::absolute(args.lightmap);
            writeLightmappedGltf(occluders, *layout, png.lexically_relative(gltfFolder).generic_string(), args.gltf);
        } else {
            writeColouredGltf(occluders, colours, args.gltf);
        }
    }
}

} // namespace

namespace {

/// What one `ao` run computed and measured, for its report.
struct AoRun {
    std::string what;               ///< the input's file name
    std::optional<AoEnvironment> environment;
    bool texelMode = false;
    AoPoints points;
    AoTexelLayout layout;
    double offset = 0.0;
    std::size_t triangles = 0;
    std::string renderer;
    const AoGlCaster* glCaster = nullptr;
    json levels = json::array();
    double loadMs = 0.0, fillMs = 0.0, shadeMs = 0.0, relightMs = 0.0;
    std::vector<float> ao;
    std::vector<glm::vec3> colours;
    std::size_t shaded = 0, noFace = 0, zeroNormal = 0, visibleBits = 0;
    double mean = 0.0;
};

/// The scene from the mesh or project, its outputs checked first against every file it reads;
/// the importer's warnings into `warnings`.
Scene loadAoScene(const AoArgs& args, std::vector<std::string>& warnings)
{
    std::optional<Project> project;
    std::vector<FileRole> inputs{{"the mesh", args.input}};
    if (isProject(args.input)) {
        project = loadProject(args.input, {.allowOutsidePaths = args.allowOutsidePaths});
        inputs = projectInputs(args.input, *project);
    }
    if (!args.env.empty())
        inputs.push_back({"the environment", args.env});
    checkOutputs({{"--npy", args.npy}, {"--gltf", args.gltf}, {"--ply", args.ply}, {"--lightmap", args.lightmap}}, inputs);
    return project ? buildScene(*project, &warnings) : loadScene(args.input, &warnings);
}

/// AO from the matrix and, with an environment, the relit colours (else grey levels).
void shadeAo(const AoArgs& args, const AoComputation& computation, AoRun& run)
{
    const AoWeighting weighting = args.weights == "count" ? AoWeighting::PlainCount : AoWeighting::SolidAngle;
    const auto shadeStart = std::chrono::steady_clock::now();
    run.ao = ambientOcclusion(computation.matrix(), run.points, args.k, weighting);
    run.colours.assign(run.ao.size(), glm::vec3(0.0f));
    if (run.environment) {
        const AoRelighter relighter(computation.matrix(), run.points, args.k, weighting);
        const std::vector<glm::vec3> radiance = run.environment->directionRadiance(aoDirections(args.k), args.rotate, args.exposure);
        const auto relightStart = std::chrono::steady_clock::now();
        run.colours = relighter.shade(radiance, args.threads);
        run.relightMs = msSince(relightStart);
    } else {
        for (std::size_t i = 0; i < run.ao.size(); ++i)
            run.colours[i] = glm::vec3(run.ao[i]);
    }
    run.shadeMs = msSince(shadeStart);
    double sum = 0.0;
    for (float a : run.ao)
        if (!std::isnan(a)) {
            sum += a;
            ++run.shaded;
        }
    run.mean = run.shaded ? sum / double(run.shaded) : 0.0;
    run.noFace = run.points.count(AoPointStatus::NoFace);
    run.zeroNormal = run.points.count(AoPointStatus::ZeroNormal);
    if (run.noFace)
        std::cerr << "sightline-cli: warning: " << run.what << ": " << run.noFace
                  << " vertices belong to no face: no normal, no AO (NaN in --npy, black in colours)\n";
    if (run.zeroNormal)
        std::cerr << "sightline-cli: warning: " << run.what << ": " << run.zeroNormal
                  << " vertices have a zero normal (only degenerate faces): no AO (NaN in --npy, black in colours)\n";
}

json aoRunJson(const AoArgs& args, const AoRun& run)
{
    json out = {{"k", args.k},
                {"vertices", run.texelMode ? std::size_t(0) : run.points.size()},
                {"points", run.points.size()},
                {"mode", run.texelMode ? "texel" : "vertex"},
                {"method", args.method},
                {"weights", args.weights},
                {"ms", run.fillMs},
                {"levels", run.levels},
                {"shade_ms", run.shadeMs},
                {"load_ms", run.loadMs},
                {"triangles", run.triangles},
                {"no_face", run.noFace},
                {"zero_normal", run.zeroNormal},
                {"shaded", run.shaded},
                {"mean_ao", run.mean},
                {"offset_m", run.offset},
                {"visible_bits", run.visibleBits}};
    if (run.texelMode)
        out["texel"] = {{"density", args.texel}, {"atlas", {run.layout.width, run.layout.height}}};
    if (run.environment)
        out["env"] = {{"file", args.env}, {"rotate", args.rotate}, {"exposure", args.exposure}, {"relight_ms", run.relightMs}};
    if (!run.renderer.empty())
        out["renderer"] = run.renderer;
    if (run.glCaster)
        out["gl"] = {{"resolution", args.glResolution}, {"texel_m", run.glCaster->texelSize()},
                     {"drawn_triangles", run.glCaster->drawnTriangles()}, {"simplification_m", run.glCaster->simplificationError()}};
    return out;
}

void printAoRun(const AoArgs& args, const AoRun& run)
{
    std::printf("ao         %s: %zu %s, %zu triangles, k = %d (%s, %s weights)\n", run.what.c_str(), run.points.size(),
                run.texelMode ? "texels" : "vertices", run.triangles, args.k, args.method.c_str(), args.weights.c_str());
    std::printf("values     mean %.4f over %zu points (%zu of no face, %zu zero normals: NaN)\n", run.mean, run.shaded, run.noFace,
                run.zeroNormal);
    if (run.glCaster)
        std::printf("gl         %d^2 depth maps (texel %.3g m) of %zu triangles, simplified within %.3g m\n", args.glResolution,
                    run.glCaster->texelSize(), run.glCaster->drawnTriangles(), run.glCaster->simplificationError());
    std::printf("time       %.1f ms matrix, %.1f ms shading, %.0f ms loading\n", run.fillMs, run.shadeMs, run.loadMs);
    for (const json& l : run.levels)
        std::printf("           k = %4d after %.1f ms\n", l["k"].get<int>(), l["ms"].get<double>());
}

} // namespace

int runAo(const AoArgs& args)
{
    const auto start = std::chrono::steady_clock::now();
    const int level = aoLevelOf(args.k);
    AoRun run;
    // The environment first: a bad file is refused before the expensive scene work.
    if (!args.env.empty())
        run.environment = AoEnvironment::load(args.env);
    std::vector<std::string> warnings;
    const Scene scene = loadAoScene(args, warnings);
    const AoOccluders occluders = aoOccluders(scene);
    run.what = std::filesystem::path(args.input).filename().string();
    run.triangles = occluders.triangleCount();
    if (run.triangles == 0)   // refused before the importer's warnings: one line
        throw Error(run.what + ": no triangles (an empty mesh has nothing to occlude or shade)");
    printWarnings(warnings);
    run.texelMode = args.texel > 0.0;
    if (run.texelMode)
        run.layout = aoTexelPoints(occluders, args.texel, run.points, kMaxImagePixels);
    else
        run.points = aoVertexPoints(scene);
    run.offset = kAoOffsetRelative * occluders.diagonal();
    run.points.offsetOrigins(run.offset);
    run.loadMs = msSince(start);

    const AoCasterChoice caster = chooseCaster(args, occluders);
    run.renderer = caster.renderer;
    run.glCaster = caster.gl;
    // Progressive, level by level: each level's time is reported (the editor shows each at once).
    AoComputation computation(*caster.filler, run.points, args.k);
    const auto fillStart = std::chrono::steady_clock::now();
    for (int s = 0; s <= level; ++s) {
        computation.refineLevel();
        run.levels.push_back({{"k", computation.completedK()}, {"ms", msSince(fillStart)}});
    }
    run.fillMs = msSince(fillStart);
    run.visibleBits = computation.matrix().visibleCount(args.k);

    shadeAo(args, computation, run);
    writeAoOutputs(args, occluders, run.texelMode ? &run.layout : nullptr, run.ao, run.colours);
    if (args.json)
        std::cout << dumpJson(aoRunJson(args, run)) << "\n";
    else
        printAoRun(args, run);
    return 0;
}

} // namespace sightline::cli
