#include "lights/RegionShafts.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "lighting/LightEmission.h"

namespace sightline::lights {

namespace {

struct Box {
    glm::dvec3 lo, hi;
};

/// Whether the segment a-b (or, `ray`, the ray from a through b) meets the box (slab test; the
/// box already carries the margin).
bool segmentMeetsBox(const glm::dvec3& a, const glm::dvec3& b, const Box& box, bool ray = false)
{
    double t0 = 0.0, t1 = ray ? INFINITY : 1.0;
    for (int axis = 0; axis < 3; ++axis) {
        const double d = b[axis] - a[axis];
        if (d == 0.0) {
            if (a[axis] < box.lo[axis] || a[axis] > box.hi[axis])
                return false;
            continue;
        }
        double near = (box.lo[axis] - a[axis]) / d, far = (box.hi[axis] - a[axis]) / d;
        if (near > far)
            std::swap(near, far);
        t0 = std::max(t0, near);
        t1 = std::min(t1, far);
        if (t0 > t1)
            return false;
    }
    return true;
}

/// A region grown by far more than float rounding at its coordinates (the geometry inside it is
/// float, the segments double).
Box grown(const Bounds& region)
{
    const glm::dvec3 lo(region.min), hi(region.max);
    const double margin = 1e-5 * (1.0 + glm::length(glm::max(glm::abs(lo), glm::abs(hi))));
    return {lo - margin, hi + margin};
}

Box grown(const Box& box, double by) { return {box.lo - by, box.hi + by}; }

/// A set of points as a ball: its box's centre and half diagonal.
struct Ball {
    glm::dvec3 centre;
    double radius;
};
Ball ballOf(const glm::dvec3& lo, const glm::dvec3& hi) { return {0.5 * (lo + hi), 0.5 * glm::length(hi - lo)}; }

} // namespace

std::vector<std::uint32_t> pointsShadowedThrough(const Light& light, std::span<const Bounds> regions,
                                                 const std::vector<PointTile>& tiles, std::span<const ShadingPoint> points)
{
    std::vector<std::uint32_t> out;
    std::vector<Box> boxes;
    for (const Bounds& region : regions)
        if (!region.empty())
            boxes.push_back(grown(region));
    if (boxes.empty())
        return out;
    const bool directional = light.type == LightType::Directional;
    const bool ranged = (light.type == LightType::Point || light.type == LightType::Spot) && light.range > 0.0;
    std::vector<glm::dvec3> emitters;
    for (const Emitter& e : lightEmitters({light}))
        emitters.push_back(e.position);
    glm::dvec3 lo = emitters[0], hi = emitters[0];
    for (const glm::dvec3& e : emitters)
        lo = glm::min(lo, e), hi = glm::max(hi, e);
    const Ball source = ballOf(lo, hi);
    // A segment from a point of ball A to a point of ball B stays within max(rA, rB) of the
    // segment between their centres (it is (1-t)(cA + a) + t(cB + b) with |a| <= rA, |b| <= rB),
    // so it can meet a box only if that centre segment meets the box grown by the larger radius.
    // A directional light's segments run from each point against its direction to beyond the
    // scene (DirectionalReach::end); they are taken as rays, which hold them whatever the scene's
    // bounds were or are (a change beyond the new bounds is still met).
    const auto shaftMeets = [&](const glm::dvec3& from, const glm::dvec3& to, double radius, const Box& box) {
        return segmentMeetsBox(from, to, grown(box, radius), directional);
    };
    std::vector<const Box*> near;
    for (const PointTile& tile : tiles) {
        const Ball receiver = ballOf(tile.lo, tile.hi);
        // A directional light's rays are parallel: within the tile's radius of the centre's ray.
        const glm::dvec3 to = directional ? receiver.centre - light.direction : source.centre;
        const double radius = directional ? receiver.radius : std::max(receiver.radius, source.radius);
        near.clear();
        for (const Box& box : boxes)
            if (shaftMeets(receiver.centre, to, radius, box))
                near.push_back(&box);
        if (near.empty())
            continue;
        for (const std::uint32_t j : tile.points) {
            const glm::dvec3& x = points[j].position;
            if (ranged && glm::length(light.position - x) >= light.range)
                continue;
            const auto meets = [&](const glm::dvec3& end) {
                return std::any_of(near.begin(), near.end(), [&](const Box* box) { return segmentMeetsBox(x, end, *box, directional); });
            };
            bool any = false;
            if (directional)
                any = meets(x - light.direction);
            else if (emitters.size() == 1)
                any = meets(emitters[0]);
            else   // an area light's samples: first the point's whole shaft to them, then each
                any = std::any_of(near.begin(), near.end(), [&](const Box* box) { return shaftMeets(x, source.centre, source.radius, *box); }) &&
                      std::any_of(emitters.begin(), emitters.end(), meets);
            if (any)
                out.push_back(j);
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

} // namespace sightline::lights
