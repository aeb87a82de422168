#pragma once
// The paper-faithful GL filler (Sattler et al. 2004 §3.2): for each light direction the scene is
// rendered into an orthographic depth map covering its bounding sphere; then, instead of one
// occlusion query per vertex read back by the CPU (the paper's §8.1 names that read-back as the
// drawback), a compute shader compares every facing point's depth with the map and sets its bit
// with atomicOr in a shader storage buffer. The buffer is read once per fill call.
//
// Tolerance: a depth map answers for texel centres. A point sees direction d when its depth is at
// most the map's plus a bias of texel * (1 + tan theta) (theta between the normal and d, capped at
// kAoGlMaxBiasTexels texels), the slope-scaled form of the paper's glPolygonOffset(1, 1): its
// own surface, sampled up to half a texel diagonal away, must not hide it. So a bit may differ
// from the exact CPU mode where a blocker lies within that bias above the point, or within a texel
// of the point's projection (tests/lighting/tst_AoGl.cpp checks exactly this).
//
// Runs on any current OpenGL 4.5 core context (OSMesa, EGL, the editor's Qt context).

#include <memory>

#include "lighting/ao/AoFiller.h"
#include "visibility/gl/GlFunctions.h"

namespace sightline {

inline constexpr float kAoGlMaxBiasTexels = 8.0f;

struct AoGlOptions {
    int resolution = 1024;   ///< depth map side in pixels (2048: half the differing bits, 1.5x the time on llvmpipe)
    /// The depth maps are drawn from the occluders simplified (meshoptimizer's edge collapses)
    /// within this many texels: a depth map resolves nothing finer, and on llvmpipe the time is
    /// the triangles' (the bunny at 0.25 texel: 35,684 of 69,451 triangles). 0: every triangle.
    double simplifyTexels = 0.25;
};

class AoGlCaster final : public AoFiller {
public:
    /// Uploads the occluders; the context must stay current while this object is used.
    AoGlCaster(const gl::Functions& gl, const AoOccluders& occluders, AoGlOptions options = {});
    ~AoGlCaster() override;
    std::string name() const override { return "gl-depth-map"; }
    bool fill(const AoPoints& points, const AoDirectionSet& set, int first, int last, VisibilityMatrix& matrix,
              const AoFillControl& control = {}) override;

    /// World size of one depth-map texel, and the bias a point facing d at cos theta gets.
    double texelSize() const;
    /// The triangles the depth maps draw, and how far (metres) their surface may lie from the
    /// occluders' (meshoptimizer's error measure; 0 when not simplified).
    std::size_t drawnTriangles() const;
    double simplificationError() const;
    double bias(double cosTheta) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace sightline
