#include "lights/FloatShadowRays.h"

#include <algorithm>
#include <string>

#include <embree3/rtcore.h>

#include "visibility/EmbreeTriangles.h"
#include "base/Error.h"

namespace sightline::lights {

namespace {

constexpr float kEndOffset = 1e-4f;   ///< of the way, off each end (the shaded point and the light)

} // namespace

/// Flat, not robust, a high-quality build: what a user tuning Embree for speed would pick.
struct FloatShadowRays::Embree {
    EmbreeSoupScene soup;
    std::size_t triangles = 0;

    explicit Embree(const WorldTriangles& world)
        : soup(world.vertices, RTC_SCENE_FLAG_NONE, RTC_BUILD_QUALITY_HIGH), triangles(world.vertices.size() / 3)
    {
    }
};

FloatShadowRays::FloatShadowRays(const WorldTriangles& triangles) : embree_(std::make_unique<Embree>(triangles)) {}

FloatShadowRays::~FloatShadowRays() = default;

namespace {

/// `count` float rays in packets of 16, ray i from start(i) to end(i), kept kEndOffset of the way
/// off each end; blocked[i] gets the answer.
template <typename Start, typename End>
void castPackets(RTCScene scene, std::size_t count, Start&& start, End&& end, std::uint8_t* blocked)
{
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRay16 rays;
    alignas(64) int valid[16];
    for (std::size_t first = 0; first < count; first += 16) {
        for (int k = 0; k < 16; ++k) {
            const std::size_t i = first + std::size_t(k);
            valid[k] = i < count ? -1 : 0;
            const glm::vec3 org = i < count ? glm::vec3(start(i)) : glm::vec3(0.0f);
            const glm::vec3 dir = i < count ? glm::vec3(end(i) - start(i)) : glm::vec3(1.0f, 0.0f, 0.0f);
            rays.org_x[k] = org.x, rays.org_y[k] = org.y, rays.org_z[k] = org.z;
            rays.dir_x[k] = dir.x, rays.dir_y[k] = dir.y, rays.dir_z[k] = dir.z;
            rays.tnear[k] = kEndOffset;
            rays.tfar[k] = 1.0f - kEndOffset;
            rays.time[k] = 0.0f;
            rays.mask[k] = 0xffffffffu;
            rays.id[k] = unsigned(k);
            rays.flags[k] = 0;
        }
        rtcOccluded16(valid, scene, &context, &rays);
        for (int k = 0; k < 16 && first + std::size_t(k) < count; ++k)
            blocked[first + std::size_t(k)] = rays.tfar[k] < 0.0f ? 1 : 0;
    }
}

} // namespace

void FloatShadowRays::blocked(const glm::dvec3& start, std::span<const glm::dvec3> ends, std::uint8_t* blocked) const
{
    std::fill(blocked, blocked + ends.size(), std::uint8_t(0));
    if (embree_->triangles == 0)
        return;
    castPackets(embree_->soup.scene, ends.size(), [&](std::size_t) { return start; }, [&](std::size_t i) { return ends[i]; }, blocked);
    if (!embree_->soup.error.empty())
        throw Error("Embree: " + embree_->soup.error);
}

void FloatShadowRays::blocked(std::span<const glm::dvec3> starts, std::span<const glm::dvec3> ends, std::uint8_t* blocked) const
{
    if (starts.size() != ends.size())
        throw Error("FloatShadowRays::blocked: as many starts as ends are needed");
    std::fill(blocked, blocked + ends.size(), std::uint8_t(0));
    if (embree_->triangles == 0)
        return;
    castPackets(embree_->soup.scene, ends.size(), [&](std::size_t i) { return starts[i]; }, [&](std::size_t i) { return ends[i]; }, blocked);
    if (!embree_->soup.error.empty())
        throw Error("Embree: " + embree_->soup.error);
}

} // namespace sightline::lights
