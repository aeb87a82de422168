#pragma once
// sightline-cli coarse: what coarse occluders cost and save ("model no more than a scene needs").
// The level's dense meshes are replaced by coarse ones, the closest (OpenMesh's decimater,
// plugins/MeshSimplification.h) or the conservative (visibility/InnerOccluder.h), and the
// project's pair is sampled exactly with each: the triangles, the sampling times side by side and
// the rays the coarse level answers differently, each way. `--sweep` measures several triangle
// counts in one run (project/CoarseSweep.h) and `--chart` draws them; `--tolerance` finds the fewest
// triangles that answer at most a fraction of the rays differently; `--write` keeps the stand-ins
// in a copy of the project ("coarse_occluders", project/CoarseOccluders.h).

#include <string>

namespace CLI {
class App;
}

namespace sightline::cli {

struct CoarseArgs {
    std::string project;
    std::string kind = "closest";
    int triangles = 1000;     ///< closest: at most this many a mesh; meshes above it are simplified
    int resolution = 32;      ///< inner: voxels along a mesh's longest side
    int repeat = 3;
    int threads = 0;
    std::string sweep;        ///< comma-separated triangle counts, or "auto"; empty: one run
    double tolerance = -1.0;  ///< a fraction of the rays: the fewest triangles within it (negative: not given)
    std::string chart;        ///< PNG of the sweep
    std::string write;        ///< a copy of the project with the stand-ins kept
    bool json = false;
    bool allowOutsidePaths = false;
};

CLI::App* addCoarseCommand(CLI::App& app, CoarseArgs& args);
int runCoarse(const CoarseArgs& args);

} // namespace sightline::cli
