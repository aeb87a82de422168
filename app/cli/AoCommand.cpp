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
#include "visibility/Error.h"
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

int runAo(const AoArgs& args)
{
    const auto start = std::chrono::steady_clock::now();
    const int level = aoLevelOf(args.k);
    // The environment first: a bad file is refused before the expensive scene work.
    std::optional<AoEnvironment> environment;
    if (!args.env.empty())
        environment = AoEnvironment::load(args.env);

    std::vector<std::string> warnings;
    std::optional<Project> project;
    std::vector<FileRole> inputs{{"the mesh", args.input}};
    if (isProject(args.input)) {
        project = loadProject(args.input, {.allowOutsidePaths = args.allowOutsidePaths});
        inputs = projectInputs(args.input, *project);
    }
    if (!args.env.empty())
        inputs.push_back({"the environment", args.env});
    checkOutputs({{"--npy", args.npy}, {"--gltf", args.gltf}, {"--ply", args.ply}, {"--lightmap", args.lightmap}}, inputs);
    const Scene scene = project ? buildScene(*project, &warnings) : loadScene(args.input, &warnings);
    const AoOccluders occluders = aoOccluders(scene);
    const std::string what = std::filesystem::path(args.input).filename().string();
    if (occluders.triangleCount() == 0)   // refused before the importer's warnings: one line
        throw Error(what + ": no triangles (an empty mesh has nothing to occlude or shade)");
    printWarnings(warnings);

    const bool texelMode = args.texel > 0.0;
    AoPoints points;
    AoTexelLayout layout;
    if (texelMode) {
        layout = aoTexelPoints(occluders, args.texel, points, kMaxImagePixels);
    } else {
        points = aoVertexPoints(scene);
    }
    const double offset = kAoOffsetRelative * occluders.diagonal();
    points.offsetOrigins(offset);
    const double loadMs = msSince(start);

    const AoCasterChoice caster = chooseCaster(args, occluders);
    const std::string& renderer = caster.renderer;
    const AoGlCaster* glCaster = caster.gl;

    // Progressive, level by level: each level's time is reported (the editor shows each at once).
    AoComputation computation(*caster.filler, points, args.k);
    const auto fillStart = std::chrono::steady_clock::now();
    json levels = json::array();
    for (int s = 0; s <= level; ++s) {
        computation.refineLevel();
        levels.push_back({{"k", computation.completedK()}, {"ms", msSince(fillStart)}});
    }
    const double fillMs = msSince(fillStart);

    const AoWeighting weighting = args.weights == "count" ? AoWeighting::PlainCount : AoWeighting::SolidAngle;
    const auto shadeStart = std::chrono::steady_clock::now();
    const std::vector<float> ao = ambientOcclusion(computation.matrix(), points, args.k, weighting);
    std::vector<glm::vec3> colours(ao.size());
    double relightMs = 0.0;
    if (environment) {
        const AoRelighter relighter(computation.matrix(), points, args.k, weighting);
        const std::vector<glm::vec3> radiance = environment->directionRadiance(aoDirections(args.k), args.rotate, args.exposure);
        const auto relightStart = std::chrono::steady_clock::now();
        colours = relighter.shade(radiance, args.threads);
        relightMs = msSince(relightStart);
    } else {
        for (std::size_t i = 0; i < ao.size(); ++i)
            colours[i] = glm::vec3(ao[i]);
    }
    const double shadeMs = msSince(shadeStart);

    double sum = 0.0;
    std::size_t shaded = 0;
    for (float a : ao)
        if (!std::isnan(a)) {
            sum += a;
            ++shaded;
        }
    const std::size_t noFace = points.count(AoPointStatus::NoFace), zeroNormal = points.count(AoPointStatus::ZeroNormal);
    if (noFace)
        std::cerr << "sightline-cli: warning: " << what << ": " << noFace
                  << " vertices belong to no face: no normal, no AO (NaN in --npy, black in colours)\n";
    if (zeroNormal)
        std::cerr << "sightline-cli: warning: " << what << ": " << zeroNormal
                  << " vertices have a zero normal (only degenerate faces): no AO (NaN in --npy, black in colours)\n";
    writeAoOutputs(args, occluders, texelMode ? &layout : nullptr, ao, colours);

    const double mean = shaded ? sum / double(shaded) : 0.0;
    if (args.json) {
        json out = {{"k", args.k},
                    {"vertices", texelMode ? std::size_t(0) : points.size()},
                    {"points", points.size()},
                    {"mode", texelMode ? "texel" : "vertex"},
                    {"method", args.method},
                    {"weights", args.weights},
                    {"ms", fillMs},
                    {"levels", levels},
                    {"shade_ms", shadeMs},
                    {"load_ms", loadMs},
                    {"triangles", occluders.triangleCount()},
                    {"no_face", noFace},
                    {"zero_normal", zeroNormal},
                    {"shaded", shaded},
                    {"mean_ao", mean},
                    {"offset_m", offset},
                    {"visible_bits", computation.matrix().visibleCount(args.k)}};
        if (texelMode)
            out["texel"] = {{"density", args.texel}, {"atlas", {layout.width, layout.height}}};
        if (environment)
            out["env"] = {{"file", args.env}, {"rotate", args.rotate}, {"exposure", args.exposure}, {"relight_ms", relightMs}};
        if (!renderer.empty())
            out["renderer"] = renderer;
        if (glCaster)
            out["gl"] = {{"resolution", args.glResolution}, {"texel_m", glCaster->texelSize()},
                         {"drawn_triangles", glCaster->drawnTriangles()}, {"simplification_m", glCaster->simplificationError()}};
        std::cout << dumpJson(out) << "\n";
    } else {
        std::printf("ao         %s: %zu %s, %zu triangles, k = %d (%s, %s weights)\n", what.c_str(), points.size(),
                    texelMode ? "texels" : "vertices", occluders.triangleCount(), args.k, args.method.c_str(),
                    args.weights.c_str());
        std::printf("values     mean %.4f over %zu points (%zu of no face, %zu zero normals: NaN)\n", mean, shaded, noFace,
                    zeroNormal);
        if (glCaster)
            std::printf("gl         %d^2 depth maps (texel %.3g m) of %zu triangles, simplified within %.3g m\n",
                        args.glResolution, glCaster->texelSize(), glCaster->drawnTriangles(), glCaster->simplificationError());
        std::printf("time       %.1f ms matrix, %.1f ms shading, %.0f ms loading\n", fillMs, shadeMs, loadMs);
        for (const json& l : levels)
            std::printf("           k = %4d after %.1f ms\n", l["k"].get<int>(), l["ms"].get<double>());
    }
    return 0;
}

} // namespace sightline::cli
