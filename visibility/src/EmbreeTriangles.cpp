#include "visibility/EmbreeTriangles.h"

#include <string>

#include "base/Error.h"

namespace sightline {

namespace {

void keepFirstError(void* user, RTCError code, const char* message)
{
    auto* text = static_cast<std::string*>(user);
    if (text->empty())
        *text = std::to_string(int(code)) + ": " + (message ? message : "");
}

} // namespace

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

EmbreeSoupScene::EmbreeSoupScene(std::span<const glm::vec3> vertices, RTCSceneFlags flags, RTCBuildQuality quality)
{
    device = rtcNewDevice(nullptr);
    if (!device)
        throw Error("Embree: cannot create a device");
    try {
        rtcSetDeviceErrorFunction(device, keepFirstError, &error);
        scene = rtcNewScene(device);
        rtcSetSceneFlags(scene, flags);
        rtcSetSceneBuildQuality(scene, quality);
        if (vertices.size() >= 3) {
            RTCGeometry geometry = newTriangleSoup(device, vertices);
            rtcCommitGeometry(geometry);
            rtcAttachGeometry(scene, geometry);
            rtcReleaseGeometry(geometry);
        }
        rtcCommitScene(scene);
        if (!error.empty())
            throw Error("Embree: " + error);
    } catch (...) {
        release();   // a constructor that throws runs no destructor
        throw;
    }
}

EmbreeSoupScene::~EmbreeSoupScene() { release(); }

void EmbreeSoupScene::release()
{
    if (scene)
        rtcReleaseScene(scene);
    if (device)
        rtcReleaseDevice(device);
    scene = nullptr, device = nullptr;
}

} // namespace sightline
