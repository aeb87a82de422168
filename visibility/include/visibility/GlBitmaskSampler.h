#pragma once
// The bitmask visibility sampler on the GPU, as Eisemann & Décoret 2007 describe it: one
// rendering pass over the scene's triangles.
//   - vertex shader: world positions;
//   - geometry shader (§3): clips the triangle to the slab between the patch planes, bounds its
//     influence region by projecting it from the four source corners onto the receiver plane,
//     and emits that box as a quad over the receiver grid (one pixel = one receiver sample);
//   - fragment shader (§4-5): backprojects the clipped triangle from the pixel's receiver sample
//     onto the source and outputs the source samples inside it as a bitmask;
//   - logic-op OR (§5.1) accumulates the masks in up to 8 RGBA32UI render targets, 128 source
//     samples each, 1024 in all (§6.1, MRT).
// By default the masks are exact (per source row, the backprojection's interval of columns), like
// the CPU sampler (CpuBitmaskSampler.h); computation is in single precision, so answers can differ
// from the reference on grazing rays only. MaskMode::Table is the paper's own §5 method: the
// fragment shader ANDs the nearest-texel masks of the backprojection's edges from a Hough table
// (HoughMaskTable.h, built on the CPU and uploaded once per source grid and resolution), exactly
// as the CPU sampler's table mode does.
//
// Runs in any current OpenGL 4.5 core context: pass its resolved functions (HeadlessContext for
// OSMesa and EGL, or the editor's Qt context). The triangles are uploaded once.

#include <cstdint>
#include <memory>

#include "visibility/HiddenSampleMap.h"
#include "visibility/MaskMode.h"
#include "visibility/Patch.h"
#include "visibility/Scene.h"
#include "visibility/SourceJitter.h"
#include "visibility/gl/GlFunctions.h"

namespace sightline {

struct GlBitmaskStats {
    double setupMs = 0.0;    ///< uniforms, render targets
    double drawMs = 0.0;     ///< the pass, until the GPU finished
    double readbackMs = 0.0; ///< hidden-samples map back to the CPU
    double tableMs = 0.0;    ///< Table: building and uploading the Hough table (0 when cached)
};

struct GlBitmaskOptions {
    SourceJitter jitter{};           ///< decorrelated source samples (§6.2)
    /// Watertight front-face culling (§7) for meshes flagged Mesh::watertight, with the CPU
    /// sampler's safety rule (receiverApartFrom). Needs the Scene constructor.
    bool watertightCulling = true;
    MaskMode mode = MaskMode::Exact;
    int tableWidth = 256;            ///< Table: angles (4..8192, as HoughMaskTable)
    int tableHeight = 128;           ///< Table: distances (2..8192)
};

class GlBitmaskSampler {
public:
    /// Keeps, per instance, its watertight flag and bounds, for watertight culling.
    GlBitmaskSampler(const gl::Functions& gl, const Scene& scene);
    /// Compiles the shaders and uploads the triangles; the context must stay current while the
    /// sampler is used. Throws sightline::Error (shader compile log on one line) on failure.
    GlBitmaskSampler(const gl::Functions& gl, const WorldTriangles& triangles);
    ~GlBitmaskSampler();
    GlBitmaskSampler(const GlBitmaskSampler&) = delete;
    GlBitmaskSampler& operator=(const GlBitmaskSampler&) = delete;

    /// Validates the pair and the table resolution (sightline::Error if invalid), renders, reads
    /// the map back.
    HiddenSampleMap sample(const Patch& source, const Patch& receiver, GlBitmaskStats* stats = nullptr);
    HiddenSampleMap sample(const Patch& source, const Patch& receiver, const GlBitmaskOptions& options,
                           GlBitmaskStats* stats = nullptr);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace sightline
