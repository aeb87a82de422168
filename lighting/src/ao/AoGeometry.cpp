#include "lighting/ao/AoGeometry.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace sightline {

double AoOccluders::diagonal() const
{
    if (bounds.empty())
        return 0.0;
    return glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min));
}

AoOccluders aoOccluders(const Scene& scene)
{
    AoOccluders out;
    for (const Instance& instance : scene.instances) {
        const Mesh& mesh = scene.meshes[instance.mesh];
        const auto base = std::uint32_t(out.vertices.size());
        for (const glm::vec3& p : mesh.positions) {
            const glm::vec3 w = glm::vec3(instance.transform * glm::vec4(p, 1.0f));
            out.vertices.push_back(w);
            out.bounds.extend(w);
        }
        for (std::uint32_t index : mesh.indices)
            out.indices.push_back(base + index);
    }
    return out;
}

std::size_t AoPoints::count(AoPointStatus s) const
{
    std::size_t n = 0;
    for (AoPointStatus t : status)
        n += t == s;
    return n;
}

void AoPoints::offsetOrigins(double offset)
{
    origins.resize(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i)
        origins[i] = glm::vec3(glm::dvec3(positions[i]) + offset * glm::dvec3(normals[i]));
}

namespace {

bool usable(const glm::vec3& n)
{
    return std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) && glm::dot(n, n) > 1e-30f;
}

} // namespace

AoPoints aoVertexPoints(const Scene& scene)
{
    AoPoints points;
    for (const Instance& instance : scene.instances) {
        const Mesh& mesh = scene.meshes[instance.mesh];
        const glm::mat3 linear(instance.transform);
        const glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));
        std::vector<glm::dvec3> faceSum(mesh.positions.size(), glm::dvec3(0.0));
        std::vector<std::uint8_t> onFace(mesh.positions.size(), 0);
        for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
            const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
            // Twice the area times the unit normal: the area-weighted mean.
            const glm::dvec3 n = glm::cross(glm::dvec3(mesh.positions[b]) - glm::dvec3(mesh.positions[a]),
                                            glm::dvec3(mesh.positions[c]) - glm::dvec3(mesh.positions[a]));
            for (std::uint32_t v : {a, b, c}) {
                faceSum[v] += n;
                onFace[v] = 1;
            }
        }
        const bool ownNormals = mesh.normals.size() == mesh.positions.size();
        for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
            points.positions.push_back(glm::vec3(instance.transform * glm::vec4(mesh.positions[v], 1.0f)));
            if (!onFace[v]) {
                points.normals.emplace_back(0.0f);
                points.status.push_back(AoPointStatus::NoFace);
                continue;
            }
            glm::vec3 n = ownNormals && usable(mesh.normals[v]) ? mesh.normals[v] : glm::vec3(faceSum[v]);
            if (usable(n))
                n = normalMatrix * n;
            if (usable(n) && usable(glm::normalize(n))) {
                points.normals.push_back(glm::normalize(n));
                points.status.push_back(AoPointStatus::Ok);
            } else {
                points.normals.emplace_back(0.0f);
                points.status.push_back(AoPointStatus::ZeroNormal);
            }
        }
    }
    return points;
}

} // namespace sightline
