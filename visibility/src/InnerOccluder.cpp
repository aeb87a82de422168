#include "visibility/InnerOccluder.h"

#include "bitmask/InnerProxy.h"
#include "base/Error.h"

namespace sightline {

Mesh innerOccluderMesh(const Mesh& mesh, int resolution)
{
    if (!closedAndOutward(mesh))
        throw Error("mesh '" + mesh.name + "' is not closed and outward-facing: only a closed mesh has an inside to "
                    "stand a conservative occluder in (its holes would let rays past)");
    std::vector<glm::vec3> corners;
    corners.reserve(mesh.indices.size());
    for (const std::uint32_t i : mesh.indices)
        corners.push_back(mesh.positions[i]);
    const std::vector<glm::vec3> inner = bitmask::innerProxyTriangles(corners.data(), mesh.triangleCount(), resolution);
    Mesh out;
    out.name = mesh.name + " (inner)";
    out.positions = inner;
    for (std::uint32_t i = 0; i < inner.size(); ++i)
        out.indices.push_back(i);
    return out;
}

} // namespace sightline
