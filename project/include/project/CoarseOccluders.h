#pragma once
// Coarse occluders kept in a project ("model no more than a scene needs", Eisemann & Décoret §10):
// objects of the scene file whose rays are answered by a coarse stand-in. An optional key, kept on
// save like any other:
//
//   "coarse_occluders": [{"instance": 3, "kind": "closest", "triangles": 2000},
//                        {"instance": 7, "kind": "inner", "resolution": 32}]
//
// `closest` is OpenMesh's decimater (plugins/MeshSimplification.h: fewest differences, either way);
// `inner` the faces around a region strictly inside a closed mesh (visibility/InnerOccluder.h:
// never blocks a ray the mesh lets through). Instances are the scene file's, in file order, as in
// `scene_transforms` and `info --json`.
//
// The stand-in answers the rays between the patches only: the shaft and its mask, importance,
// suggest, gaps, disagreement and the editor's live view. The level is still drawn from the full
// mesh, and its AO, lights and PVS are computed on it: they answer about its surfaces.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "project/Project.h"
#include "visibility/Scene.h"

namespace sightline {

inline constexpr const char* kCoarseOccludersKey = "coarse_occluders";

enum class CoarseKind { Closest, Inner };

struct CoarseOccluder {
    std::size_t instance = 0;                           ///< the scene file's instance
    CoarseKind kind = CoarseKind::Closest;
    std::size_t triangles = 5000;                       ///< closest: at most this many triangles, 4..1e8
    int resolution = 32;                                ///< inner: voxels along the longest side, 4..256
    nlohmann::json extra = nlohmann::json::object();   ///< unknown keys, kept

    bool sameStandIn(const CoarseOccluder& other) const
    {
        return kind == other.kind && (kind == CoarseKind::Closest ? triangles == other.triangles
                                                                  : resolution == other.resolution);
    }
};

/// The project's "coarse_occluders", in file order (none when absent). Throws sightline::Error
/// naming the key for a malformed entry or an instance listed twice.
std::vector<CoarseOccluder> coarseOccluders(const Project& project);
/// The key's value for `list` (an empty list: the key is to be removed).
nlohmann::json coarseOccludersJson(const std::vector<CoarseOccluder>& list);
/// "closest, 2000 triangles" or "inner, 32 voxels".
std::string describeCoarse(const CoarseOccluder& spec);

/// The stand-in for `mesh` (object space). Throws sightline::Error when the kind does not apply:
/// an inner stand-in needs a closed, outward mesh, and a thin one may hold no voxel inside.
Mesh coarseOccluderMesh(const Mesh& mesh, const CoarseOccluder& spec);

/// Whether a level-wide replacement gives `mesh` a stand-in of `spec`'s kind: closest, a mesh of
/// more than spec.triangles; inner, a closed and outward mesh of more than 12 triangles.
bool standInApplies(const Mesh& mesh, const CoarseOccluder& spec);

struct ReplacedMeshes {
    std::size_t replaced = 0;
    std::size_t skipped = 0;   ///< inner: meshes of more than 12 triangles left whole for being open
};
/// Every mesh of `scene` that standInApplies to replaced by its stand-in, whichever instance uses
/// it: `sightline-cli coarse`, its sweep and the disagreement view's coarse modes. A thin mesh's
/// inner stand-in may be empty (it then blocks nothing, which is still conservative).
ReplacedMeshes replaceDenseMeshes(Scene& scene, const CoarseOccluder& spec);

/// Stand-ins made before, by mesh content and spec: the editor builds its ray scene again on every
/// edit, and simplifying a dense mesh takes seconds.
class CoarseMeshCache {
public:
    const Mesh& standIn(const Mesh& mesh, const CoarseOccluder& spec);

private:
    std::map<std::tuple<std::uint64_t, int, std::size_t>, Mesh> meshes_;
};

/// Replaces the mesh of each listed instance of `level` (the scene file's instances come first in
/// a built scene, so a full scene works too) by its stand-in, placed by the instance's transform.
/// Throws sightline::Error, naming the key, for an instance the level does not have or a stand-in
/// that does not apply.
void applyCoarseOccluders(const std::vector<CoarseOccluder>& list, Scene& level, CoarseMeshCache* cache = nullptr);

/// buildScene with the project's coarse occluders in place: what the rays between the patches are
/// tested against.
Scene buildRayScene(const Project& project, std::vector<std::string>* warnings = nullptr);

} // namespace sightline
