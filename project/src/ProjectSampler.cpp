#include "project/ProjectSampler.h"

#include "project/CoarseOccluders.h"

#include <algorithm>
#include <chrono>

#include "base/Error.h"
#include "visibility/GlBitmaskSampler.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline {

ProjectSampler::ProjectSampler(const Project& project, ProjectMeshes meshes, SamplerSettings settings)
    : meshes_(std::move(meshes)), settings_(std::move(settings))
{
    if (settings_.method != "cpu" && settings_.method != "raycast" && settings_.method != "gl")
        throw Error("unknown method '" + settings_.method + "' (use cpu, raycast or gl)");
    if (settings_.method == "gl" && !settings_.heights.empty())
        throw Error("the GL sampler does not take receiver heights; use cpu or raycast for a bumpy receiver");
    if (settings_.method == "gl") {
        if (!settings_.glContext)
            throw Error("the GL sampler needs an OpenGL context, and none was provided");
        context_ = settings_.glContext();
    }
    applyCoarseOccluders(coarseOccluders(project), meshes_.level);
    rebuild(project);
}

ProjectSampler::~ProjectSampler() = default;

void ProjectSampler::rebuild(const Project& frame)
{
    builtTransforms_.clear();
    for (const OccluderSpec& spec : frame.occluders)
        builtTransforms_.push_back(spec.transform);
    const Scene scene = assembleScene(frame, meshes_);
    triangles_ = scene.triangleCount();
    if (settings_.method == "cpu") {
        if (cpu_)
            cpu_->setScene(scene);   // keeps the warm buffers
        else
            cpu_ = std::make_unique<CpuBitmaskSampler>(scene);
    } else if (settings_.method == "gl") {
        gl_.reset();   // before its replacement allocates: GPU memory
        gl_ = std::make_unique<GlBitmaskSampler>(context_->functions(), scene);
    } else {
        rayCaster_ = std::make_unique<RayCastScene>(scene);
    }
}

HiddenSampleMap ProjectSampler::sample(const Project& frame)
{
    const bool occludersMoved =
        frame.occluders.size() != builtTransforms_.size() ||
        !std::equal(frame.occluders.begin(), frame.occluders.end(), builtTransforms_.begin(),
                    [](const OccluderSpec& spec, const glm::mat4& built) { return spec.transform == built; });
    if (occludersMoved)
        rebuild(frame);
    const ReceiverHeights* heights = settings_.heights.empty() ? nullptr : &settings_.heights;
    const auto start = std::chrono::steady_clock::now();
    HiddenSampleMap map;
    if (cpu_) {
        BitmaskOptions options;
        options.threads = settings_.threads;
        options.jitter = settings_.jitter;
        options.heights = heights;
        map = cpu_->sample(frame.source, frame.receiver, options);
    } else if (gl_) {
        map = gl_->sample(frame.source, frame.receiver, GlBitmaskOptions{.jitter = settings_.jitter});
    } else {
        RayCastOptions options;
        options.threads = settings_.threads;
        options.jitter = settings_.jitter;
        options.heights = heights;
        map = rayCaster_->sample(frame.source, frame.receiver, options);
    }
    lastMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return map;
}

} // namespace sightline
