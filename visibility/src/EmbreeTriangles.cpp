#include "visibility/EmbreeTriangles.h"

#include <string>

#include "visibility/Error.h"

namespace sightline {

RTCGeometry newTriangleSoup(RTCDevice device, std::span<const glm::vec3> vertices)
{
    const std::size_t triangles = vertices.size() / 3;
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices.size()));
    auto* index = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles));
    if (!v || !index) {
        rtcReleaseGeometry(geometry);
        throw Error("Embree: out of memory for " + std::to_string(triangles) + " triangles");
    }
    for (std::size_t k = 0; k < vertices.size(); ++k) {
        v[3 * k] = vertices[k].x, v[3 * k + 1] = vertices[k].y, v[3 * k + 2] = vertices[k].z;
        index[k] = unsigned(k);
    }
    return geometry;
}

} // namespace sightline
