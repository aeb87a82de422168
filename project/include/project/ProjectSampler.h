#pragma once
// Samples a project's hidden-samples map frame after frame (an animation, or the editor's drags),
// keeping what does not change: the level's triangles, the CPU sampler's warm buffers, Embree's
// BVH while no occluder moves.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "project/Project.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/RayCastSampler.h"
#include "visibility/ReceiverHeights.h"

namespace sightline {

class GlBitmaskSampler;
namespace gl {
class HeadlessContext;
}

struct SamplerSettings {
    std::string method = "cpu";     ///< "cpu" (exact bitmask, auto strategy), "raycast" (Embree) or
                                    ///< "gl" (the paper's GPU pass in a headless context)
    /// "gl": makes the headless context the sampler runs in (current on the calling thread from
    /// then on). Passed in, so that the project model links no windowing system (OSMesa, EGL).
    std::function<std::unique_ptr<gl::HeadlessContext>()> glContext;
    int threads = 0;                ///< 0 = all cores
    SourceJitter jitter{};          ///< decorrelated source samples (§6.2)
    ReceiverHeights heights;        ///< a bumpy receiver (§8); empty = flat
};

class ProjectSampler {
public:
    /// Throws sightline::Error for an unknown method, or "gl" with heights or without a context
    /// factory (or whatever the factory throws).
    ProjectSampler(const Project& project, ProjectMeshes meshes, SamplerSettings settings);
    ~ProjectSampler();

    /// The map for `frame` (the project at some frame: moved patches and occluders, same occluder
    /// list). The scene is reassembled only when an occluder's transform differs from the last
    /// assembly's. Validates the pair; throws sightline::Error.
    HiddenSampleMap sample(const Project& frame);

    std::size_t triangleCount() const { return triangles_; }
    /// Milliseconds of the last sample() call spent sampling (scene updates excluded).
    double lastSampleMs() const { return lastMs_; }
    const SamplerSettings& settings() const { return settings_; }

private:
    void rebuild(const Project& frame);

    ProjectMeshes meshes_;
    SamplerSettings settings_;
    std::unique_ptr<CpuBitmaskSampler> cpu_;
    std::unique_ptr<RayCastScene> rayCaster_;
    std::unique_ptr<gl::HeadlessContext> context_;   ///< "gl": current on the calling thread
    std::unique_ptr<GlBitmaskSampler> gl_;
    std::vector<glm::mat4> builtTransforms_;   ///< the occluders' transforms of the last assembly
    std::size_t triangles_ = 0;
    double lastMs_ = 0.0;
};

} // namespace sightline
