#include "visibility/pvs/EdgeRays.h"

#include <algorithm>

#include <glm/geometric.hpp>

namespace sightline::pvs {

std::vector<std::int64_t> mostMet(const std::unordered_map<std::int64_t, int>& met, int count)
{
    std::vector<std::pair<std::int64_t, int>> sorted(met.begin(), met.end());
    std::sort(sorted.begin(), sorted.end(),
              [](const auto& x, const auto& y) { return x.second != y.second ? x.second > y.second : x.first < y.first; });
    std::vector<std::int64_t> out;
    for (std::size_t k = 0; k < sorted.size() && out.size() < std::size_t(std::max(count, 0)); ++k)
        out.push_back(sorted[k].first);
    return out;
}

bool edgeWitness(const std::vector<glm::vec3>& triangleVertices, const FirstHitCaster& caster,
                 const std::vector<std::int32_t>& objectOf, std::int32_t object, const Bounds& objectBox,
                 const std::vector<glm::vec3>& from, const std::vector<std::int64_t>& blockers, std::uint64_t& rays)
{
    for (std::int64_t t : blockers) {
        const glm::vec3* v = &triangleVertices[3 * std::size_t(t)];
        for (int e = 0; e < 3; ++e) {
            const glm::vec3 a = v[e], b = v[(e + 1) % 3], opposite = v[(e + 2) % 3];
            const glm::vec3 edge = b - a;
            const float length = glm::length(edge);
            if (!(length > 0.0f))
                continue;
            // Out of the triangle, in its plane, across this edge.
            glm::vec3 out = (a + b) * 0.5f - opposite;
            out -= edge * (glm::dot(out, edge) / (length * length));
            const float outLength = glm::length(out);
            if (!(outLength > 0.0f))
                continue;
            out *= std::max(1e-5f * length, 2e-5f) / outLength;
            for (float s : {0.25f, 0.5f, 0.75f}) {
                const glm::vec3 past = a + edge * s + out;
                for (const glm::vec3& p : from) {
                    const glm::vec3 direction = past - p;
                    const float d = glm::length(direction);
                    if (!(d > 0.0f))
                        continue;
                    float reach = 0.0f;   // on to the object's far side
                    for (int k = 0; k < 8; ++k) {
                        const glm::vec3 corner((k & 1) ? objectBox.max.x : objectBox.min.x, (k & 2) ? objectBox.max.y : objectBox.min.y,
                                               (k & 4) ? objectBox.max.z : objectBox.min.z);
                        reach = std::max(reach, glm::length(corner - p));
                    }
                    ++rays;
                    const RayHit hit = caster.cast(p, direction, reach / d * 1.01f);
                    if (hit.instance >= 0 && objectOf[std::size_t(hit.instance)] == object)
                        return true;
                }
            }
        }
    }
    return false;
}

} // namespace sightline::pvs
