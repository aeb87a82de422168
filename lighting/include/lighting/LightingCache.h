#pragma once
// Amortised many-light updates for a live view (Barczak 2006 §4: shadow maps refreshed by
// priority within a budget per frame): each light's shadowed contribution at the view's points is
// kept, so that moving one light costs that light's shadow rays alone, and after an occluder moves
// only the points whose shadow segments could pass where it was or is go stale, light by light,
// and are refreshed, the brightest and longest stale lights first, until a frame's budget of
// shadow segments is spent. The view converges to the exact answer and
// says when it has.
//
// A light's contribution is its colour times a scalar field (the shadowed sum of its terms with a
// white colour, computed by the exact fast path of DirectLight.h), kept in float per point. The
// shown irradiance is updated by differences as lights refresh; once none is stale it is summed
// again from the kept fields in double, light by light, so an exact frame is the reference's
// answer up to the fields' float rounding (below 1e-6 relative).
//
// A light being dragged can take Barczak's low-resolution pass first (LowResolutionPass.h): its
// field at the coarse points, interpolated between them where they agree and exact where they do
// not. It stays stale after that pass, so the next frame refreshes it exactly unless it moved again.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/DirectLight.h"
#include "lighting/Light.h"
#include "lighting/LowResolutionPass.h"
#include "visibility/Scene.h"

namespace sightline {

class LightingCache {
public:
    /// Every light starts stale. `lights` must have passed validateLights, `points`
    /// validateShadingPoints.
    LightingCache(std::vector<ShadingPoint> points, std::vector<Light> lights);
    /// With a plan over the same points for the low-resolution pass.
    LightingCache(std::vector<ShadingPoint> points, std::vector<Light> lights, LowResolutionPlan plan);
    ~LightingCache();

    /// Light `index` moved or changed: stale until refreshed; the view shows its old light until
    /// then. `rough`: (with a plan) the next update gives it the low-resolution pass first.
    void setLight(std::size_t index, const Light& light, bool rough = false);
    /// Something inside the boxes `regions` changed (an occluder moved, was added or removed there;
    /// the points stay). Per light, the points one of whose segments to it may meet a region go
    /// stale (lights/RegionShafts.h) and are refreshed alone: every other point's segments avoid
    /// the regions, so they are blocked or free as before and its field stands.
    void sceneChanged(std::span<const Bounds> regions);
    /// The same where the points changed with the scene (a moved occluder carries texels of its
    /// own): `points` replace the cache's, `previous[j]` is new point j's index among the old
    /// points or SIZE_MAX (a new point: stale for every light), and `plan` covers the new points.
    /// A point kept has the same position and normal, so its field is carried over.
    void sceneChanged(std::span<const Bounds> regions, std::vector<ShadingPoint> points,
                      std::span<const std::size_t> previous, LowResolutionPlan plan);

    struct Frame {
        std::size_t refreshed = 0;      ///< lights refreshed this frame
        std::vector<std::size_t> lights;   ///< which, in the order refreshed
        std::size_t rough = 0;          ///< of those, by the low-resolution pass (still stale)
        std::size_t stale = 0;          ///< lights still stale after it
        std::uint64_t segments = 0;     ///< shadow segments those refreshes could cast (points x samples)
        bool exact = false;             ///< no light stale: the view is the exact answer
        double ms = 0.0;
    };
    /// Gives the lights set rough their low-resolution pass, then refreshes stale lights by
    /// priority (brightness x (1 + frames stale); a light never computed first) until `budget`
    /// segments are spent, at least one light a frame. `scene` is the scene as it is now.
    Frame update(const LightingScene& scene, std::uint64_t budget, int threads = 0);

    const std::vector<glm::dvec3>& irradiance() const { return shown_; }
    /// Per point, the share of its shown irradiance that comes from stale lights (0 to 1), and 1
    /// where a change in the scene may have moved a light's shadows (by an unknown amount): the
    /// staleness overlay.
    std::vector<float> staleness() const;
    std::size_t staleCount() const;
    bool isStale(std::size_t index) const { return kept_.at(index).stale; }
    /// Light `index`'s kept field (its shadowed white contribution per point, as last computed);
    /// empty before it is first computed. The overlays read it: how many lights reach a point,
    /// and (against the unshadowed terms) which of them are fully lit, partial or shadowed there.
    const std::vector<float>& field(std::size_t index) const { return kept_.at(index).field; }
    const std::vector<ShadingPoint>& points() const { return points_; }
    /// The light's shown energy over the points (its field's sum times its mean colour): the
    /// priority's weight; 0 before it is first computed.
    double brightness(std::size_t index) const { return kept_.at(index).brightness; }
    const std::vector<Light>& lights() const { return lights_; }

    /// What a light cost when last refreshed (O'Rorke's and Barczak's question: which lights are
    /// worth their shadows), for the editor's cost panel.
    struct LightCost {
        int samples = 0;               ///< point lights it is sampled into (an area light's grid)
        std::uint64_t terms = 0;       ///< (point, sample) pairs it lights before shadowing
        std::uint64_t rays = 0;        ///< shadow rays those cost (the rest decided by tile proofs)
        double ms = 0.0;               ///< its last refresh
        std::uint64_t age = 0;         ///< frames since it was last refreshed exactly
        bool stale = true;
        bool rough = false;            ///< last shown from the low-resolution pass
    };
    LightCost cost(std::size_t index) const;

private:
    struct Kept {
        std::vector<float> field;       ///< shadowed white contribution per point, as last computed
        glm::dvec3 colour{0.0};         ///< the colour that field was shown with
        double brightness = 0.0;        ///< sum of field x mean colour: the priority's weight
        bool computed = false;
        bool stale = true;
        bool whole = true;              ///< stale everywhere; else at `stalePoints` alone
        std::vector<std::uint32_t> stalePoints;   ///< ascending, when stale but not whole
        bool roughNext = false;         ///< the next update gives it the low-resolution pass
        std::uint64_t staleSince = 0;   ///< frame it went stale
        std::uint64_t refreshedAt = 0;  ///< frame of its last exact refresh
        LightCost cost;
    };

    void resum();
    /// resum() where a refresh changed the view since the last sum (every point once a whole
    /// light was refreshed): elsewhere the view already is that sum.
    void resumTouched();
    void markStale(std::size_t index);
    /// Light `index` stale at `points` (ascending) besides what already is.
    void markStalePoints(std::size_t index, std::vector<std::uint32_t> points);
    void setPlan(LowResolutionPlan plan);
    /// Points light `index` must refresh: all of them when whole.
    std::size_t stalePointCount(std::size_t index) const;
    /// Shows `field` as light `index`'s (by differences) and keeps it.
    void keep(std::size_t index, std::vector<float> field);
    /// The same for its stale points alone (`values` in their order).
    void keepAt(std::size_t index, const std::vector<float>& values);
    /// The low-resolution pass's field of `light`; `segments` gets the points it cast to,
    /// `stats` what directIrradiance counted.
    std::vector<float> roughField(const LightingScene& scene, const Light& light, int threads, std::uint64_t& segments,
                                  DirectLightStats& stats) const;

    std::vector<ShadingPoint> points_;
    std::unique_ptr<PointTiling> tiling_;
    LowResolutionPlan plan_;
    std::vector<ShadingPoint> coarsePoints_;   ///< plan_.coarse's points, in its order
    std::unique_ptr<PointTiling> coarseTiling_;
    std::vector<Light> lights_;
    std::vector<Kept> kept_;
    std::vector<glm::dvec3> shown_;
    std::vector<std::uint32_t> touched_;   ///< points keepAt changed since the last sum (repeats allowed)
    bool touchedAll_ = false;              ///< keep changed every point since the last sum
    std::uint64_t frame_ = 0;
};

} // namespace sightline
