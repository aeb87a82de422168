#include "cli/LightsCommand.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <numeric>
#include <optional>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/OptionRules.h"
#include "cli/OutputPaths.h"
#include "lighting/DirectLight.h"
#include "lighting/GlDirectLight.h"
#include "lighting/ShadowAgreement.h"
#include "lighting/Indirect.h"
#include "lighting/LightSets.h"
#include "lighting/LightingCache.h"
#include "lighting/TexelCharts.h"
#include "lighting/ao/AoTexels.h"
#include "cli/AoFiles.h"
#include "cli/OutputLimits.h"
#include "cli/Timing.h"
#include "project/Project.h"
#include "project/ProjectLights.h"
#include "base/Error.h"
#include "base/NpyFile.h"
#include "visibility/gl/HeadlessContext.h"
#include "visibility/pvs/PvsData.h"
#include "editor/Camera.h"
#include "editor/CameraVisibility.h"
#include "editor/PvsDebugger.h"
#include "editor/ViewSettings.h"

namespace sightline::cli {

using nlohmann::json;

namespace {

/// (point, light sample) pairs one call may ask for: past this a run would take hours, and a
/// mistyped file should say so rather than appear to hang.
constexpr double kMaxTerms = 1e11;

std::vector<ShadingPoint> readPoints(const std::string& file)
{
    const FloatArray array = readFloatNpy(file);
    if (array.columns != 6)
        throw Error(file + ": --points must have shape (N, 6): rows x, y, z, nx, ny, nz (got " +
                    std::to_string(array.rows) + " x " + std::to_string(array.columns) + ")");
    std::vector<ShadingPoint> points(std::size_t(array.rows));
    for (std::size_t j = 0; j < points.size(); ++j) {
        const float* row = &array.values[6 * j];
        points[j].position = glm::dvec3(row[0], row[1], row[2]);
        points[j].normal = glm::dvec3(row[3], row[4], row[5]);
    }
    validateShadingPoints(points, file);
    return points;
}

std::string lightSummary(const std::vector<Light>& lights)
{
    std::size_t counts[4] = {0, 0, 0, 0};
    for (const Light& light : lights)
        ++counts[int(light.type)];
    std::string text;
    for (int t = 0; t < 4; ++t)
        if (counts[t])
            text += (text.empty() ? "" : ", ") + std::to_string(counts[t]) + " " + toString(LightType(t));
    return text.empty() ? "none" : text;
}

/// The largest difference between two answers, relative to the larger value at the point (with a
/// floor of 1e-12 W/m², so that dark points compare absolutely), and how many points differ by
/// more than 1e-12 of it. Both paths sum the same terms in the same order, so a point differs only
/// where a shadow segment is a tie.
double largestRelativeDifference(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b, std::size_t* differing)
{
    double worst = 0.0;
    *differing = 0;
    for (std::size_t j = 0; j < a.size(); ++j) {
        double here = 0.0;
        for (int c = 0; c < 3; ++c)
            here = std::max(here, std::abs(a[j][c] - b[j][c]) / std::max({std::abs(a[j][c]), std::abs(b[j][c]), 1e-12}));
        *differing += here > 1e-12;
        worst = std::max(worst, here);
    }
    return worst;
}

/// How far the light cut's answer is from the reference's: the relative difference of each point's
/// brightest channel (a floor of 1e-6 of the largest reference value, so that dark points compare
/// absolutely), its mean, 99th percentile and largest, and the share of points beyond 1% and 5%.
json lightCutError(const std::vector<glm::dvec3>& cut, const std::vector<glm::dvec3>& reference)
{
    double peak = 0.0;
    for (const glm::dvec3& e : reference)
        peak = std::max({peak, e.x, e.y, e.z});
    const double floor = std::max(1e-6 * peak, 1e-12);
    std::vector<double> relative(cut.size());
    for (std::size_t j = 0; j < cut.size(); ++j) {
        double here = 0.0;
        for (int c = 0; c < 3; ++c)
            here = std::max(here, std::abs(cut[j][c] - reference[j][c]) / std::max(reference[j][c], floor));
        relative[j] = here;
    }
    const double n = std::max<double>(1.0, double(relative.size()));
    const double mean = std::accumulate(relative.begin(), relative.end(), 0.0) / n;
    const auto beyond = [&](double limit) { return double(std::count_if(relative.begin(), relative.end(), [&](double r) { return r > limit; })) / n; };
    std::vector<double> sorted = relative;
    std::sort(sorted.begin(), sorted.end());
    const double p99 = sorted.empty() ? 0.0 : sorted[std::min(sorted.size() - 1, std::size_t(0.99 * double(sorted.size())))];
    return {{"mean_relative", mean},
            {"p99_relative", p99},
            {"max_relative", sorted.empty() ? 0.0 : sorted.back()},
            {"points_beyond_1pct", beyond(0.01)},
            {"points_beyond_5pct", beyond(0.05)}};
}

/// Light-map texels as shading points (lighting/TexelCharts.h): the charts' texels on the surface,
/// lifted off it as the AO texels are (kAoOffsetRelative of the scene's diagonal).
struct TexelBake {
    AoOccluders occluders;
    ChartLayout layout;
    AoPoints texels;
    std::vector<ShadingPoint> points;
    std::vector<std::size_t> texelOf;   ///< per point, its texel in `texels`
};

TexelBake texelBake(const Scene& scene, double density)
{
    TexelBake bake;
    bake.occluders = aoOccluders(scene);
    bake.layout = chartTexelPoints(bake.occluders, density, bake.texels, kMaxImagePixels);
    const double lift = kAoOffsetRelative * bake.occluders.diagonal();
    for (std::size_t k = 0; k < bake.texels.size(); ++k)
        if (bake.texels.status[k] == AoPointStatus::Ok) {
            const glm::dvec3 n(bake.texels.normals[k]);
            bake.points.push_back({glm::dvec3(bake.texels.positions[k]) + lift * n, n});
            bake.texelOf.push_back(k);
        }
    return bake;
}

/// The PNG's texels reach this many pixels into the gutters and the space around their charts:
/// the mip maps an engine builds stay true at the charts' edges for three levels.
constexpr int kLightmapDilation = 8;

/// The lights a glTF can carry (KHR_lights_punctual has no area lights), named as the messages name them.
std::vector<PunctualLight> punctualLights(const std::vector<Light>& lights)
{
    std::vector<PunctualLight> out;
    for (std::size_t l = 0; l < lights.size(); ++l) {
        const Light& light = lights[l];
        if (light.type == LightType::Area)
            continue;
        PunctualLight p;
        p.type = light.type == LightType::Point ? "point" : light.type == LightType::Spot ? "spot" : "directional";
        p.name = displayName(lights, l);
        p.colour = light.colour;
        p.intensity = light.intensity;
        p.range = light.type == LightType::Directional ? 0.0 : light.range;
        p.innerAngle = light.innerAngle, p.outerAngle = light.outerAngle;
        p.position = light.position;
        p.direction = light.direction;
        out.push_back(p);
    }
    return out;
}

/// The bake's atlas: .npy (H, W, 3) float32 irradiance, NaN where no texel; PNG scaled so that the
/// 99th percentile of texels' brightest channel is white, dilated kLightmapDilation pixels; glTF
/// with TEXCOORD_1, the PNG and the lights KHR_lights_punctual can carry.
json writeTexelOutputs(const LightsArgs& args, const TexelBake& bake, const std::vector<glm::dvec3>& irradiance,
                       const std::vector<Light>& lights)
{
    const ChartLayout& layout = bake.layout;
    std::vector<std::size_t> pixelOf(bake.texels.size(), 0);   // texel -> atlas pixel
    for (const TexelChart& chart : layout.charts)
        for (int t = 0; t < chart.height; ++t)
            for (int s = 0; s < chart.width; ++s)
                pixelOf[chart.firstPoint + std::size_t(t) * std::size_t(chart.width) + std::size_t(s)] =
                    std::size_t(chart.y + t) * std::size_t(layout.width) + std::size_t(chart.x + s);
    const std::size_t pixels = std::size_t(layout.width) * std::size_t(layout.height);
    std::vector<float> atlas(3 * pixels, std::nanf(""));
    std::vector<double> brightest;
    for (std::size_t j = 0; j < irradiance.size(); ++j) {
        const std::size_t px = pixelOf[bake.texelOf[j]];
        for (int c = 0; c < 3; ++c)
            atlas[3 * px + std::size_t(c)] = float(irradiance[j][c]);
        brightest.push_back(std::max({irradiance[j].x, irradiance[j].y, irradiance[j].z}));
    }
    double white = 0.0;
    if (!brightest.empty()) {
        const std::size_t at = std::min(brightest.size() - 1, brightest.size() * 99 / 100);
        std::nth_element(brightest.begin(), brightest.begin() + std::ptrdiff_t(at), brightest.end());
        white = brightest[at];
    }
    const double exposure = white > 0.0 ? 1.0 / white : 1.0;
    if (!args.npy.empty())
        writeFloatNpy(atlas, {std::size_t(layout.height), std::size_t(layout.width), 3}, args.npy);
    if (!args.lightmap.empty()) {
        std::vector<glm::vec3> image(pixels, glm::vec3(0.0f));
        std::vector<std::uint8_t> filled(pixels, 0);
        for (std::size_t px = 0; px < pixels; ++px)
            if (std::isfinite(atlas[3 * px])) {
                image[px] = glm::clamp(glm::vec3(atlas[3 * px], atlas[3 * px + 1], atlas[3 * px + 2]) * float(exposure), 0.0f, 1.0f);
                filled[px] = 1;
            }
        dilateAtlas(layout.width, layout.height, image, filled, kLightmapDilation);
        writeAtlasPng(layout.width, layout.height, image, args.lightmap);
    }
    json out = {{"density", args.texel},
                {"atlas", {layout.width, layout.height}},
                {"charts", layout.charts.size()},
                {"texels", bake.points.size()},
                {"exposure", exposure}};
    if (!args.gltf.empty()) {
        std::vector<glm::vec2> uvs;
        for (std::uint32_t t = 0; t < bake.occluders.triangleCount(); ++t)
            for (int c = 0; c < 3; ++c)
                uvs.push_back(layout.uv(bake.occluders, t, c));
        const std::filesystem::path png = std::filesystem::absolute(args.lightmap);
        const std::string uri = std::filesystem::relative(png, std::filesystem::absolute(args.gltf).parent_path()).generic_string();
        const std::vector<PunctualLight> punctual = punctualLights(lights);
        writeLightmappedGltf(bake.occluders, uvs, uri, args.gltf, LightmapUse::Emissive, punctual);
        if (punctual.size() < lights.size())
            std::fprintf(stderr, "sightline-cli: note: %s holds the %zu point, spot and directional lights; its %zu area lights have no "
                                 "KHR_lights_punctual counterpart and are baked into the light map only\n",
                         args.gltf.c_str(), punctual.size(), lights.size() - punctual.size());
        out["gltf_lights"] = punctual.size();
    }
    return out;
}

/// One bounce of VPLs added to `total` (lighting/Indirect.h); with --indirect-reference, the
/// gathering reference's mean and the VPLs' error against it. Returns the `indirect` JSON.
json addIndirectBounce(const LightingScene& lighting, const std::vector<Light>& lights, const std::vector<ShadingPoint>& points,
                       const LightsArgs& args, std::vector<glm::dvec3>& total, GlDirectLight* gl)
{
    IndirectOptions indirect;
    indirect.vpls = args.vpls;
    indirect.seed = args.seed;
    indirect.albedo = args.albedo;
    indirect.clampMetres = args.clamp;
    indirect.threads = args.threads;
    const VplSet vpls = traceVpls(lighting, lights, indirect);
    IndirectResult bounce;
    if (gl) {   // the VPLs by shadow maps, as Barczak shades them (no clamp loss is measured)
        GlDirectLightStats glStats;
        bounce.irradiance = gl->irradiance(vpls.vpls, points, &glStats);
        bounce.stats.ms = glStats.ms;
    } else {
        bounce = vplIrradiance(lighting, vpls, points, indirect);
    }
    glm::dvec3 mean(0.0);
    for (std::size_t j = 0; j < points.size(); ++j) {
        total[j] += bounce.irradiance[j];
        mean += bounce.irradiance[j] / double(points.size());
    }
    json out = {{"vpls", vpls.vpls.size()},
                {"photons", vpls.photons},
                {"emitted_w", {vpls.emitted.x, vpls.emitted.y, vpls.emitted.z}},
                {"trace_ms", vpls.ms},
                {"ms", bounce.stats.ms},
                {"clamp_loss", gl ? json(nullptr) : json(bounce.clampLoss)},
                {"mean", {mean.x, mean.y, mean.z}}};
    if (args.gatherSamples > 0) {
        const auto gatherStart = std::chrono::steady_clock::now();
        const std::vector<glm::dvec3> gathered = gatheredIndirect(lighting, lights, points, args.gatherSamples, indirect);
        double squared = 0.0, reference = 0.0;
        for (std::size_t j = 0; j < points.size(); ++j)
            for (int c = 0; c < 3; ++c) {
                const double d = bounce.irradiance[j][c] - gathered[j][c];
                squared += d * d;
                reference += gathered[j][c];
            }
        const double rmse = std::sqrt(squared / double(3 * points.size()));
        const double meanReference = reference / double(3 * points.size());
        out["reference"] = {{"samples", args.gatherSamples},
                            {"ms", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - gatherStart).count()},
                            {"rmse", rmse},
                            {"relative_rmse", meanReference > 0.0 ? rmse / meanReference : 0.0},
                            {"mean", meanReference}};
    }
    return out;
}

/// A designer dragging one light (lighting/LightingCache.h): the first point or spot light moves
/// 5 cm along x a frame and each frame refreshes it alone; the last frame is checked against the
/// reference (the largest relative difference, which float fields bound at about 1e-7).
json timeDrag(const LightingScene& lighting, const std::vector<Light>& lights, const std::vector<ShadingPoint>& points,
              const LightsArgs& args)
{
    const auto dragged = std::find_if(lights.begin(), lights.end(), [](const Light& l) {
        return l.type == LightType::Point || l.type == LightType::Spot;
    });
    if (dragged == lights.end())
        throw Error("--drag needs a point or spot light to drag");
    const std::size_t index = std::size_t(dragged - lights.begin());
    LightingCache cache(points, lights);
    const auto fullStart = std::chrono::steady_clock::now();
    while (!cache.update(lighting, ~std::uint64_t(0), args.threads).exact) {
    }
    const double fullMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - fullStart).count();
    std::vector<Light> moved = lights;
    std::vector<double> times;
    for (int f = 0; f < args.drag; ++f) {
        moved[index].position.x += 0.05;
        cache.setLight(index, moved[index]);
        times.push_back(cache.update(lighting, 1, args.threads).ms);
    }
    const std::vector<glm::dvec3> reference = directIrradiance(lighting, moved, points, {.path = LightingPath::Reference, .threads = args.threads});
    double worst = 0.0;
    for (std::size_t j = 0; j < points.size(); ++j)
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(cache.irradiance()[j][c] - reference[j][c]) /
                                        std::max({std::abs(reference[j][c]), std::abs(cache.irradiance()[j][c]), 1e-12}));
    std::vector<double> sorted = times;
    std::sort(sorted.begin(), sorted.end());
    return {{"frames", args.drag},
            {"light", displayName(lights, index)},
            {"full_ms", fullMs},
            {"median_ms", sorted[sorted.size() / 2]},
            {"max_ms", sorted.back()},
            {"max_relative_difference", worst},
            {"exact", worst < 1e-5}};
}

/// The GL path (lighting/GlDirectLight.h) on a headless context; with --compare, the exact fast
/// path in the same run and the agreement pair by pair (the exact bits by the reference's segment
/// test) and point by point. `stats` gets the counts the JSON shares with the other paths.
std::vector<glm::dvec3> glIrradiance(GlDirectLight& gl, const std::string& renderer, const LightingScene& lighting,
                                     const std::vector<Light>& lights, const std::vector<ShadingPoint>& points,
                                     const LightsArgs& args, json& glJson, json& comparison, DirectLightStats& stats)
{
    GlDirectLightStats glStats;
    // One light at a few points first: the driver compiles the shaders' pipelines on first use.
    gl.irradiance({Light{}}, std::span(points.data(), std::min<std::size_t>(points.size(), 64)));
    // Barczak's occlusion pyramid: the proved tile classes, on the CPU, counted in the GL time.
    std::optional<TileClasses> classes;
    if (!args.glNoPyramid)
        classes = classifyTiles(lighting, lights, points, args.threads);
    const double classifyMs = classes ? classes->ms : 0.0;
    const TileClasses* pyramid = classes ? &*classes : nullptr;
    EmitterBits bits;
    std::vector<glm::dvec3> irradiance = gl.irradiance(lights, points, &glStats, args.compare ? &bits : nullptr, pyramid);
    if (args.compare)   // the bits were asked for: time the answer alone again, as a user gets it
        gl.irradiance(lights, points, &glStats, nullptr, pyramid);
    stats.lights = glStats.lights;
    stats.lightSamples = glStats.emitters;
    stats.points = glStats.points;
    stats.ms = glStats.ms + classifyMs;
    glJson = {{"renderer", renderer},
              {"backend", args.glBackend},
              {"resolution", args.glResolution},
              {"pyramid", pyramid != nullptr},
              {"classify_ms", classifyMs},
              {"maps", glStats.maps},
              {"batches", glStats.batches},
              {"render_ms", glStats.renderMs},
              {"shade_ms", glStats.shadeMs}};
    if (!args.compare)
        return irradiance;
    DirectLightStats exactStats;
    const std::vector<glm::dvec3> exact =
        directIrradiance(lighting, lights, points, {.path = LightingPath::Fast, .threads = args.threads}, &exactStats);
    const ShadowAgreement agreement = compareEmitterBits(lights, points, bits, exactEmitterBits(lighting, lights, points, args.threads));
    std::size_t within = 0;
    double sum = 0.0;
    for (std::size_t j = 0; j < points.size(); ++j) {
        double here = 0.0;
        for (int c = 0; c < 3; ++c)
            here = std::max(here, std::abs(irradiance[j][c] - exact[j][c]) / std::max({exact[j][c], irradiance[j][c], 1e-12}));
        within += here <= 0.01;
        sum += here;
    }
    comparison = {{"fast_ms", exactStats.ms},
                  {"gl_ms", stats.ms},
                  {"speedup", stats.ms > 0.0 ? exactStats.ms / stats.ms : 0.0},
                  {"pairs", agreement.pairs},
                  {"pairs_differing", agreement.differing()},
                  {"false_lit", agreement.falseLit},
                  {"false_shadowed", agreement.falseShadowed},
                  {"points_within_1pct", points.empty() ? 1.0 : double(within) / double(points.size())},
                  {"mean_relative_difference", points.empty() ? 0.0 : sum / double(points.size())}};
    return irradiance;
}

} // namespace

CLI::App* addLightsCommand(CLI::App& app, LightsArgs& args)
{
    CLI::App* command = app.add_subcommand(
        "lights", "Direct irradiance (W/m² per colour channel) from the project's \"lights\", shadowed exactly, at "
                  "--points or over the receiver patch's samples (docs/lights.md)");
    command->add_option("project", args.project, "Project file (JSON) with a \"lights\" list")->required();
    command->add_option("--points", args.points,
                        "float32 .npy of shape (N, 6): rows x, y, z, nx, ny, nz (normals are normalised; lift "
                        "surface points off their surface). Default: the receiver patch's samples, with its normal");
    command->add_option("--npy", args.npy, "Write the irradiance as float32 .npy: (N, 3) with --points, else (nb, na, 3)")
        ->check(outputFile());
    command->add_flag("--json", args.json, "Print one JSON object instead of text");
    command->add_flag("--reference", args.reference,
                      "Brute force: every light sample at every point by exact ray casting (the fast path answers the "
                      "same sum, with area lights facing the receiver by the bitmask sampler)");
    command->add_flag("--compare", args.compare,
                      "Also run the other path in the same run: its time, the speed-up and the largest difference");
    command->add_flag("--gl", args.gl,
                      "The GL path (Barczak's octahedral shadow maps, one per light sample; a tolerance of about a "
                      "texel, not exact): with --compare, its time against the exact fast path and how many "
                      "(point, light sample) pairs differ from the exact answer");
    command->add_option("--gl-backend", args.glBackend, "--gl: osmesa (software) or egl (GPU)")
        ->check(CLI::IsMember({"osmesa", "egl"}))
        ->capture_default_str();
    command->add_option("--gl-resolution", args.glResolution, "--gl: each shadow map's side in texels")
        ->check(CLI::Range(16, 8192))
        ->capture_default_str();
    command->add_flag("--gl-no-pyramid", args.glNoPyramid,
                      "--gl: read a shadow map for every pair, without the occlusion pyramid's proved tile classes "
                      "(out of reach, shadowed, lit) that settle most pairs and spare the maps of lights they settle");
    command->add_option("--light-cut", args.lightCut,
                        "Point lights through a light tree's cut per tile of points (Lightcuts): a cluster whose bound "
                        "on any point is below ERROR times the tile's estimated total is shaded by one representative "
                        "(approximate; --compare gives its error against the exact reference)")
        ->check(CLI::Range(1e-6, 1.0));
    command->add_flag("--bitmask-area", args.bitmaskArea,
                      "Without --points: area lights facing the receiver by the exact bitmask sampler (Eisemann & "
                      "Décoret §8) instead of tiles of rays");
    command->add_option("--indirect", args.vpls,
                        "Add one bounce of indirect light from N virtual point lights (instant radiosity; "
                        "output beyond the contract: direct + indirect)")
        ->check(CLI::Range(1, 1000000));
    command->add_option("--seed", args.seed, "--indirect: the photons' seed")->capture_default_str();
    command->add_option("--albedo", args.albedo, "--indirect: the diffuse reflectance of surfaces without a material's base colour, in [0, 1)")
        ->capture_default_str();
    command->add_option("--clamp", args.clamp, "--indirect: VPL distances below this count as this (metres; 0: none)")
        ->capture_default_str();
    command->add_option("--indirect-reference", args.gatherSamples,
                        "--indirect: also gather the bounce by Monte Carlo with N directions a point, and report "
                        "the VPLs' error against it")
        ->check(CLI::Range(1, 100000));
    command->add_option("--texel", args.texel,
                        "Bake a light map instead of --points: the irradiance at DENSITY texels a metre over every "
                        "surface, on charts of connected coplanar faces (--npy: the atlas, shape (H, W, 3), NaN "
                        "where no texel; DENSITY in (0, 1000])");
    command->add_option("--lightmap", args.lightmap, "--texel: the atlas as a PNG (the 99th percentile white; texels dilated 8 pixels into the gutters, for mip maps)")->check(outputFile());
    command->add_option("--gltf", args.gltf, "--texel: the level as glTF with TEXCOORD_1, the --lightmap PNG as its emissive map and its point, spot and directional lights (KHR_lights_punctual)")
        ->check(outputFile());
    command->add_option("--drag", args.drag,
                        "Also time N frames of a designer dragging the first point or spot light 5 cm a frame, each "
                        "frame refreshing that light alone (amortised updates), and check the last against the "
                        "reference")
        ->check(CLI::Range(1, 10000));
    command->add_flag("--sets", args.sets,
                      "Print O'Rorke's light visibility sets instead: per light V (instances seen from the project's "
                      "camera), L (those it reaches), I = V and L, S (those casting shadows onto I); instance indices "
                      "as in info --json");
    command->add_option("--pvs", args.pvs,
                        "--sets: a PVS baked from this project (.pvs or .pvs.json) serves V (the row of the camera's "
                        "cell) and bounds each light's L by the rows of the cells it stands in");
    command->add_option("--threads", args.threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
    addAllowOutsidePaths(command, args.allowOutsidePaths);
    return command;
}

namespace {

/// O'Rorke's V: the instances seen from the project's camera (its saved editor view, else the
/// editor's view across the shaft) in a 640 x 360 view.
std::vector<std::uint32_t> cameraVisibleInstances(const Project& project, const LightingScene& lighting)
{
    const json editor = project.extra.value("editor", json::object());
    return ui::visibleInstances(ui::projectView(editor, project.source, project.receiver), lighting);
}

int printSets(const LightsArgs& args, const Project& project, const std::vector<Light>& lights)
{
    std::vector<std::string> warnings;
    const Scene scene = buildScene(project, &warnings);
    printWarnings(warnings);
    const LightingScene lighting(scene);
    LightSetOptions options;
    options.threads = args.threads;
    // With a bake, V is the camera cell's row and each light's L is sampled only over the rows of
    // the cells it stands in (O'Rorke's sets served by the PVS).
    std::vector<std::uint32_t> V;
    json served = nullptr;
    if (!args.pvs.empty()) {
        const pvs::PvsData baked = ui::readBakedPvs(args.pvs, project, scene);
        const json editor = project.extra.value("editor", json::object());
        const glm::dvec3 eye = ui::projectView(editor, project.source, project.receiver).eye();
        const std::optional<std::size_t> cameraCell = pvs::cellAt(baked.cells, eye);
        if (cameraCell)
            V = pvs::instancesVisibleFrom(baked.rows, baked.objects, *cameraCell);
        else
            std::cerr << "sightline-cli: note: the camera stands in none of " << args.pvs
                      << "'s cells; V is what it sees (rendered)\n";
        options.restricted.assign(lights.size(), false);
        options.candidates.assign(lights.size(), {});
        std::size_t lightsServed = 0;
        for (std::size_t l = 0; l < lights.size(); ++l)
            if (std::optional<std::vector<std::uint32_t>> reach = pvsReach(baked.cells, baked.rows, baked.objects, lights[l])) {
                options.candidates[l] = std::move(*reach);
                options.restricted[l] = true;
                ++lightsServed;
            }
        served = {{"file", args.pvs}, {"camera_cell", cameraCell ? json(*cameraCell) : json(nullptr)}, {"lights_served", lightsServed}};
        if (!cameraCell)
            V = cameraVisibleInstances(project, lighting);
    } else {
        V = cameraVisibleInstances(project, lighting);
    }
    const std::vector<LightSets> sets = lightSets(lighting, scene, lights, V, options);
    json list = json::array();
    for (std::size_t l = 0; l < sets.size(); ++l)
        list.push_back({{"light", displayName(lights, l)}, {"V", sets[l].V}, {"L", sets[l].L}, {"I", sets[l].I}, {"S", sets[l].S}});
    if (args.json) {
        json out = {{"sets", list}};
        if (!served.is_null())
            out["pvs"] = served;
        std::cout << out.dump() << "\n";
        return 0;
    }
    std::printf("%-24s %6s %6s %6s %6s\n", "light", "V", "L", "I", "S");
    for (std::size_t l = 0; l < sets.size(); ++l)
        std::printf("%-24s %6zu %6zu %6zu %6zu\n", displayName(lights, l).c_str(), sets[l].V.size(), sets[l].L.size(),
                    sets[l].I.size(), sets[l].S.size());
    return 0;
}

} // namespace

void checkLightsOptions(const CLI::App& command, const LightsArgs& args)
{
    if (given(command, "--texel"))
        checkTexelDensity(args.texel);   // before the mode is chosen by it: NaN is not "no --texel"
    if (args.texel <= 0.0) {
        for (const char* option : {"--lightmap", "--gltf"})
            if (given(command, option))
                throw Error(std::string(option) + " needs --texel DENSITY (a light map to write)");
    } else {
        for (const char* option : {"--points", "--bitmask-area"})
            if (given(command, option))
                throw Error(std::string(option) + " does not apply to --texel (the points are the light map's texels)");
        if (given(command, "--gltf") && !given(command, "--lightmap"))
            throw Error("--gltf needs --lightmap PNG (the image the glTF refers to)");
    }
    if (!args.gl) {
        for (const char* option : {"--gl-backend", "--gl-resolution", "--gl-no-pyramid"})
            if (given(command, option))
                throw Error(std::string(option) + " needs --gl (the GL path)");
    } else {
        for (const char* option : {"--reference", "--bitmask-area", "--drag", "--sets", "--light-cut"})
            if (given(command, option))
                throw Error(std::string(option) + " does not apply to --gl (it answers direct light by shadow maps)");
    }
    if (args.sets)
        for (const char* option : {"--points", "--npy", "--reference", "--compare", "--bitmask-area", "--indirect", "--texel"})
            if (given(command, option))
                throw Error(std::string(option) + " does not apply to --sets (it prints the sets, no irradiance)");
    if (args.reference && given(command, "--light-cut"))
        throw Error("--light-cut does not apply to --reference (the brute force sums every light exactly)");
    if (given(command, "--pvs") && !args.sets)
        throw Error("--pvs needs --sets (it serves O'Rorke's V and L)");
    if (args.vpls > 0)
        return;
    for (const char* option : {"--seed", "--albedo", "--clamp", "--indirect-reference"})
        if (given(command, option))
            throw Error(std::string(option) + " needs --indirect N (the VPL count)");
}

namespace {

/// What one run computed, for its report.
struct LightsRun {
    std::vector<Light> lights;
    std::vector<ShadingPoint> points;
    std::optional<TexelBake> bake;
    bool onReceiver = false;
    DirectLightStats stats;
    double setupMs = 0.0, totalMs = 0.0;
    std::size_t triangles = 0;
    glm::dvec3 mean{0.0}, peak{0.0};
    json glJson, comparison, indirectJson, dragJson, texelJson;
};

/// The first call in a process pays one-time costs (the thread pool's start, first touches of the
/// acceleration structures and of buffers sized by the light samples): a small call with every
/// light pays them before anything is timed, so that each path's time is what a warm editor or a
/// second call sees. Small: at most 256 points and about a million (point, light sample) terms, so
/// the warm-up never rivals the run it warms, even for a light of a million samples.
void warmUp(const LightingScene& lighting, const std::vector<Light>& lights, const std::vector<ShadingPoint>& points,
            const DirectLightOptions& options)
{
    std::size_t samples = 0;
    for (const Light& light : lights)
        samples += std::size_t(light.sampleCount());
    const std::size_t count = std::min({points.size(), std::size_t(256), std::max<std::size_t>(1, 1000000 / std::max<std::size_t>(1, samples))});
    directIrradiance(lighting, lights, std::span<const ShadingPoint>(points.data(), count), options);
}

/// Where the irradiance is computed: light-map texels (--texel), the receiver's samples, or the
/// points of --points.
void choosePoints(const LightsArgs& args, const Project& project, const Scene& scene, LightsRun& run)
{
    run.onReceiver = args.points.empty() && args.texel <= 0.0;
    if (args.texel > 0.0) {
        run.bake = texelBake(scene, args.texel);
        run.points = run.bake->points;
    } else if (run.onReceiver) {
        validatePatch(project.receiver, "receiver");
        run.points = patchShadingPoints(project.receiver);
    } else {
        run.points = readPoints(args.points);
    }
}

/// --compare without --gl: the other exact path on the same points, its time and how far apart;
/// and the brute force a user would write with Embree alone (float rays, not exact): its time and
/// how many points it gets wrong against the reference.
json compareExactPaths(const LightsArgs& args, const LightingScene& lighting, const LightsRun& run,
                       const DirectLightOptions& options, const std::vector<glm::dvec3>& irradiance)
{
    DirectLightOptions other = options;
    other.path = args.reference ? LightingPath::Fast : LightingPath::Reference;
    DirectLightStats otherStats;
    const std::vector<glm::dvec3> second = directIrradiance(lighting, run.lights, run.points, other, &otherStats);
    std::size_t differing = 0;
    const double worst = largestRelativeDifference(irradiance, second, &differing);
    const double fastMs = args.reference ? otherStats.ms : run.stats.ms, referenceMs = args.reference ? run.stats.ms : otherStats.ms;
    // The float baseline, warmed as the exact paths were: its scene built (a first small call
    // need not cast a ray), then a first small call.
    const DirectLightOptions user{.path = LightingPath::EmbreeFloat, .threads = args.threads};
    lighting.floatRays();
    warmUp(lighting, run.lights, run.points, user);
    DirectLightStats userStats;
    const std::vector<glm::dvec3> floatAnswer = directIrradiance(lighting, run.lights, run.points, user, &userStats);
    std::size_t floatDiffering = 0;
    largestRelativeDifference(floatAnswer, args.reference ? irradiance : second, &floatDiffering);
    json out = {{"reference_ms", referenceMs},
                {"fast_ms", fastMs},
                {"speedup", fastMs > 0.0 ? referenceMs / fastMs : 0.0},
                {"max_relative_difference", worst},
                {"points_differing", differing},
                {"embree_float_ms", userStats.ms},
                {"speedup_over_embree_float", fastMs > 0.0 ? userStats.ms / fastMs : 0.0},
                {"embree_float_points_differing", floatDiffering}};
    if (args.lightCut > 0.0)
        out["light_cut"] = lightCutError(args.reference ? second : irradiance, args.reference ? irradiance : second);
    return out;
}

/// The irradiance as .npy or light-map outputs, and its mean and peak.
void writeIrradiance(const LightsArgs& args, const Project& project, const std::vector<glm::dvec3>& total, LightsRun& run)
{
    std::vector<float> values(3 * total.size());
    for (std::size_t j = 0; j < total.size(); ++j) {
        for (int c = 0; c < 3; ++c) {
            // Finite lights can still sum past what the float32 outputs hold (an intensity of 1e300).
            if (!(std::abs(total[j][c]) <= double(std::numeric_limits<float>::max()))) {
                char value[32];
                std::snprintf(value, sizeof value, "%.3g", total[j][c]);
                throw Error("the irradiance at point " + std::to_string(j) + " (" + value +
                            " W/m²) is beyond float32's range of the outputs: lower the lights' intensities or radiances");
            }
            values[3 * j + std::size_t(c)] = float(total[j][c]);
        }
        run.mean += total[j];
        run.peak = glm::max(run.peak, total[j]);
    }
    if (!total.empty())
        run.mean /= double(total.size());
    if (run.bake) {
        run.texelJson = writeTexelOutputs(args, *run.bake, total, run.lights);
    } else if (!args.npy.empty()) {
        const std::vector<std::size_t> shape = run.onReceiver
                                                   ? std::vector<std::size_t>{std::size_t(project.receiver.nb), std::size_t(project.receiver.na), 3}
                                                   : std::vector<std::size_t>{run.points.size(), 3};
        writeFloatNpy(values, shape, args.npy);
    }
}

json lightsRunJson(const LightsArgs& args, const LightsRun& run)
{
    const DirectLightStats& stats = run.stats;
    const glm::dvec3 mean = run.mean, peak = run.peak;
    json out = {{"lights", stats.lights},
                {"light_samples", stats.lightSamples},
                {"points", stats.points},
                {"path", args.gl ? "gl" : args.reference ? "reference" : "fast"},
                {"ms", stats.ms},
                {"setup_ms", run.setupMs},
                {"total_ms", run.totalMs},
                {"terms", stats.terms},
                {"segments_cast", stats.segmentsCast},
                {"tiles_unreached", stats.tilesUnreached},
                {"tiles_proven_shadowed", stats.tilesProvenShadowed},
                {"tiles_proven_lit", stats.tilesProvenLit},
                {"tiles_cast", stats.tilesCast},
                {"bitmask_lights", stats.bitmaskLights},
                {"bitmask_rays", stats.bitmaskRays},
                {"cut_clusters", stats.cutClusters},
                {"cut_lights", stats.cutLights},
                {"triangles", run.triangles},
                {"irradiance_mean", {mean.x, mean.y, mean.z}},
                {"irradiance_max", {peak.x, peak.y, peak.z}}};
    if (args.compare)
        out["compare"] = run.comparison;
    if (args.gl)
        out["gl"] = run.glJson;
    if (args.vpls > 0)
        out["indirect"] = run.indirectJson;
    if (run.bake)
        out["texel"] = run.texelJson;
    if (args.drag > 0)
        out["drag"] = run.dragJson;
    return out;
}

void printLightsRun(const LightsArgs& args, const Project& project, const LightsRun& run)
{
    const DirectLightStats& stats = run.stats;
    const std::vector<Light>& lights = run.lights;
    const std::vector<ShadingPoint>& points = run.points;
    const std::optional<TexelBake>& bake = run.bake;
    const bool onReceiver = run.onReceiver;
    const json &glJson = run.glJson, &comparison = run.comparison, &indirectJson = run.indirectJson, &dragJson = run.dragJson;
    const glm::dvec3 mean = run.mean, peak = run.peak;
    const double setupMs = run.setupMs;
    std::printf("lights     %zu (%s), %zu light samples\n", lights.size(), lightSummary(lights).c_str(), stats.lightSamples);
    if (bake)
        std::printf("points     %zu light-map texels (%zu charts, a %dx%d atlas at %g texels a metre)\n", points.size(),
                    bake->layout.charts.size(), bake->layout.width, bake->layout.height, args.texel);
    else if (onReceiver)
        std::printf("points     %zu (the receiver's %dx%d samples)\n", points.size(), project.receiver.na, project.receiver.nb);
    else
        std::printf("points     %zu (%s)\n", points.size(), args.points.c_str());
    if (args.gl)
        std::printf("path       gl (%s): tiles classified in %.1f ms, %zu octahedral shadow maps of %d^2 in %zu batches, "
                    "drawn in %.1f ms, shaded in %.1f ms\n",
                    glJson["renderer"].get<std::string>().c_str(), glJson["classify_ms"].get<double>(),
                    glJson["maps"].get<std::size_t>(), args.glResolution, glJson["batches"].get<std::size_t>(),
                    glJson["render_ms"].get<double>(), glJson["shade_ms"].get<double>());
    else
        std::printf("path       %s: %llu of %llu shadow segments cast; (tile, light) pairs: %llu out of reach, %llu shadowed "
                    "by one triangle or coplanar region, %llu lit through an empty shaft, %llu cast; %zu area lights by the bitmask\n",
                    args.reference ? "reference" : "fast", (unsigned long long)stats.segmentsCast, (unsigned long long)stats.terms,
                    (unsigned long long)stats.tilesUnreached, (unsigned long long)stats.tilesProvenShadowed,
                    (unsigned long long)stats.tilesProvenLit, (unsigned long long)stats.tilesCast, stats.bitmaskLights);
    std::printf("irradiance mean (%.6g, %.6g, %.6g), max (%.6g, %.6g, %.6g) W/m²\n", mean.x, mean.y, mean.z, peak.x, peak.y, peak.z);
    std::printf("time       %.2f ms (scene setup %.1f ms, %zu triangles)\n", stats.ms, setupMs, run.triangles);
    if (args.vpls > 0) {
        std::printf("indirect   %zu VPLs from %d photons (%.1f ms) in %.1f ms%s", indirectJson["vpls"].get<std::size_t>(),
                    indirectJson["photons"].get<int>(), indirectJson["trace_ms"].get<double>(), indirectJson["ms"].get<double>(),
                    args.gl ? " by shadow maps"
                            : (", clamp loss " + std::to_string(100.0 * indirectJson["clamp_loss"].get<double>()) + "%").c_str());
        if (indirectJson.contains("reference"))
            std::printf("; against %d-direction gathering: relative RMSE %.3g", args.gatherSamples,
                        indirectJson["reference"]["relative_rmse"].get<double>());
        std::printf("\n");
    }
    if (args.drag > 0)
        std::printf("drag       %d frames of one light: median %.2f ms, slowest %.2f ms a frame (%.1f Hz); exact at the end: %s\n",
                    args.drag, dragJson["median_ms"].get<double>(), dragJson["max_ms"].get<double>(),
                    1000.0 / std::max(dragJson["median_ms"].get<double>(), 1e-9), dragJson["exact"].get<bool>() ? "yes" : "NO");
    if (args.compare && args.gl)
        std::printf("compare    exact fast path %.2f ms, gl %.2f ms: %.2fx; %llu of %llu (point, light sample) pairs differ "
                    "(%llu lit that are shadowed, %llu shadowed that are lit); irradiance within 1%% at %.2f%% of "
                    "points, mean relative difference %.3g\n",
                    comparison["fast_ms"].get<double>(), comparison["gl_ms"].get<double>(), comparison["speedup"].get<double>(),
                    (unsigned long long)comparison["pairs_differing"].get<std::uint64_t>(),
                    (unsigned long long)comparison["pairs"].get<std::uint64_t>(),
                    (unsigned long long)comparison["false_lit"].get<std::uint64_t>(),
                    (unsigned long long)comparison["false_shadowed"].get<std::uint64_t>(),
                    100.0 * comparison["points_within_1pct"].get<double>(), comparison["mean_relative_difference"].get<double>());
    else if (args.compare)
        std::printf("compare    reference %.2f ms, fast %.2f ms: %.2fx; largest relative difference %.3g, %zu points differ; "
                    "Embree's float rays alone %.2f ms (%.2fx the fast path's time), %zu points off the reference\n",
                    comparison["reference_ms"].get<double>(), comparison["fast_ms"].get<double>(),
                    comparison["speedup"].get<double>(), comparison["max_relative_difference"].get<double>(),
                    comparison["points_differing"].get<std::size_t>(), comparison["embree_float_ms"].get<double>(),
                    comparison["speedup_over_embree_float"].get<double>(), comparison["embree_float_points_differing"].get<std::size_t>());
}

} // namespace

int runLights(const LightsArgs& args)
{
    const auto start = std::chrono::steady_clock::now();
    // Albedos are read by the bounce alone: textures decoded only for it.
    const Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths, .textureAlbedos = args.vpls > 0});
    const std::string what = std::filesystem::path(args.project).filename().string();
    LightsRun run;
    bool fromScene = false;
    run.lights = lightsToUse(project, &fromScene);
    const std::vector<Light>& lights = run.lights;
    if (fromScene && !lights.empty())
        std::cerr << "sightline-cli: note: " << what << " has no \"lights\"; using the " << lights.size()
                  << " KHR_lights_punctual lights of its scene file\n";
    if (args.sets)
        return printSets(args, project, lights);
    if (args.vpls > 0)
        validateIndirectOptions({.vpls = args.vpls, .seed = args.seed, .albedo = args.albedo, .clampMetres = args.clamp});
    std::vector<FileRole> inputs = projectInputs(args.project, project);
    if (!args.points.empty())
        inputs.push_back({"--points", args.points});
    checkOutputs({{"--npy", args.npy}, {"--lightmap", args.lightmap}, {"--gltf", args.gltf}}, inputs);

    std::vector<std::string> warnings;
    const Scene scene = buildScene(project, &warnings);
    printWarnings(warnings);
    run.triangles = scene.triangleCount();
    choosePoints(args, project, scene, run);
    const std::vector<ShadingPoint>& points = run.points;
    std::size_t lightSamples = 0;
    for (const Light& light : lights)
        lightSamples += std::size_t(light.sampleCount());
    if (double(points.size()) * double(lightSamples) > kMaxTerms)
        throw Error(what + ": " + std::to_string(points.size()) + " points x " + std::to_string(lightSamples) +
                    " light samples is more than " + std::to_string(std::uint64_t(kMaxTerms)) +
                    " shadow rays; use fewer points or coarser area lights");
    if (lights.empty())
        std::cerr << "sightline-cli: warning: " << what << " has no \"lights\" (nor its scene file); every irradiance is 0\n";

    const auto setupStart = std::chrono::steady_clock::now();
    const LightingScene lighting(scene);
    run.setupMs = millisecondsSince(setupStart);

    DirectLightOptions options;
    options.path = args.reference ? LightingPath::Reference : LightingPath::Fast;
    options.threads = args.threads;
    options.receiverGrid = run.onReceiver ? &project.receiver : nullptr;
    options.bitmaskAreaLights = args.bitmaskArea;
    options.lightCutError = args.lightCut;
    std::unique_ptr<gl::HeadlessContext> glContext;
    std::unique_ptr<GlDirectLight> glPath;
    if (args.gl) {
        glContext = gl::HeadlessContext::create(gl::parseBackend(args.glBackend));
        glPath = std::make_unique<GlDirectLight>(glContext->functions(), lighting.triangles(),
                                                 GlDirectLightOptions{.resolution = args.glResolution});
    }
    warmUp(lighting, lights, points, DirectLightOptions{.threads = args.threads});   // --compare times both paths alike
    const std::vector<glm::dvec3> irradiance =
        args.gl ? glIrradiance(*glPath, glContext->renderer(), lighting, lights, points, args, run.glJson, run.comparison, run.stats)
                : directIrradiance(lighting, lights, points, options, &run.stats);
    if (args.compare && !args.gl)
        run.comparison = compareExactPaths(args, lighting, run, options, irradiance);
    std::vector<glm::dvec3> total = irradiance;
    if (args.vpls > 0)
        run.indirectJson = addIndirectBounce(lighting, lights, points, args, total, glPath.get());
    if (args.drag > 0)
        run.dragJson = timeDrag(lighting, lights, points, args);
    writeIrradiance(args, project, total, run);
    run.totalMs = millisecondsSince(start);
    if (args.json)
        std::cout << lightsRunJson(args, run).dump() << "\n";
    else
        printLightsRun(args, project, run);
    return 0;
}

} // namespace sightline::cli
