#pragma once
// A triangle soup as an Embree triangle geometry (Embree's own float intersector): the one way the
// float tracers built on Embree hand it their triangles, 3 vertices per triangle as the scene holds
// them, primitive k the k-th triangle.

#include <span>
#include <string>

#include <embree3/rtcore.h>
#include <glm/vec3.hpp>

namespace sightline {

/// A new geometry holding `vertices` (3 per triangle), not yet committed (filters may still be
/// set). Embree over-allocates the buffers it creates for its 16-byte loads. Throws
/// sightline::Error when it cannot allocate them.
RTCGeometry newTriangleSoup(RTCDevice device, std::span<const glm::vec3> vertices);

/// A device and a committed scene holding one triangle soup (geometry 0), released together.
/// Embree's errors are kept in `error` (the first one); construction throws sightline::Error on
/// any. Neither copied nor moved: the device holds the address of `error`.
struct EmbreeSoupScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::string error;

    EmbreeSoupScene(std::span<const glm::vec3> vertices, RTCSceneFlags flags, RTCBuildQuality quality);
    ~EmbreeSoupScene();
    EmbreeSoupScene(const EmbreeSoupScene&) = delete;
    EmbreeSoupScene& operator=(const EmbreeSoupScene&) = delete;

private:
    void release();
};

} // namespace sightline
