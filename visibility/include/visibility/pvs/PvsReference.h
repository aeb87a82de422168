#pragma once
// How wrong a baked PVS is, against a dense reference.
//
// Sampling can only miss visibility (every "visible" the bake writes has a witness ray), so the
// error measured is false invisibility:
//  - reference: in `cells` random cells (seeded), exact-as-Embree first-hit rays from
//    `cellPoints` stratified points of the cell towards `objectPoints` area-stratified points on
//    every object, with seeds of its own (never the bake's): the object is visible when some ray's
//    first hit is the object;
//  - object miss rate: reference-visible (cell, object) pairs the PVS culls / reference-visible pairs;
//  - pixel error rate: from `views` random points in each of those cells, a `width` x `height`
//    panorama (equirectangular, every direction) "rendered" by first-hit rays; a pixel is wrong when
//    the object it shows is culled by the cell's row; rate = wrong pixels / all pixels;
//  - PVS size: the bake's visible pairs over the reference's, in those cells (>= 1 can be the
//    bake's conservative boxes or the reference's own sampling misses);
//  - gap list: for each missed pair, every witness ray of the reference (from a point of the cell
//    to where it meets the object) grouped into the openings they pass through, by the same
//    mechanism as a view's openings (suggest/Openings.h): one gap per opening the bake stepped over;
//  - the edge search (EdgeRays.h), for every pair the area rays did not see: rays past the edges of
//    the triangles those rays met first. Its finds are reported apart (edgeVisible, edgeMissed), so
//    the area figures keep their meaning, and together in adversarialMissRate().

#include <atomic>
#include <cstdint>
#include <vector>

#include "visibility/Scene.h"
#include "visibility/pvs/EdgeRays.h"
#include "visibility/suggest/Openings.h"
#include "visibility/pvs/PvsData.h"

namespace sightline::pvs {

struct ReferenceSettings {
    int cells = 64;          ///< random cells (all when the PVS has fewer)
    int cellPoints = 64;
    int objectPoints = 64;
    int views = 4;           ///< panoramas per cell
    int width = 64, height = 32;
    int edgeBlockers = kEdgeBlockers;       ///< blockers per unseen pair the edge search grazes; 0: none
    int edgeCellPoints = kEdgeCellPoints;   ///< cell points the edge rays start from
    std::uint64_t seed = 0x5eed;   ///< mixed with the scene hash
    int threads = 0;
    /// Checked between objects; true stops the measurement (measureAccuracy then throws
    /// PvsCancelled, PvsBake.h): the editor runs it in the background.
    const std::atomic<bool>* cancel = nullptr;
};

/// The witness rays kept per gap for drawing.
inline constexpr std::size_t kGapWitnessSample = 64;

struct Gap {
    std::uint32_t cell = 0, object = 0;
    glm::vec3 from{0.0f}, to{0.0f};   ///< the witness passing closest to the opening's centre: a point of the cell, where it meets the object
    /// Where the pair's witnesses pass (rays: how many of the reference's rays from the cell to the
    /// object pass through it; raySample is left empty, the rays are in `witnesses`).
    suggest::Opening opening;
    std::vector<std::pair<glm::vec3, glm::vec3>> witnesses;   ///< up to kGapWitnessSample of its witness rays
};

struct AccuracyReport {
    std::vector<std::uint32_t> cells;       ///< the reference cells, sorted
    std::uint64_t referenceVisible = 0;     ///< (cell, object) pairs the reference sees
    std::uint64_t bakedVisible = 0;         ///< pairs the PVS keeps, in those cells
    std::uint64_t missed = 0;               ///< reference-visible, culled by the PVS
    std::uint64_t extra = 0;                ///< kept by the PVS, not seen by the reference
    std::uint64_t pixels = 0, wrongPixels = 0;
    std::uint64_t rays = 0;
    std::uint64_t edgeVisible = 0;   ///< pairs the area rays did not see and the edge search did
    std::uint64_t edgeMissed = 0;    ///< of those, pairs the PVS culls
    std::uint64_t edgeRays = 0;
    double ms = 0.0;
    std::vector<Gap> gaps;

    double objectMissRate() const { return referenceVisible ? double(missed) / double(referenceVisible) : 0.0; }
    /// Misses over visible pairs, by the area rays and the edge search together.
    double adversarialMissRate() const
    {
        const std::uint64_t visible = referenceVisible + edgeVisible;
        return visible ? double(missed + edgeMissed) / double(visible) : 0.0;
    }
    double pixelErrorRate() const { return pixels ? double(wrongPixels) / double(pixels) : 0.0; }
    double sizeRatio() const { return referenceVisible ? double(bakedVisible) / double(referenceVisible) : 0.0; }
};

/// Measures `pvs` (baked from `scene`, whose instances its objects name) against the dense
/// reference. Throws sightline::Error when the PVS names an instance the scene lacks.
AccuracyReport measureAccuracy(const Scene& scene, const PvsData& pvs, const ReferenceSettings& settings);

} // namespace sightline::pvs
