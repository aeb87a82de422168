#pragma once
// The editor's ambient-occlusion preview: the level's AO in light-map texels
// (Sattler et al. 2004's visibility matrix over texel points, lighting/ao/AoTexels.h, so a room
// gets contact shadows in its corners, which per-vertex AO on large wall faces would miss),
// computed progressively on a worker thread: k = 6 arrives at once, then 18, 66 and 258, each
// level reusing the bits of the one before (AoComputation). A new start() cancels the running
// one. Plain C++ (no Qt): the caller decides how an answer reaches its thread.

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "editor/RestartingWorker.h"
#include "lighting/ao/AoEnvironment.h"
#include "visibility/Scene.h"

namespace sightline::ui {

/// The preview's default reach: occluders within 2 m darken (corners, under furniture).
inline constexpr double kAoPreviewReach = 2.0;

/// How the AO is lit (Sattler et al. §4: lighting from the matrix without tracing again): a
/// uniform white sky (plain AO) or an HDR lat-long environment, turned about +Y and exposed.
struct AoLighting {
    std::shared_ptr<const AoEnvironment> environment;   ///< null: the uniform sky
    double rotationDegrees = 0.0;
    double exposureEv = 0.0;
};

struct AoPreviewLevel {
    std::uint64_t generation = 0;
    int k = 0, targetK = 0;
    /// Per world-triangle corner of the scene (worldTriangles order), its place in the map; -1
    /// for the triangles of instances that were not asked for (AoPreviewRequest::instances).
    std::vector<glm::vec2> uvs;
    int width = 0, height = 0;
    /// width x height lit colours, row 0 at the top (uv origin): AO in [0, 1] under the uniform
    /// sky, the environment's light reaching each texel otherwise.
    std::vector<glm::vec3> map;
    std::size_t texels = 0;   ///< sample points (texels inside tiles; the atlas has gutters too)
    double density = 0.0;     ///< texels per metre
    bool relit = false;       ///< a new lighting of the last level (no new directions traced)
    double ms = 0.0;          ///< since start(); for a relit level, the relighting's own time
    std::string error;        ///< non-empty: nothing else is set
};

/// What to compute: the AO of `scene`'s surfaces, every triangle of it occluding.
struct AoPreviewRequest {
    std::shared_ptr<const Scene> scene;
    /// Which instances get texels (AO of chosen objects); empty: all of them. The
    /// texel density is chosen for the surfaces asked for, so a chosen object gets finer texels.
    std::vector<std::uint32_t> instances;
    int targetK = 258;   ///< 6, 18, 66, 258 or 1026
    /// Occluders within this many metres darken (under a uniform sky a closed room is dark
    /// everywhere; engines' AO has a radius too).
    double reach = kAoPreviewReach;
};

class AoPreview {
public:
    using Deliver = std::function<void(AoPreviewLevel level)>;   ///< called on the worker thread
    explicit AoPreview(Deliver deliver);
    ~AoPreview();
    AoPreview(const AoPreview&) = delete;
    AoPreview& operator=(const AoPreview&) = delete;

    /// Cancels any running computation (without waiting for it) and starts `request` on a worker
    /// thread, which runs at a low scheduling priority so that the live rays and the frames keep
    /// their core.
    void start(std::uint64_t generation, AoPreviewRequest request);
    /// Cancels the running computation without waiting: a worker in its set-up (texel layout,
    /// binning; many frames' worth on a big level) notices between steps and ends on its
    /// own, so the GUI thread never blocks on it while a drag restarts the AO every frame. An
    /// answer already on its way may still arrive; callers drop it by its generation.
    void cancel();
    /// Cancels and waits for every worker.
    void stop();
    /// Lights the AO anew: levels from now on use it, and a finished computation is relit from
    /// its matrix at once (delivered with `relit`), without tracing.
    void setLighting(AoLighting lighting);

private:
    Deliver deliver_;
    std::mutex mutex_;
    std::condition_variable wake_;
    AoLighting lighting_;
    std::uint64_t lightingVersion_ = 0;
    RestartingWorker worker_{mutex_, wake_};   // last: its jobs use the above
};

/// The light-map texel density the preview uses for the triangles with these `corners` (three a
/// triangle): 4 texels a metre for a level (16 for chosen objects, `maxDensity`), lowered so the
/// atlas stays under about 400,000 texels (so that a k = 258 answer stays short enough for a
/// preview).
double previewTexelDensity(const std::vector<glm::vec3>& corners, double maxDensity = 4.0);

} // namespace sightline::ui
