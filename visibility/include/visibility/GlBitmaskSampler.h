#pragma once
// The bitmask visibility sampler on the GPU (Eisemann & Décoret 2007): one rendering pass in
// which every occluder covers its influence region (§3) on a render target of one pixel per
// receiver sample, the fragment shader backprojects it onto the source (§4) and outputs the
// source samples inside as a bitmask (§5, exact per-row intervals instead of the Hough table),
// and logic-op OR (§5.1) accumulates the masks in up to 8 RGBA32UI render targets, 128 source
// samples each, 1024 in all (§6.1, MRT).
//
// Exact by docs/design.md §2's contract. The shader has no double, so:
// - the CPU prepares the occluders as the CPU sampler does (bitmask/Occluders.h), in double:
//   shaft and watertight culling, clipping to the slab, the move to the source frame, and each
//   occluder's influence region, which a vertex shader then draws as a quad (the paper does this
//   in a geometry shader, in float; clipping huge triangles in float was 0.3-0.6 m wrong);
// - only well-conditioned occluders go to the GPU (projection factors d_R / (d_R - d_X) up to
//   16 over their whole region), as float pairs (value and rounding residual), and the fragment
//   shader runs the CPU float kernel's filter (BitmaskRows.h): it bounds its own answer's error
//   as a distance between ray and occluder boundary, answers only what it proves within the
//   budget, and flags every receiver sample it cannot prove;
// - the other occluders (those reaching near a receiver sample's distance) take the CPU
//   sampler's double path, and so do the flagged samples; everything is ORed into one map.
// MaskMode::Table is the paper's own §5 method, inexact by design: every occluder on the GPU,
// the AND of its edges' nearest-texel masks from a Hough table (HoughMaskTable.h, uploaded once
// per source grid and resolution), as the CPU sampler's table mode does.
//
// Runs in any current OpenGL 4.5 core context: pass its resolved functions (HeadlessContext for
// OSMesa and EGL, or the editor's Qt context). The triangles stay on the CPU; each call uploads
// the occluders of its shaft.

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
    double setupMs = 0.0;    ///< occluder preparation, uploads, uniforms, render targets
    double drawMs = 0.0;     ///< the pass, until the GPU finished
    double readbackMs = 0.0; ///< hidden-samples map and flags back to the CPU
    double tableMs = 0.0;    ///< Table: building and uploading the Hough table (0 when cached)
    double cpuMs = 0.0;      ///< Exact: the occluders and samples the CPU answered
    std::size_t gpuOccluders = 0;     ///< drawn
    std::size_t cpuOccluders = 0;     ///< answered by the CPU's double path
    std::size_t flaggedSamples = 0;   ///< receiver samples the shader could not prove
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
    /// Compiles the shaders; the context must stay current while the sampler is used. Throws
    /// sightline::Error (shader compile log on one line) on failure, or for coordinates beyond
    /// docs/design.md §2's range.
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
