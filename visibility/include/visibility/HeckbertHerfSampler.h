#pragma once
// The Heckbert-Herf baseline (Heckbert & Herf 1997; the comparison in Eisemann & Décoret 2007,
// §10): one render per source sample. For source sample S, every occluder is projected from S
// onto the receiver plane into a render target with one pixel per receiver sample; the pixels it
// covers are the receiver samples that do not see S. A stencil test counts each pixel once per
// render and additive blending sums the renders, so the result is, per receiver sample, the
// number of source samples it does not see: counts only, not which samples (the bitmask method's
// advantage). It exists to be charted against the bitmask samplers (`sightline-cli bench`).
//
// Projection: with the receiver's affine coordinates (X, Y, D) and S = (Sx, Sy, Sd), the ray
// from S through a point meets the receiver plane at (a, b) with a w = X - Sx D / Sd, b w = Y -
// Sy D / Sd, w = 1 - D / Sd: linear in the point, so a 4x4 matrix. Two clip distances keep
// D / Sd in [0, 1 - 1e-6]: strictly between S and the receiver plane, the reference's segment
// interior.
// Triangles are first culled against the shaft's hull on the CPU, as any user of the method
// would. Single precision: answers differ from the reference on grazing rays.

#include <cstdint>
#include <memory>
#include <vector>

#include "visibility/Patch.h"
#include "visibility/Scene.h"
#include "visibility/gl/GlFunctions.h"

namespace sightline {

struct HeckbertHerfStats {
    double setupMs = 0.0;      ///< culling, upload, render target
    double drawMs = 0.0;       ///< one render per source sample, until the GPU finished
    double readbackMs = 0.0;
    std::size_t trianglesDrawn = 0;   ///< per render, after culling
};

class HeckbertHerfSampler {
public:
    /// Compiles the shaders; the context must stay current while the sampler is used.
    HeckbertHerfSampler(const gl::Functions& gl, WorldTriangles triangles);
    ~HeckbertHerfSampler();
    HeckbertHerfSampler(const HeckbertHerfSampler&) = delete;
    HeckbertHerfSampler& operator=(const HeckbertHerfSampler&) = delete;

    /// Validates the pair (sightline::Error if invalid); returns, per receiver sample b * na + a,
    /// how many source samples it does not see.
    std::vector<std::uint32_t> blockedCounts(const Patch& source, const Patch& receiver,
                                             HeckbertHerfStats* stats = nullptr);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace sightline
