#pragma once
// How the viewport draws many rays so that they stay readable and cheap (a million rays drawn
// plainly make an opaque slab and a frame far too slow to interact with; the interaction targets
// are 30 Hz at 16,384 rays and 20 Hz at 65,536 on llvmpipe).
//
// On llvmpipe (1280x720, the demo's 16,384 rays, 29% of them free) the rays' drawing time is the
// lines' pixels: drawn at 10% of their length it falls to about a sixth, with every ray clipped
// (the vertex work alone) to a thirtieth or so, and without blending only to about three
// quarters. So the lever is fewer pixels a ray, where that loses nothing to the eye:
//   - Density. Each ray's opacity a comes from how many drawn rays are expected to cross a pixel
//     of the bundle on screen (their count times the bundle's projected length over its projected
//     area): an open shaft then reaches the style's coverage at any ray count and any zoom, and
//     where rays are blocked the bundle is fainter in proportion. A thousand rays seen close are
//     crisp separate lines; a million are a smooth haze whose shadows still read, instead of an
//     opaque slab. Dense bundles are counted, free rays in one channel and blocked ones (when
//     shown) in another of a float layer (additive and exact: an 8-bit coverage layer rounded the
//     tiny opacities away, a 16-bit count overflowed at a million rays; R32F blends as fast as
//     RG16 on llvmpipe), and n rays cover 1 - (1 - a)^n when laid over the frame.
//   - Resolution. Where more than a couple of rays cross each pixel no single ray can be seen
//     anyway, so the layer is drawn at a half, a quarter or (past 256 rays a pixel) an eighth of
//     the view's resolution (that fraction of the pixels a ray), then laid over the frame with bilinear
//     filtering, only over the bundle's screen rectangle. Its depth is the frame's, sampled down,
//     so walls in front still hide rays.
// The pure functions below decide; RayLayer owns the GL objects.

#include <array>
#include <cstdint>
#include <optional>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "visibility/Patch.h"
#include "visibility/gl/GlFunctions.h"

namespace sightline::ui {

/// Where the bundle of rays between two patches lies on screen, in pixels of a width x height
/// view: its rectangle, its projected length (centre to centre) and area (the convex hull of the
/// eight corners). Empty when a corner lies behind the eye (the estimate would mislead).
struct BundleOnScreen {
    glm::dvec2 min{0.0}, max{0.0};
    double length = 0.0;
    double area = 0.0;
};
std::optional<BundleOnScreen> bundleOnScreen(const glm::mat4& viewProj, int width, int height, const Patch& source,
                                             const Patch& receiver);

/// How many of `rays` drawn rays are expected to cross one pixel of the bundle (at full resolution).
double expectedOverlap(const BundleOnScreen& bundle, std::uint64_t rays);

/// The layer's resolution, as a divisor of the view's (1, 2, 4 or 8): full where rays are sparse
/// enough to be told apart (at most 2 a pixel), a half up to 8, a quarter up to 256, else an
/// eighth (a dense haze of rays looks the same at an eighth, and software GL's fill rate is what
/// the frame rate spends).
int rayLayerDivisor(double overlap);

/// One ray's opacity so that `overlap` rays at full resolution reach `coverage` (in (0, 1]) where
/// all of them pass, drawn into a layer `divisor` times coarser (whose pixels span `divisor` of
/// the view's across the bundle: about overlap x divisor rays cross each). Never above
/// `coverage`; exactly 1 for coverage 1 (opaque rays, as tests and prints ask for).
float rayOpacity(double coverage, double overlap, int divisor);

/// The GL side: a float count layer with a depth buffer, and the pass that lays it over a frame.
class RayLayer {
public:
    explicit RayLayer(const gl::Functions& gl);
    ~RayLayer();
    RayLayer(const RayLayer&) = delete;
    RayLayer& operator=(const RayLayer&) = delete;

    /// Sizes the layer for a width x height frame at `divisor` (with a channel for blocked rays
    /// when `blocked`), copies the frame's depth into it (sampled down), clears its counts and
    /// binds it with its viewport, blending additive. Draw each free ray with colour (1, 0, 0, 0)
    /// and each blocked one with (0, 1, 0, 0). False when the layer cannot be made (then draw
    /// into the frame directly).
    bool begin(GLuint frame, int width, int height, int divisor, bool blocked);
    /// Lays the layer over `frame` within the pixel rectangle [min, max] (clamped to the frame):
    /// free rays in `free`, blocked ones in `blocked` (rgb; alpha: one ray's opacity), free over
    /// blocked.
    /// Leaves `frame` bound with a full viewport, premultiplied blending on, depth test off.
    void composite(GLuint frame, int width, int height, glm::dvec2 min, glm::dvec2 max, const glm::vec4& free,
                   const glm::vec4& blocked);

private:
    void destroyTarget();

    const gl::Functions& gl_;
    GLuint program_ = 0, vao_ = 0;
    GLuint framebuffer_ = 0, coverage_ = 0, depth_ = 0;
    int width_ = 0, height_ = 0;   ///< the layer's size
    bool blocked_ = false;         ///< it has a channel for blocked rays
    bool broken_ = false;
};

} // namespace sightline::ui
