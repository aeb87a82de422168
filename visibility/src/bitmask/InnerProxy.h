#pragma once
// Internal to the CPU bitmask sampler: coarse occluders standing in for the inside of a mesh
// ("model no more than a scene needs"). A dense statue costs ray casting and the bitmask
// one unit of work per small triangle, yet most of the rays it blocks pass through its inside. A
// few hundred large faces around a region strictly inside the volume answer those rays through
// the bitmask at the cost of a few-occluder scene, and leave only the rays near its shell to the
// exact method.
//
// Why such a face answers exactly. Take any closed surface (each undirected edge shared by an
// even number of triangles, as in Scene.h's closedAndOutward; it may even cross itself): the
// parity of the number of times a path crosses it is the same for every path between two
// points, so every point off the surface has a parity, 0 far away, changing only where a path
// crosses the surface. Let R be a region whose points all have parity 1 and lie farther than
// kInnerMarginMetres from every triangle. A segment between two points of parity 0 that reaches
// R (or passes within the contract's tie distance of it) must cross the surface between its
// ends, so it is blocked by the contract, or is a tie (it crosses at an edge). And a segment
// from outside R that reaches R crosses R's boundary: so R's boundary faces, as occluders, block
// only blocked rays. The sampler uses a mesh's proxy only while both patches lie outside the
// mesh's bounds (their points then have parity 0); the bitmask answers the faces' rays exactly
// up to the faces' own ties, which lie in R's margin and so are blocked rays too. Faces it
// misses (gaps, culling) only leave rays to the exact method.
//
// Open meshes (a scanned statue without its base, a prop whose hidden bottom was deleted) are
// closed for the argument by caps: for each connected part of the mesh's boundary (the edges an
// odd number of its triangles share, after welding equal positions), the triangles from the
// part's centroid to each of its edges. The mesh and its caps form a closed surface in the sense
// above (every edge shared an even number of times), so R is found for it as for a closed mesh;
// a segment that reaches R then crosses the mesh or a cap, and the rays that meet a box around a
// cap (tested one by one in double, only those the proxies blocked) are taken back from their
// answer.
//
// How R is found. The mesh's bounds are cut into cubic voxels; a voxel that no triangle's box
// (grown by the margin) touches holds no surface, so its parity is that of its centre, taken
// along the line through the voxel centres of its x column: the column's crossings are counted
// in double, and a column whose line passes within kColumnClearanceMetres of a triangle edge
// (where the count could round either way) is left out. R is the union of the odd voxels; its
// boundary, the voxel faces with an odd voxel on one side only, is merged greedily into
// rectangles per plane, rounded to float toward R.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "Occluders.h"
#include "Shaft.h"
#include "TilePass.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/Scene.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/ShaftGeometry.h"
#include "visibility/SourceJitter.h"

namespace sightline::bitmask {

/// How far R stays from the surface: ten times the contract's tie distance (1e-5 m), so a ray
/// the bitmask counts as touching one of R's faces (a tie of the face) still passes through the
/// inside.
inline constexpr double kInnerMarginMetres = 1e-4;

/// A voxel column's line passing closer than this to a triangle edge (in the projection along
/// x) leaves the column out: far above double rounding at any accepted coordinate (1e6 m:
/// ~1e-10 m), so the crossings counted elsewhere are the true ones.
inline constexpr double kColumnClearanceMetres = 1e-6;

/// The boundary of R (above) for the closed surface of `triangleCount` triangles (three
/// vertices each at `vertices`), from a grid of `resolution` voxels along the longest side of
/// their bounds, as outward-facing triangles (counter-clockwise seen from outside R, the winding
/// of Scene.h), three vertices each. The surface must be closed (each edge shared by an even
/// number of triangles: a closed mesh, or an open one with its boundaryCaps); its orientation
/// does not matter. Empty when no voxel clears the surface.
std::vector<glm::vec3> innerProxyTriangles(const glm::vec3* vertices, std::size_t triangleCount, int resolution);

/// The caps of a mesh's boundary (above), one list of triangles (three vertices each) per
/// connected part of the boundary; none for a closed mesh.
std::vector<std::vector<glm::vec3>> boundaryCaps(const glm::vec3* vertices, std::size_t triangleCount);

/// How far a cap's box reaches past the cap: far above double rounding at any accepted
/// coordinate, so the box test of each ray (in double) finds every segment that meets the cap.
inline constexpr double kCapBoxGrowthMetres = 1e-5;

/// A cap's box grown by kCapBoxGrowthMetres, rounded outward to float.
Bounds grownCapBox(const Bounds& capBounds);

/// Whether the segment from p to q meets the box [lo, hi] (slabs in double; a margin in the box
/// absorbs their rounding).
bool segmentMeetsBox(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& lo, const glm::dvec3& hi);

/// Open meshes with more boundary parts than this, or whose caps' boxes fill more than
/// kProxyMaxCapVolumeShare of the mesh's bounds (a terrain's cap is a tent over all of it), get
/// no proxy: the rays near their caps are the ones the proxy would answer.
inline constexpr std::size_t kProxyMaxCaps = 64;
inline constexpr double kProxyMaxCapVolumeShare = 0.25;

/// A call tests each receiver sample against each cap box in the shaft (the box's shadow on the
/// source grid, then the slab test of the samples in it). Per ray and box that test costs about
/// a hundredth of a ray cast, and with a torus's holes in the shaft the boxes give back about a
/// third of the rays the proxy blocked; at few source samples the shadows, one per receiver
/// sample and box, weigh more. So the boxes in the shaft are kept to an eighth of the source
/// samples, two at least and 16 at most; proxies past that sit the call out (a scan with many
/// holes).
inline constexpr double kProxyCapBoxesPerSource = 0.125;
inline constexpr double kProxyMaxCapBoxesPerCall = 16;

/// One instance's proxy: its faces (three vertices each; empty when it has none worth using),
/// their bounds, and the boxes of its caps (none for a closed mesh).
struct InnerProxy {
    std::vector<glm::vec3> faces;
    Bounds faceBounds;
    std::vector<Bounds> capBoxes;
    /// The triangles it was built from, and their hash: a scene replaced with this instance
    /// unchanged, bit for bit (the editor moved another object), keeps the proxy.
    std::vector<glm::vec3> builtFrom;
    std::uint64_t fingerprint = 0;

    /// Whether `triangleCount` triangles at `vertices` are those it was built from.
    bool builtFor(const glm::vec3* vertices, std::size_t triangleCount, std::uint64_t fingerprintOfThem) const;
};

/// Meshes with fewer triangles are left whole: their proxies would cost the bitmask about
/// what the mesh does.
inline constexpr std::size_t kProxyMinTriangles = 512;
/// A proxy is kept only while its faces are at most this part of its mesh's triangles.
inline constexpr double kProxyMaxFaceShare = 0.25;
/// A proxy is built for a call of at least this many rays per triangle of its mesh: building a
/// dense statue's costs several times what it saves a small call (32 x 32²), but a built proxy
/// serves every later call on the scene (the editor samples the same scene many times); a call
/// of a few rays never waits for it.
inline constexpr double kProxyBuildRaysPerTriangle = 0.25;

/// A hash of `triangleCount` triangles at `vertices` (InnerProxy::fingerprint).
std::uint64_t triangleFingerprint(const glm::vec3* vertices, std::size_t triangleCount);

/// The proxy of one instance from its triangles, capped where it is open; no faces below
/// kProxyMinTriangles, above kProxyMaxFaceShare, or past kProxyMaxCaps and
/// kProxyMaxCapVolumeShare.
InnerProxy buildInnerProxy(const glm::vec3* vertices, std::size_t triangleCount, int resolution);

/// Of R's faces, a call backprojects those whose outward normal makes at least this cosine
/// with the shaft's axis (source centre to receiver centre): a ray through R leaves it through a
/// face it sees from behind, and along the axis those are the faces across it. R's faces are
/// axis-aligned and some component of a unit axis is at least 0.577, so one orientation at least
/// is always kept. Any subset answers exactly (a ray missed is left to the strategy). Every face
/// the culling keeps goes in where their pairs are at most kProxyAllFacesPairsPerRay per ray.
/// On dense statues, where a ray meets well under one pair (many source samples), every face
/// answers more rays than the faces across the axis alone (about a fifth of them) and the call
/// is faster; where it meets a few pairs (fewer source samples) the faces across the axis are
/// faster, and at 32 and 64 source samples only they fit the budget below, where they take
/// about half the call's time without proxies.
inline constexpr double kProxyFaceAxisCos = 0.3;
inline constexpr double kProxyAllFacesPairsPerRay = 1.0;

/// The pass runs only while the pairs of the faces it backprojects are at most this many per
/// ray: a pair costs the bitmask a tenth or less of a ray cast through a dense mesh, and the
/// proxies answer over half of a dense statue's blocked rays.
inline constexpr std::uint64_t kProxyPairsPerRay = 4;

/// The call's patches and sampling, for the rays near caps (their segments' ends are built from
/// them only when a cap's box lies in the shaft).
struct PatchPair {
    const Patch& source;
    const Patch& receiver;
    const SourceJitter& jitter;
    const ReceiverHeights* heights = nullptr;   ///< a bumpy receiver's; null: flat
};

/// One call's view of the proxies: the shaft, and the boxes every segment end lies in.
struct ProxyPass {
    /// `receiverPoints`: every receiver-side segment end, or points whose bounds hold them all (a
    /// flat receiver's corners, a bumpy one's displaced samples).
    ProxyPass(const Shaft& shaft, const ShaftHull& hull, const std::array<glm::dvec3, 4>& sourceCorners,
              const std::vector<glm::dvec3>& receiverPoints, const PatchPair& patches, bool culling, bool narrow);

    const Shaft& shaft;
    const ShaftHull& hull;
    PatchPair patches;
    std::array<glm::dvec3, 4> sourceCorners;
    glm::dvec3 sourceLo, sourceHi, receiverLo, receiverHi;
    glm::dvec3 axis;       ///< unit, source centre to the receiver points' centroid
    bool culling = true;   ///< §7's front-face culling (the receiver is apart from every proxy used)
    bool narrow = true;
};

/// Whether a proxy of a mesh with these bounds may serve the call: both patches clear of the
/// bounds by kInnerMarginMetres (the jittered source samples stay in their cells, so the source
/// rectangle bounds them), and the bounds not wholly outside the shaft.
bool proxyApplies(const Bounds& meshBounds, const ProxyPass& pass);

/// ORs into `map` the rays the proxies block (each one proxyApplies), through the faces
/// kProxyFaceAxisCos chooses, less the rays that meet the boxes of their caps. Returns the
/// faces it backprojected, 0 when it did not run (no faces in the shaft, or more pairs than
/// kProxyPairsPerRay allows). `occluders` and `bins` are
/// working storage.
std::size_t seedFromInnerProxies(const std::vector<std::shared_ptr<const InnerProxy>>& proxies, const ProxyPass& pass,
                                 OccluderSet& occluders, TileBins& bins, HiddenSampleMap& map);

} // namespace sightline::bitmask
