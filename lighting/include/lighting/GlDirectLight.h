#pragma once
// The paper-faithful GL path for many lights (Barczak 2006 §4.2): every emitter of the lights
// (a point or spot light, an area light's samples, VPLs) gets an octahedral shadow map, a
// directional light an orthographic one over the scene's bounding sphere; a compute shader then
// sums the contract's terms (LightEmission.h, in float) at every point, each counted where the
// point is no farther from the emitter than the map's nearest surface plus a bias.
//
// Octahedral maps (§4.2.1): the sphere of directions around the emitter is the octahedron
// |x| + |y| + |z| = 1, its upper four faces laid on the square [-1, 1]² as they project and the
// lower four folded out to its corners. On one face the map is a projective (linear in clip space)
// function of the position, so each triangle is rasterised exactly once per face it touches: a
// geometry shader sends it to the faces whose octant it may enter, and clip distances s.q >= 0
// keep each copy inside its octant. One instanced draw renders a batch of emitters into the
// layers of an array texture, each texel keeping the nearest distance by MIN blending. A light
// with a range draws only the triangles whose boxes come within it (nothing beyond can shadow
// what it lights).
//
// Tolerance: a map answers for its texel centres. A point at distance t from the emitter, its
// normal at angle theta from the emitter, counts as unshadowed when its distance is at most the
// texel's plus t * texelAngle() * min(1 + tan theta, kGlLightMaxBiasTexels) (a directional map's
// texel width in place of t * texelAngle()). So a pair may differ from the exact answer where a
// blocker lies within that bias in front of the point, or within a texel of the point's direction
// from the emitter (tests/lighting/tst_GlDirectLight.cpp explains every difference this way).
//
// Barczak's occlusion pyramid (§4.3.1) is the fast path's proved tile classes (classifyTiles in
// DirectLight.h): where given, they settle whole (tile, light) pairs before any map is read.
//
// Runs on any current OpenGL 4.5 core context (OSMesa, EGL, the editor's Qt context).

#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/DirectLight.h"
#include "lighting/Light.h"
#include "lighting/ShadowAgreement.h"
#include "visibility/Scene.h"
#include "visibility/gl/GlFunctions.h"

namespace sightline {

inline constexpr float kGlLightMaxBiasTexels = 8.0f;

struct GlDirectLightOptions {
    int resolution = 512;           ///< side of each emitter's map in texels
    std::size_t mapBytes = 256u << 20;   ///< GPU memory for the maps of one batch
};

struct GlDirectLightStats {
    std::size_t lights = 0;
    std::size_t emitters = 0;
    std::size_t maps = 0;           ///< emitters whose shadow maps were drawn
    std::size_t points = 0;
    std::size_t batches = 0;
    std::size_t triangles = 0;
    double renderMs = 0.0;          ///< drawing the shadow maps
    double shadeMs = 0.0;           ///< the compute passes and the read-back
    double ms = 0.0;
};

class GlDirectLight {
public:
    /// Uploads the triangles; the context must stay current while this object is used. Throws
    /// sightline::Error for a resolution outside [16, 8192] or a framebuffer the driver refuses.
    GlDirectLight(const gl::Functions& gl, const WorldTriangles& triangles, GlDirectLightOptions options = {});
    ~GlDirectLight();
    GlDirectLight(const GlDirectLight&) = delete;
    GlDirectLight& operator=(const GlDirectLight&) = delete;

    /// Direct irradiance (W/m² per channel) at each point, in the points' order. `lights` must
    /// have passed validateLights and `points` validateShadingPoints. With `bits`, also each
    /// (point, emitter) pair's answer, for every pair (a zero term's too). With `classes`
    /// (classifyTiles of the same lights and points: Barczak's occlusion pyramid, §4.3.1), a
    /// pair in an unreached or shadowed tile takes nothing and one in a lit tile no shadow test,
    /// exactly as proved; only lights with a partial tile get maps.
    std::vector<glm::dvec3> irradiance(const std::vector<Light>& lights, std::span<const ShadingPoint> points,
                                       GlDirectLightStats* stats = nullptr, EmitterBits* bits = nullptr,
                                       const TileClasses* classes = nullptr);

    int resolution() const;
    /// An upper bound on the angle one octahedral texel spans (radians): the octahedron's points
    /// lie within sqrt(3) of the unit sphere's scale and its fold stretches a texel by up to
    /// sqrt(3), so 3 * (2 / resolution).
    double texelAngle() const;
    /// The width of a directional map's texel (metres).
    double directionalTexel() const;
    /// The bias a point at distance t (metres; ignored for a directional light) whose normal is
    /// at cos theta from the light direction gets.
    double bias(bool directional, double distance, double cosTheta) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace sightline
