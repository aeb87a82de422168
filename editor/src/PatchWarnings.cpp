#include "editor/PatchWarnings.h"

#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "editor/Picking.h"

namespace sightline::ui {

namespace {

/// The triangle's own (winding) normal, unit.
glm::dvec3 windingNormal(const WorldTriangles& triangles, std::size_t t)
{
    const glm::dvec3 a(triangles.vertices[3 * t]), b(triangles.vertices[3 * t + 1]), c(triangles.vertices[3 * t + 2]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double length = glm::length(n);
    return length > 0.0 ? n / length : glm::dvec3(0.0);
}

void warnAbout(const WorldTriangles& triangles, const Bounds& level, const Patch& patch, const Patch& other, const char* role,
               const char* otherRole, std::vector<std::string>& out)
{
    const glm::dvec3 centre = patch.centre(), normal = patch.normal();
    if (glm::dot(normal, other.centre() - centre) < 0.0)
        out.push_back(std::string("the ") + role + " faces away from the " + otherRole);
    if (const auto hit = pickSurface(triangles, Ray{centre, normal}); hit && hit->distance < kFacingSurfaceMetres) {
        char text[96];
        std::snprintf(text, sizeof text, "the %s faces a surface %.0f cm in front of it", role, std::max(1.0, std::round(100.0 * hit->distance)));
        out.emplace_back(text);
    }
    if (!level.empty()) {
        const glm::dvec3 lo(level.min), hi(level.max);
        const double margin = 0.01 * glm::length(hi - lo);
        // Beside or above the level; below it is the floor check's case.
        if (centre.x < lo.x - margin || centre.x > hi.x + margin || centre.z < lo.z - margin || centre.z > hi.z + margin ||
            centre.y > hi.y + margin) {
            out.push_back(std::string("the ") + role + " is outside the level");
            return;   // nothing else about it means much
        }
    }
    // Straight up, the first surface is a floor's top seen from below, and straight down there is
    // no floor to stand on (nothing, or an underside): the patch is under the floor. (An up-facing
    // ceiling, a common wrong winding, has the room's floor below it.)
    const auto above = pickSurface(triangles, Ray{centre, {0.0, 1.0, 0.0}});
    if (above && windingNormal(triangles, above->triangle).y > 0.5) {
        const auto below = pickSurface(triangles, Ray{centre, {0.0, -1.0, 0.0}});
        if (!below || windingNormal(triangles, below->triangle).y < -0.5)
            out.push_back(std::string("the ") + role + " is below a floor");
    }
}

} // namespace

std::vector<std::string> patchWarnings(const WorldTriangles& triangles, const Bounds& level, const Patch& source, const Patch& receiver)
{
    std::vector<std::string> out;
    warnAbout(triangles, level, source, receiver, "source", "receiver", out);
    warnAbout(triangles, level, receiver, source, "receiver", "source", out);
    return out;
}

} // namespace sightline::ui
