#pragma once
// Live visibility for the editor: re-samples the hidden-samples map whenever the patches or the
// scene change, with the fastest bitmask sampler available.
//
// Two back ends answer the same question (both exact, Eisemann & Décoret §2-5): the CPU sampler
// (CpuBitmaskSampler) and the GL sampler (GlBitmaskSampler) in the viewport's own context.
// chooseBackend() times both on the current patches and keeps the faster, except that a software
// rasterizer (llvmpipe) is not timed at all: there the CPU sampler wins by about 35x (README
// "Measured") and the GL trial alone would freeze the editor far too long. On a real GPU the GL
// one should win. No Qt here, so the headless screenshot path uses it too.

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "project/Project.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/GlBitmaskSampler.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/Scene.h"
#include "visibility/gl/GlFunctions.h"

namespace sightline::ui {

struct VisibilityResult {
    bool valid = false;      ///< false: the pair is invalid (see error) and nothing was sampled
    std::string error;       ///< why the pair is invalid (validatePatchPair's message)
    HiddenSampleMap map;
    std::uint64_t rays = 0;
    std::uint64_t blocked = 0;
    double ms = 0.0;         ///< sampling time
    std::string strategy;    ///< e.g. "bitmask" (CPU), "gl"
    Patch source, receiver;  ///< the pair this answers (a background answer may be older than the document)
    /// Where each drawn ray ends (RayEnds.h) for a subset of `rayEndsCap` rays; empty: drawn whole.
    std::vector<float> rayEnds;
    int rayEndsCap = 0;

    std::uint64_t unblocked() const { return rays - blocked; }
    double visibleFraction() const { return rays ? double(unblocked()) / double(rays) : 0.0; }
};

class LiveVisibility {
public:
    enum class Backend { Cpu, Gl };

    LiveVisibility();
    ~LiveVisibility();

    /// The triangles to sample against (copied into the samplers).
    void setScene(const Scene& scene);
    /// Enables the GL back end with the functions of a context that is current whenever
    /// sample() or chooseBackend() runs, and now (the renderer's name is read); nullptr disables it.
    void setGl(const gl::Functions* gl);

    /// Times one sample with each available back end on this pair and keeps the faster.
    /// Returns a line for the user ("CPU bitmask 12 ms, GL bitmask 740 ms: using CPU"). Without a
    /// GL back end worth timing (none, or a software rasterizer) it samples nothing.
    std::string chooseBackend(const Patch& source, const Patch& receiver);
    /// The GL back end is set, is not a software rasterizer, and may answer (not yet timed, or won).
    bool mayUseGl() const;
    /// A new level is coming (setScene next): both samplers may answer until chooseBackend() runs
    /// again, since which is faster depends on the level.
    void forgetChoice() { chosen_ = false; }
    void setBackend(Backend backend) { backend_ = backend; }
    Backend backend() const { return backend_; }
    std::string backendName() const;

    /// A bumpy receiver (§8; the project's "receiver_heights" for the current receiver grid), or
    /// empty for a flat one. Only the CPU sampler takes heights: while they are set, it answers
    /// whichever back end was chosen.
    void setReceiverHeights(ReceiverHeights heights) { heights_ = std::move(heights); }
    /// The project's heights could not be read: every result is invalid with this message until
    /// heights are set again (a flat answer would be a wrong one). Empty clears it.
    void setReceiverHeightsError(std::string error) { heightsError_ = std::move(error); }
    /// Both of the above from the project's "receiver_heights" for its receiver grid
    /// (LightingSetup.h); `what` names the project in messages.
    void loadReceiverHeights(const Project& project, const std::string& what);
    const ReceiverHeights& receiverHeights() const { return heights_; }
    const std::string& receiverHeightsError() const { return heightsError_; }

    /// Never throws for an invalid pair or invalid heights: the result says why instead.
    VisibilityResult sample(const Patch& source, const Patch& receiver);

private:
    VisibilityResult sampleWith(Backend backend, const Patch& source, const Patch& receiver);

    /// The renderer's name when GL is a software rasterizer (llvmpipe, softpipe, swrast), else empty.
    std::string softwareRenderer() const;

    Backend backend_ = Backend::Cpu;
    bool chosen_ = false;   ///< chooseBackend() ran
    std::unique_ptr<CpuBitmaskSampler> cpu_;
    const gl::Functions* gl_ = nullptr;
    std::optional<Scene> glScene_;   ///< kept until the GL sampler is (re)built in the context
    std::unique_ptr<GlBitmaskSampler> glSampler_;
    ReceiverHeights heights_;
    std::string heightsError_;
    std::string softwareRenderer_;
};

} // namespace sightline::ui
