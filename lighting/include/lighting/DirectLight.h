#pragma once
// Direct irradiance from many lights, shadowed exactly (docs/lights.md; the contract of
// `sightline-cli lights`).
//
// E(x, n) = sum over the lights' emitters s of colour * term(s, x, n) * [segment x s unblocked],
// the terms of LightEmission.h, visibility by docs/design.md §2's segment test (ties either way).
// Two paths answer the same sum, term by term in the same order (light by light, an area light's
// samples in bit order), so they differ only where a segment is a tie:
//
// - Reference: every emitter with a non-zero term at every point, one shadow segment each, tile
//   by tile (the fast path's tiles of nearby points, below): each emitter's segments to a tile
//   cast together from the emitter (a directional light's from each point) in packets of 16
//   (RayCastScene::segmentsBlocked: Embree finds candidates, the contract's double test decides).
//   Nearby points towards one light are coherent packets, as a brute force tuned for Embree
//   casts them.
// - Fast: per tile of 64 nearby points (lights/PointTiles.h) and per light (Barczak's tiles x
//   lights). A tile the light cannot reach (out of its range, behind an area light) costs a box
//   test; a tile one triangle shadows whole (lights/ShaftBlocker.h: a proof from the corners of
//   the light and of the tile's box, with the triangles the rays from the light's centre to the
//   tile's centre meet first as candidates) costs two float rays and the proof; the rest cast
//   their shadow segments in coherent packets sharing the light's end (a directional light's are
//   parallel). Optionally, an area light whose samples face a planar receiver grid (the receiver
//   patch's samples) is the bitmask method's source patch (Eisemann & Décoret §8): one call of the
//   exact CPU bitmask sampler answers all its samples against all the grid's points.
//
// Beside them, two answers that are not the contract's, each measured against the reference: the
// fast path with a light cut (LightTree.h: clusters of point lights shaded by one representative),
// and the yardstick a user would write with Embree alone (LightingPath::EmbreeFloat: float rays).

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/Light.h"
#include "lighting/LightEmission.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/Patch.h"
#include "visibility/RayCastSampler.h"
#include "visibility/Scene.h"
#include "visibility/pvs/FirstHitCaster.h"

namespace sightline {

struct ShadingPoint {
    glm::dvec3 position{0.0};
    glm::dvec3 normal{0.0, 1.0, 0.0};   ///< unit length
};

/// Throws sightline::Error naming the point for a non-finite position or normal, a position beyond
/// docs/design.md §2's range, or a zero normal; normalises the normals.
void validateShadingPoints(std::span<ShadingPoint> points, const std::string& what);

namespace lights {
class TriangleBoxTree;
class FloatShadowRays;
}

/// The scene as lighting asks about it, built once: exact segment queries, the bitmask sampler,
/// the scene's bounds (where a directional light's segments end).
class LightingScene {
public:
    /// Throws sightline::Error for coordinates beyond docs/design.md §2's range, or if Embree fails.
    explicit LightingScene(const Scene& scene);
    ~LightingScene();

    const RayCastScene& rays() const { return *rays_; }
    const pvs::FirstHitCaster& firstHits() const { return *firstHits_; }
    const WorldTriangles& triangles() const { return triangles_; }
    /// The triangle across each edge of each triangle (-1: none, or a non-manifold edge).
    const std::vector<std::array<std::int64_t, 3>>& neighbours() const { return neighbours_; }
    const DirectionalReach& reach() const { return reach_; }
    /// World triangle `triangle`'s diffuse albedo: its mesh's (Mesh::albedo) where known, else
    /// `fallback` in every channel.
    glm::dvec3 albedo(std::int64_t triangle, double fallback) const;
    /// The triangles' box tree (lights/TriangleBoxTree.h): which shafts are empty.
    const lights::TriangleBoxTree& boxTree() const { return *boxTree_; }
    /// Built on first use (its set-up is not free, and only area lights over a grid ask for it).
    const CpuBitmaskSampler& bitmask() const;
    /// Embree's own float scene for LightingPath::EmbreeFloat, built on first use.
    const lights::FloatShadowRays& floatRays() const;

private:
    Scene scene_;
    WorldTriangles triangles_;
    std::vector<std::array<std::int64_t, 3>> neighbours_;
    std::unique_ptr<RayCastScene> rays_;
    std::unique_ptr<pvs::FirstHitCaster> firstHits_;
    std::unique_ptr<lights::TriangleBoxTree> boxTree_;
    DirectionalReach reach_;
    std::vector<std::size_t> instanceFirst_;   ///< each instance's first world triangle, where some mesh carries albedos
    mutable std::once_flag bitmaskOnce_;
    mutable std::unique_ptr<CpuBitmaskSampler> bitmask_;
    mutable std::once_flag floatOnce_;
    mutable std::unique_ptr<lights::FloatShadowRays> floatRays_;
};

enum class LightingPath {
    Fast,
    Reference,
    /// Not the contract: the brute force a user would write with Embree alone (float rays over its
    /// own triangles, lights/FloatShadowRays.h), the yardstick the exact paths' speed is told against.
    EmbreeFloat,
};

namespace lights {
struct PointTile;
}

/// The fast path's tiles of a set of points (Morton order, 64 a tile), built once where the same
/// points are lit again and again (a live view, amortised updates).
class PointTiling {
public:
    explicit PointTiling(std::span<const ShadingPoint> points);
    ~PointTiling();
    PointTiling(const PointTiling&) = delete;
    PointTiling& operator=(const PointTiling&) = delete;

    const std::vector<lights::PointTile>& tiles() const { return *tiles_; }
    std::size_t pointCount() const { return points_; }

private:
    std::unique_ptr<std::vector<lights::PointTile>> tiles_;
    std::size_t points_ = 0;
};

struct DirectLightOptions {
    LightingPath path = LightingPath::Fast;
    int threads = 0;                     ///< 0 = all cores
    /// The points are exactly this patch's samples in bit order, with its normal. Not owned.
    const Patch* receiverGrid = nullptr;
    /// Fast path with a receiver grid: area lights that form a valid pair with it (docs/design.md §2)
    /// take the bitmask sampler. Off by default: on one call its set-up costs more than the rays
    /// it saves on the levels measured (docs/lights.md).
    bool bitmaskAreaLights = false;
    /// Fast path: tiles built once for these same points (else built per call). Not owned.
    const PointTiling* tiling = nullptr;
    /// Fast path, > 0: point lights through a light tree's cut per tile with this error (LightTree.h),
    /// an approximation of the exact sum; 0: exact.
    double lightCutError = 0.0;
    /// Fast path: also weigh the terms of tiles proved shadowed whole, so that stats.terms counts
    /// every non-zero term (a cost panel's "reaches before shadows"; it costs about what the proof
    /// saves there).
    bool countAllTerms = false;
};

struct DirectLightStats {
    std::size_t lights = 0;
    std::size_t lightSamples = 0;        ///< emitters: one per point, spot or directional light, na x nb per area light
    std::size_t points = 0;
    /// (point, emitter) pairs with a non-zero unshadowed term, less (fast path without
    /// countAllTerms) those of the (tile, light) pairs a proof shadowed whole, which are not weighed.
    std::uint64_t terms = 0;
    std::uint64_t segmentsCast = 0;      ///< of those, decided by ray casting
    std::uint64_t tilesUnreached = 0;    ///< fast: (tile, light) pairs skipped by a box test
    std::uint64_t tilesProvenShadowed = 0;   ///< fast: (tile, light) pairs one triangle, or one coplanar region, shadows whole
    std::uint64_t tilesProvenLit = 0;    ///< fast: (tile, light) pairs whose shaft no triangle enters
    std::uint64_t tilesCast = 0;         ///< fast: (tile, light) pairs whose segments were cast
    std::size_t bitmaskLights = 0;       ///< area lights decided by the bitmask sampler
    std::uint64_t bitmaskRays = 0;       ///< rays those calls answered
    std::uint64_t cutClusters = 0;       ///< light cut: (tile, cluster) pairs shaded by a stand-in
    std::uint64_t cutLights = 0;         ///< light cut: (tile, light) pairs those and the cut's single lights stood for
    double ms = 0.0;
};

/// Direct irradiance (W/m² per channel) at each point, in the points' order. `lights` must have
/// passed validateLights and `points` validateShadingPoints.
std::vector<glm::dvec3> directIrradiance(const LightingScene& scene, const std::vector<Light>& lights,
                                         std::span<const ShadingPoint> points, const DirectLightOptions& options = {},
                                         DirectLightStats* stats = nullptr);

/// Barczak's occlusion-pyramid classes (§4.3.1) of a (tile, light) pair, proved as the fast path
/// proves them (never guessed): out of the light's reach, shadowed whole by one triangle or a
/// fused pair, lit through a shaft no triangle enters, or partial (some segments must be decided).
enum class TileClass : std::uint8_t { Unreached = 0, Shadowed = 1, Lit = 2, Partial = 3 };

struct TileClasses {
    std::size_t tiles = 0;
    std::size_t lights = 0;
    std::vector<std::uint32_t> tileOf;   ///< per point, its tile
    std::vector<TileClass> classes;      ///< [tile * lights + light]
    double ms = 0.0;

    TileClass at(std::size_t point, std::size_t light) const { return classes[tileOf[point] * lights + light]; }
};

/// The classes over the fast path's tiles of `points` (every class tried for every light, so a
/// light may turn out to need no shadow test at all).
TileClasses classifyTiles(const LightingScene& scene, const std::vector<Light>& lights, std::span<const ShadingPoint> points,
                          int threads = 0);

/// The receiver patch's samples with its normal, in bit order (the points of `lights` without
/// --points).
std::vector<ShadingPoint> patchShadingPoints(const Patch& patch);

} // namespace sightline
