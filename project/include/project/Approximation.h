#pragma once
// The fast and coarse ways of answering a pair that the disagreement view holds against the exact
// answer (visibility/RayDisagreement.h): the paper's Hough table on the CPU or the GPU (Eisemann &
// Décoret §5), the GPU pass with exact masks, fewer samples on both patches, and coarse occluders
// ("model no more than a scene needs", §10: OpenMesh's closest decimation, or the conservative inner
// kind). One spelling each, shared by `sightline-cli disagreement` and the editor's view.

#include <cstddef>
#include <memory>
#include <string>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/RayDisagreement.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/Scene.h"
#include "visibility/gl/GlFunctions.h"

namespace sightline {

class CpuBitmaskSampler;
class GlBitmaskSampler;

enum class ApproximationKind {
    Table,          ///< the CPU sampler's Hough table mode (nearest texel)
    GlTable,        ///< the GPU pass with the Hough table (the paper's own method)
    Gl,             ///< the GPU pass with exact per-row masks: differs on ties only
    FewerSamples,   ///< both grids `sampleFactor` times coarser, each coarse ray standing for its rays
    Coarse,         ///< meshes above `triangles` simplified by OpenMesh's decimater (closest kind)
    Inner,          ///< closed meshes replaced by faces strictly inside them (never block a free ray)
};

struct Approximation {
    ApproximationKind kind = ApproximationKind::Table;
    int tableWidth = 256, tableHeight = 128;   ///< Table, GlTable
    int sampleFactor = 2;                      ///< FewerSamples, 2..64
    std::size_t triangles = 5000;              ///< Coarse, 4..100,000,000
    int resolution = 32;                       ///< Inner: voxels along a mesh's longest side, 4..256

    bool needsGl() const { return kind == ApproximationKind::Gl || kind == ApproximationKind::GlTable; }
    bool replacesMeshes() const { return kind == ApproximationKind::Coarse || kind == ApproximationKind::Inner; }
};

/// "table[-WxH]", "gl", "gl-table[-WxH]", "samples-K", "coarse[-N]", "inner[-R]". Throws
/// sightline::Error naming the spelling and the accepted ones.
Approximation parseApproximation(const std::string& name);
/// The canonical spelling (parseApproximation reads it back to the same approximation).
std::string approximationName(const Approximation& approximation);
/// For people: "Hough table 256x128 (CPU)", "a quarter of the samples (half each side)", ...
std::string describeApproximation(const Approximation& approximation);

/// Samples pairs the approximate way. Keeps its (possibly coarse) scene and samplers between calls.
class ApproximateSampler {
public:
    /// Builds the approximation's scene from the level: the level itself, or with its meshes
    /// replaced (Coarse, Inner; sightline::Error when none qualifies).
    ApproximateSampler(const Approximation& approximation, const Scene& level);
    ~ApproximateSampler();
    ApproximateSampler(const ApproximateSampler&) = delete;
    ApproximateSampler& operator=(const ApproximateSampler&) = delete;

    const Approximation& approximation() const { return approximation_; }
    /// The scene it samples: its triangle count is what the approximation costs to sample.
    const Scene& scene() const { return scene_; }
    std::size_t meshesReplaced() const { return replaced_; }

    /// The pair's hidden-samples map on the pair's own grids. `heights` (may be null or empty):
    /// a bumpy receiver, which only the CPU kinds on the full grids sample (others refuse it).
    /// `gl`: a current OpenGL 4.5 core context's functions, for the GL kinds (the same context on
    /// every call). Throws sightline::Error for an invalid pair or a missing context.
    HiddenSampleMap sample(const Patch& source, const Patch& receiver, const ReceiverHeights* heights, int threads,
                           const gl::Functions* gl = nullptr);

private:
    Approximation approximation_;
    Scene scene_;
    std::size_t replaced_ = 0;
    std::unique_ptr<CpuBitmaskSampler> cpu_;
    std::unique_ptr<GlBitmaskSampler> gl_;
    const gl::Functions* glFunctions_ = nullptr;
};

/// The pair answered by `sampler` and held against `exact` (the level's exact map for the pair),
/// every differing ray judged on `level` with the receiver's bumps (RayDisagreement.h), and timed.
struct JudgedDisagreement {
    RayDisagreement disagreement;
    std::uint64_t approximateBlocked = 0;
    double approximateMs = 0.0, judgeMs = 0.0;
};
JudgedDisagreement judgedDisagreement(ApproximateSampler& sampler, const Scene& level, const Patch& source,
                                      const Patch& receiver, const ReceiverHeights* heights, const HiddenSampleMap& exact,
                                      int threads, const gl::Functions* gl = nullptr);

} // namespace sightline
