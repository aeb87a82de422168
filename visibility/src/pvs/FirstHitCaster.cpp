#include "visibility/pvs/FirstHitCaster.h"

#include <embree3/rtcore.h>

#include "visibility/EmbreeTriangles.h"

namespace sightline::pvs {

/// The world's triangles in Embree's robust mode (FirstHitCaster.h), and each one's instance.
struct FirstHitCaster::Embree {
    std::vector<std::uint32_t> instanceOf;
    std::vector<glm::vec3> vertices;
    EmbreeSoupScene soup;

    explicit Embree(WorldTriangles world)
        : instanceOf(std::move(world.instanceOf)), vertices(std::move(world.vertices)),
          soup(vertices, RTC_SCENE_FLAG_ROBUST, RTC_BUILD_QUALITY_HIGH)
    {
    }
};

FirstHitCaster::FirstHitCaster(const Scene& scene)
{
    WorldTriangles world = worldTriangles(scene);
    validateCoordinates(world, "scene");
    embree_ = std::make_unique<Embree>(std::move(world));
}

FirstHitCaster::~FirstHitCaster() = default;

std::size_t FirstHitCaster::triangleCount() const { return embree_->instanceOf.size(); }

float segmentFirstHit(const FirstHitCaster& caster, const glm::dvec3& from, const glm::dvec3& to)
{
    const glm::dvec3 d = to - from;
    if (!(glm::dot(d, d) > 0.0))
        return 1.0f;
    constexpr double kEnds = 1e-4;
    const RayHit hit = caster.cast(glm::vec3(from + kEnds * d), glm::vec3(d), float(1.0 - 2.0 * kEnds));
    return hit.instance < 0 ? 1.0f : float(kEnds + double(hit.t));
}

RayHit FirstHitCaster::cast(const glm::vec3& origin, const glm::vec3& direction, float tnear, float tfar) const
{
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_x = origin.x;
    rh.ray.org_y = origin.y;
    rh.ray.org_z = origin.z;
    rh.ray.dir_x = direction.x;
    rh.ray.dir_y = direction.y;
    rh.ray.dir_z = direction.z;
    rh.ray.tnear = tnear;
    rh.ray.tfar = tfar;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(embree_->soup.scene, &context, &rh);
    RayHit out;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return out;
    out.instance = embree_->instanceOf[rh.hit.primID];
    out.triangle = std::int64_t(rh.hit.primID);
    out.t = rh.ray.tfar;
    out.normal = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
    return out;
}

} // namespace sightline::pvs
