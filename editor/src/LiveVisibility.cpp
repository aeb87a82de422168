#include "editor/LiveVisibility.h"

#include <cstdio>

#include "project/LightingSetup.h"
#include "base/Error.h"

namespace sightline::ui {

namespace {
double msSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}
} // namespace

LiveVisibility::LiveVisibility() : cpu_(std::make_unique<CpuBitmaskSampler>(Scene{})) {}
LiveVisibility::~LiveVisibility() = default;

void LiveVisibility::setScene(const Scene& scene)
{
    cpu_->setScene(scene);
    glSampler_.reset();
    // The GL sampler needs its own copy only while it may answer: once the CPU won the timing, a
    // drag of an occluder should not copy the level every frame.
    if (gl_ && (backend_ == Backend::Gl || !chosen_))
        glScene_ = scene;
    else
        glScene_.reset();
}

void LiveVisibility::setGl(const gl::Functions* gl)
{
    gl_ = gl;
    glSampler_.reset();
    softwareRenderer_.clear();
    if (gl_) {
        const auto* renderer = reinterpret_cast<const char*>(gl_->GetString(GL_RENDERER));
        const std::string name = renderer ? renderer : "";
        for (const char* software : {"llvmpipe", "softpipe", "swrast", "Software Rasterizer"})
            if (name.find(software) != std::string::npos)
                softwareRenderer_ = name;
    }
    if (!gl_) {
        glScene_.reset();
        backend_ = Backend::Cpu;
    }
}

std::string LiveVisibility::backendName() const
{
    if (backend_ == Backend::Gl)
        return "GL bitmask";
    return CpuBitmaskSampler::simdAvailable() ? "CPU bitmask (AVX2)" : "CPU bitmask";
}

std::string LiveVisibility::softwareRenderer() const { return softwareRenderer_; }

bool LiveVisibility::mayUseGl() const
{
    return gl_ && (!chosen_ || backend_ == Backend::Gl) && softwareRenderer().empty();
}

std::string LiveVisibility::chooseBackend(const Patch& source, const Patch& receiver)
{
    chosen_ = true;
    backend_ = Backend::Cpu;
    if (!gl_)
        return "using " + backendName();
    // A software rasterizer (llvmpipe, softpipe, swrast) is the CPU running the GL sampler's
    // fragments, far slower than the CPU sampler; timing it on the GUI thread would freeze the
    // window far too long on a 512x512 receiver. Neither is timed: the CPU sampler answers, off
    // the GUI thread.
    if (const std::string software = softwareRenderer(); !software.empty())
        return "GL is a software rasterizer (" + software + "): using " + backendName();
    const VisibilityResult cpu = sampleWith(Backend::Cpu, source, receiver);
    if (!cpu.valid)
        return "using " + backendName();
    std::string line;
    try {
        sampleWith(Backend::Gl, source, receiver);   // warm-up: shader compile, upload
        const VisibilityResult glResult = sampleWith(Backend::Gl, source, receiver);
        backend_ = glResult.ms < cpu.ms ? Backend::Gl : Backend::Cpu;
        char buffer[160];
        std::snprintf(buffer, sizeof buffer, "CPU %.1f ms, GL %.1f ms per update: ", cpu.ms, glResult.ms);
        line = buffer;
    } catch (const Error& e) {
        backend_ = Backend::Cpu;
        line = std::string("GL sampler unavailable (") + e.what() + "): ";
    }
    return line + "using " + backendName();
}

void LiveVisibility::loadReceiverHeights(const Project& project, const std::string& what)
{
    try {
        heights_ = projectReceiverHeights(project, project.receiver, what);
        heightsError_.clear();
    } catch (const Error& e) {
        heights_ = {};
        heightsError_ = e.what();
    }
}

VisibilityResult LiveVisibility::sample(const Patch& source, const Patch& receiver)
{
    return sampleWith(backend_, source, receiver);
}

VisibilityResult LiveVisibility::sampleWith(Backend backend, const Patch& source, const Patch& receiver)
{
    VisibilityResult result;
    result.source = source;
    result.receiver = receiver;
    try {
        validatePatchPair(source, receiver);
        if (!heightsError_.empty())
            throw Error(heightsError_);
        if (!heights_.empty())
            validateReceiverHeights(source, receiver, heights_);
    } catch (const Error& e) {
        result.error = e.what();
        return result;
    }
    const auto start = std::chrono::steady_clock::now();
    if (backend == Backend::Gl && heights_.empty()) {
        if (!glSampler_) {
            glSampler_ = std::make_unique<GlBitmaskSampler>(*gl_, glScene_ ? *glScene_ : Scene{});
        }
        result.map = glSampler_->sample(source, receiver);
        result.strategy = "gl";
    } else {
        BitmaskStats stats;
        BitmaskOptions options;
        options.heights = heights_.empty() ? nullptr : &heights_;
        result.map = cpu_->sample(source, receiver, options, &stats);
        result.strategy = stats.strategy;
    }
    result.ms = msSince(start);
    result.valid = true;
    result.rays = result.map.rayCount();
    result.blocked = result.map.blockedCount();
    return result;
}

} // namespace sightline::ui
