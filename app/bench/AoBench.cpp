// sightline-ao-bench: the ambient-occlusion figures of docs/ao.md, measured in one run.
//
//   sightline-ao-bench [MESH] [--mc RAYS] [--threads N] [--repeat N] [--texel M] [--cells C] [--no-gl]
//                      [--gl-backend osmesa|egl]
//   (AO_BENCH_CASTERS_ONLY=1 in the environment: only the CPU-vs-Embree rows)
//
// Prints, for the mesh (default: the Stanford bunny of tests/data): the exact CPU (binned) mode against
// Embree at k = 258 and 1026 (the faster of single rays and packets of 16 directions; same run,
// ratio), progressive times to k = 6 and 66,
// relight time at k = 258, RMSE against a Monte-Carlo reference per k (solid-angle weights and
// the paper's plain counting), the GL mode (OSMesa, or EGL on a GPU), and the demo level's texel mode.

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "lighting/ao/AoBinnedCaster.h"
#include "lighting/ao/AoComputation.h"
#include "lighting/ao/AoEmbree.h"
#include "lighting/ao/AoEnvironment.h"
#include "lighting/ao/AoShading.h"
#include "demo/DemoLevel.h"
#include "lighting/ao/AoGlCaster.h"
#include "lighting/ao/AoTexels.h"
#include "plugins/SceneFormats.h"
#include "visibility/gl/HeadlessContext.h"

using namespace sightline;

namespace {

double msSince(std::chrono::steady_clock::time_point t)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

/// Lower median of `repeat` timed runs of `f` (after none: the first run is cold on purpose only
/// when repeat is 1).
double timeMs(int repeat, const std::function<void()>& f)
{
    std::vector<double> t;
    for (int r = 0; r < repeat; ++r) {
        const auto start = std::chrono::steady_clock::now();
        f();
        t.push_back(msSince(start));
    }
    std::sort(t.begin(), t.end());
    return t[(t.size() - 1) / 2];
}

double rmse(const std::vector<float>& a, const std::vector<float>& b)
{
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!std::isnan(a[i]) && !std::isnan(b[i])) {
            sum += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
            ++n;
        }
    return n ? std::sqrt(sum / double(n)) : 0.0;
}


/// The command line: sightline-ao-bench [MESH] [--mc N] [--threads N] [--repeat N] [--texel D]
/// [--cells C] [--no-gl] [--gl-backend osmesa|egl].
struct AoBenchArgs {
    std::string mesh = std::string(SIGHTLINE_TEST_DATA) + "/meshes/bun_zipper.ply";
    int mcRays = 4096, threads = 0, repeat = 3;
    double texel = 4.0;
    double cellsPerTriangle = AoBinnedOptions{}.cellsPerTriangle;
    bool gl = true;
    gl::Backend glBackend = gl::Backend::OSMesa;
};

/// The arguments, or none after a one-line error on stderr.
std::optional<AoBenchArgs> parseArguments(int argc, char** argv)
{
    AoBenchArgs args;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--mc" && a + 1 < argc)
            args.mcRays = std::atoi(argv[++a]);
        else if (arg == "--threads" && a + 1 < argc)
            args.threads = std::atoi(argv[++a]);
        else if (arg == "--repeat" && a + 1 < argc)
            args.repeat = std::max(1, std::atoi(argv[++a]));
        else if (arg == "--texel" && a + 1 < argc)
            args.texel = std::atof(argv[++a]);
        else if (arg == "--cells" && a + 1 < argc)
            args.cellsPerTriangle = std::atof(argv[++a]);
        else if (arg == "--no-gl")
            args.gl = false;
        else if (arg == "--gl-backend" && a + 1 < argc) {
            const std::string name = argv[++a];
            if (name != "egl" && name != "osmesa") {
                std::fprintf(stderr, "error: --gl-backend takes osmesa or egl, not '%s'\n", name.c_str());
                return std::nullopt;
            }
            args.glBackend = name == "egl" ? gl::Backend::Egl : gl::Backend::OSMesa;
        }
        else if (arg[0] != '-')
            args.mesh = arg;
    }
    return args;
}

/// The binned caster against the best Embree traversal a user could pick, at k = 258 and 1026.
void benchCasters(const AoBenchArgs& args, const AoOccluders& occluders, const AoPoints& points,
                  AoBinnedCaster& binned)
{
    const int threads = args.threads, repeat = args.repeat;
    // The baseline: Embree tuned as a user would, the faster of single rays and packets of 16
    // directions from a point (same answers), chosen per k by their times in this run.
    AoEmbreeCaster singles(occluders, threads, AoEmbreeTraversal::SingleRays);
    AoEmbreeCaster packets(occluders, threads, AoEmbreeTraversal::DirectionPackets);
    for (int k : {258, 1026}) {
        VisibilityMatrix me, mb;
        const double ts = timeMs(repeat, [&] {
            me = VisibilityMatrix(points.size(), k);
            singles.fill(points, aoDirections(k), 0, k, me);
        });
        const double tp = timeMs(repeat, [&] {
            me = VisibilityMatrix(points.size(), k);
            packets.fill(points, aoDirections(k), 0, k, me);
        });
        AoEmbreeCaster& embree = tp < ts ? packets : singles;
        const double te = std::min(ts, tp);
        std::printf("k=%4d  embree single rays %8.1f ms, packets of 16 directions %8.1f ms: the baseline is %s\n", k, ts, tp,
                    embree.name().c_str());
        const double tb = timeMs(repeat, [&] {
            mb = VisibilityMatrix(points.size(), k);
            binned.fill(points, aoDirections(k), 0, k, mb);
        });
        std::uint64_t differ = 0;
        for (std::size_t i = 0; i < points.size(); ++i)
            for (int w = 0; w < mb.words(); ++w)
                differ += unsigned(std::popcount(mb.row(i)[w] ^ me.row(i)[w]));
        std::printf("k=%4d  embree (its best) %8.1f ms   cpu binned %8.1f ms   ratio %.2fx   bits differing %llu of %llu visible\n",
                    k, te, tb, te / tb, (unsigned long long)differ, (unsigned long long)me.visibleCount(k));
        // Processor time of the whole process (all threads) for one more run of each: less
        // sensitive than wall time to other work on a shared machine.
        const std::clock_t c0 = std::clock();
        embree.fill(points, aoDirections(k), 0, k, me);
        const std::clock_t c1 = std::clock();
        binned.fill(points, aoDirections(k), 0, k, mb);
        const std::clock_t c2 = std::clock();
        std::printf("        processor time: embree %.0f ms, cpu binned %.0f ms, ratio %.2fx\n", 1e3 * double(c1 - c0) / CLOCKS_PER_SEC,
                    1e3 * double(c2 - c1) / CLOCKS_PER_SEC, double(c1 - c0) / double(c2 - c1));
    }
}

/// The GL caster at k = 258 against the CPU's bits and the Monte-Carlo reference `mc`.
void benchGl(const AoBenchArgs& args, const AoOccluders& occluders, const AoPoints& points, const VisibilityMatrix& cpu,
             const std::vector<float>& mc)
{
    try {
        const auto context = gl::HeadlessContext::create(args.glBackend);
        // The default (occluders simplified within a quarter texel) and every triangle.
        for (const auto& [resolution, simplify] : {std::pair{1024, 0.25}, std::pair{1024, 0.0}, std::pair{2048, 0.25}}) {
            AoGlCaster caster(context->functions(), occluders, {.resolution = resolution, .simplifyTexels = simplify});
            VisibilityMatrix m;
            const double t = timeMs(1, [&] {
                m = VisibilityMatrix(points.size(), 258);
                caster.fill(points, aoDirections(258), 0, 258, m);
            });
            std::uint64_t differ = 0;
            for (std::size_t i = 0; i < points.size(); ++i)
                for (int w = 0; w < m.words(); ++w)
                    differ += unsigned(std::popcount((m.row(i)[w] ^ cpu.row(i)[w]) & (w == 4 ? 0x3ull : ~0ull)));
            std::printf("gl k=258 %dx%d, %zu triangles (within %.2f texel) (%s): %.0f ms, RMSE vs MC %.4f, bits "
                        "differing from cpu %llu\n",
                        resolution, resolution, caster.drawnTriangles(), simplify, context->renderer().c_str(), t,
                        rmse(ambientOcclusion(m, points, 258), mc), (unsigned long long)differ);
        }
    } catch (const std::exception& e) {
        std::printf("gl: skipped (%s)\n", e.what());
    }
}

/// Progressive refinement from scratch, relighting, accuracy against Monte Carlo and the GL caster.
void benchProgressive(const AoBenchArgs& args, const AoOccluders& occluders, const AoPoints& points,
                      AoBinnedCaster& binned)
{
    const int threads = args.threads, repeat = args.repeat, mcRays = args.mcRays;
    // Progressive: time to each level from scratch, each reusing the bits before (§3.4).
    AoComputation computation(binned, points, 1026);
    const auto start = std::chrono::steady_clock::now();
    std::printf("progressive (cpu binned, from scratch):");
    for (int k : kAoDirectionCounts) {
        computation.refineLevel();
        std::printf("  k=%d %.1f ms", k, msSince(start));
    }
    std::printf("\n");

    // Relight: an environment change (new rotation) at k = 258 for every vertex.
    std::vector<glm::vec3> sky(64 * 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x)
            sky[std::size_t(y * 64 + x)] = y < 16 ? glm::vec3(0.4f, 0.6f, 1.0f) * (1.0f + 4.0f * (x > 28 && x < 34 && y > 8))
                                                   : glm::vec3(0.2f, 0.15f, 0.1f);
    const AoEnvironment env = AoEnvironment::fromPixels(64, 32, sky);
    const auto buildStart = std::chrono::steady_clock::now();
    const AoRelighter relighter(computation.matrix(), points, 258);
    const double buildMs = msSince(buildStart);
    double degrees = 0.0;
    std::vector<glm::vec3> colours;
    const double relightMs = timeMs(std::max(repeat, 5), [&] {
        degrees += 10.0;
        colours = relighter.shade(env.directionRadiance(aoDirections(258), degrees, 0.0), threads);
    });
    std::printf("relight k=258: %.2f ms for %zu points (rotation + shading; relighter set-up once %.1f ms)\n", relightMs,
                points.size(), buildMs);

    // Accuracy against the Monte-Carlo reference, every level from the one nested matrix.
    const AoEmbreeScene reference(occluders);
    const auto mcStart = std::chrono::steady_clock::now();
    const std::vector<float> mc = monteCarloAo(reference, points, mcRays, 1, threads);
    std::printf("MC reference: %d cosine-weighted rays per point, %.0f ms\n", mcRays, msSince(mcStart));
    std::printf("RMSE vs MC:   k     solid-angle   plain count (the paper's)\n");
    for (int k : kAoDirectionCounts)
        std::printf("           %5d   %.4f        %.4f\n", k, rmse(ambientOcclusion(computation.matrix(), points, k), mc),
                    rmse(ambientOcclusion(computation.matrix(), points, k, AoWeighting::PlainCount), mc));

    if (args.gl)
        benchGl(args, occluders, points, computation.matrix(), mc);
}

/// The demo level's occluders and its light-map texels at `texel` a metre, offset off the surfaces.
struct DemoTexels {
    AoOccluders occluders;
    AoPoints points;
    AoTexelLayout layout;
};

DemoTexels demoTexels(double texel)
{
    DemoTexels out{aoOccluders(demo::makeDemoLevel()), {}, {}};
    out.layout = aoTexelPoints(out.occluders, texel, out.points);
    out.points.offsetOrigins(kAoOffsetRelative * out.occluders.diagonal());
    return out;
}

/// The demo level in texel mode: time to a first picture (k = 6) and to k = 258.
void benchDemoTexels(const AoBenchArgs& args)
{
    const int threads = args.threads;
    const double texel = args.texel;
    const auto start = std::chrono::steady_clock::now();
    DemoTexels level = demoTexels(texel);
    const AoOccluders& levelOccluders = level.occluders;
    AoPoints& texels = level.points;
    const AoTexelLayout& layout = level.layout;
    AoBinnedCaster levelCaster(levelOccluders, {.threads = threads});
    const double setupMs = msSince(start);
    AoComputation computation(levelCaster, texels, 258);
    computation.refineLevel();
    std::vector<float> first = ambientOcclusion(computation.matrix(), texels, 6);
    const double firstMs = msSince(start);
    computation.run();
    std::vector<float> full = ambientOcclusion(computation.matrix(), texels, 258);
    const double fullMs = msSince(start);
    std::printf("demo level texel mode: %zu triangles, %zu texels at %.1f/m (atlas %dx%d), set-up %.0f ms, first "
                "picture (k=6) %.0f ms, k=258 %.0f ms\n",
                levelOccluders.triangleCount(), texels.size(), texel, layout.width, layout.height, setupMs, firstMs, fullMs);
}

/// As the editor runs it (editor/AoPreview.h): one thread, occluders within 2 m, and the relighter an
/// environment change uses (its memory is the editor's largest AO cost).
void benchDemoAsTheEditor(const AoBenchArgs& args)
{
    const int repeat = args.repeat;
    const double texel = args.texel;
    const auto start = std::chrono::steady_clock::now();
    DemoTexels level = demoTexels(texel);
    const AoPoints& texels = level.points;
    AoBinnedCaster levelCaster(level.occluders, {.threads = 1, .maxDistance = 2.0});
    AoComputation computation(levelCaster, texels, 258);
    computation.refineLevel();
    const double firstMs = msSince(start);
    computation.run();
    const double fullMs = msSince(start);
    const auto relightStart = std::chrono::steady_clock::now();
    const AoRelighter relighter(computation.matrix(), texels, 258);
    const double setupMs = msSince(relightStart);
    const AoEnvironment env = AoEnvironment::fromPixels(2, 1, {glm::vec3(0.4f, 0.6f, 1.0f), glm::vec3(0.2f, 0.15f, 0.1f)});
    double degrees = 0.0;
    const double relightMs = timeMs(std::max(repeat, 3), [&] {
        degrees += 15.0;
        relighter.shade(env.directionRadiance(aoDirections(258), degrees, 0.0), 1);
    });
    std::printf("demo level as the editor (1 thread, 2 m reach): first picture (k=6) %.0f ms, k=258 %.0f ms; "
                "relighter set-up %.0f ms, %.1f MB for %llu visible bits, relight %.1f ms (1 thread)\n",
                firstMs, fullMs, setupMs, double(relighter.bytes()) / 1e6,
                (unsigned long long)computation.matrix().visibleCount(258), relightMs);
}

} // namespace

int main(int argc, char** argv)
{
    const std::optional<AoBenchArgs> args = parseArguments(argc, argv);
    if (!args)
        return 2;
    const Scene scene = loadScene(args->mesh);
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points = aoVertexPoints(scene);
    points.offsetOrigins(kAoOffsetRelative * occluders.diagonal());
    std::printf("mesh %s: %zu points (%zu of no face, %zu zero normals), %zu triangles, offset %.3g m\n", args->mesh.c_str(),
                points.size(), points.count(AoPointStatus::NoFace), points.count(AoPointStatus::ZeroNormal),
                occluders.triangleCount(), kAoOffsetRelative * occluders.diagonal());
    AoBinnedCaster binned(occluders, {.threads = args->threads, .cellsPerTriangle = args->cellsPerTriangle});
    benchCasters(*args, occluders, points, binned);
    if (std::getenv("AO_BENCH_CASTERS_ONLY"))
        return 0;
    benchProgressive(*args, occluders, points, binned);
    benchDemoTexels(*args);
    benchDemoAsTheEditor(*args);
    return 0;
}
