#include "visibility/SegmentHits.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>

#include "visibility/Error.h"

namespace sightline {

struct SegmentHitCaster::Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    bool empty = true;

    ~Embree()
    {
        if (scene)
            rtcReleaseScene(scene);
        if (device)
            rtcReleaseDevice(device);
    }
};

SegmentHitCaster::SegmentHitCaster(const WorldTriangles& triangles) : embree_(std::make_unique<Embree>())
{
    Embree& e = *embree_;
    e.device = rtcNewDevice(nullptr);
    if (!e.device)
        throw Error("Embree: cannot create a device (" + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    e.scene = rtcNewScene(e.device);
    e.empty = triangles.size() == 0;
    if (!e.empty) {
        RTCGeometry geometry = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                     3 * sizeof(float), triangles.vertices.size()));
        auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                       3 * sizeof(unsigned), triangles.size()));
        if (!vertices || !indices) {
            rtcReleaseGeometry(geometry);
            throw Error("Embree: out of memory for " + std::to_string(triangles.size()) + " triangles");
        }
        for (std::size_t k = 0; k < triangles.vertices.size(); ++k) {
            vertices[3 * k] = triangles.vertices[k].x;
            vertices[3 * k + 1] = triangles.vertices[k].y;
            vertices[3 * k + 2] = triangles.vertices[k].z;
            indices[k] = unsigned(k);   // a triangle soup: vertices 3t, 3t+1, 3t+2
        }
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(e.scene, geometry);
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(e.scene);
    if (rtcGetDeviceError(e.device) != RTC_ERROR_NONE)
        throw Error("Embree: building the scene for ray hits failed");
}

SegmentHitCaster::~SegmentHitCaster() = default;

float SegmentHitCaster::firstHit(const glm::dvec3& from, const glm::dvec3& to) const
{
    const glm::dvec3 d = to - from;
    if (embree_->empty || !(glm::dot(d, d) > 0.0))
        return 1.0f;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit hit{};
    hit.ray.org_x = float(from.x), hit.ray.org_y = float(from.y), hit.ray.org_z = float(from.z);
    hit.ray.dir_x = float(d.x), hit.ray.dir_y = float(d.y), hit.ray.dir_z = float(d.z);
    // The segment's own ends do not count (a ray from a patch on a wall starts at the wall).
    constexpr float kEnds = 1e-4f;
    hit.ray.tnear = kEnds;
    hit.ray.tfar = 1.0f - kEnds;
    hit.ray.mask = 0xFFFFFFFFu;
    hit.ray.flags = 0;
    hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(embree_->scene, &context, &hit);
    return hit.hit.geomID == RTC_INVALID_GEOMETRY_ID ? 1.0f : hit.ray.tfar;
}

} // namespace sightline
