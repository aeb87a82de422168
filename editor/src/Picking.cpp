#include "editor/Picking.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sightline::ui {

std::optional<SurfaceHit> pickSurface(const WorldTriangles& triangles, const Ray& ray,
                                      const std::function<bool(std::size_t, const glm::dvec3&)>& visible)
{
    // Möller-Trumbore in double precision.
    std::optional<SurfaceHit> best;
    double bestT = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::dvec3 p0(triangles.vertices[3 * t]);
        const glm::dvec3 e1 = glm::dvec3(triangles.vertices[3 * t + 1]) - p0;
        const glm::dvec3 e2 = glm::dvec3(triangles.vertices[3 * t + 2]) - p0;
        const glm::dvec3 p = glm::cross(ray.direction, e2);
        const double det = glm::dot(e1, p);
        if (std::abs(det) < 1e-14)
            continue;
        const double inv = 1.0 / det;
        const glm::dvec3 s = ray.origin - p0;
        const double b1 = glm::dot(s, p) * inv;
        if (b1 < 0.0 || b1 > 1.0)
            continue;
        const glm::dvec3 q = glm::cross(s, e1);
        const double b2 = glm::dot(ray.direction, q) * inv;
        if (b2 < 0.0 || b1 + b2 > 1.0)
            continue;
        const double dist = glm::dot(e2, q) * inv;
        if (dist <= 1e-9 || dist >= bestT)
            continue;
        if (visible && !visible(t, ray.origin + dist * ray.direction))
            continue;
        bestT = dist;
        glm::dvec3 n = glm::cross(e1, e2);
        const double len = glm::length(n);
        if (len == 0.0)
            continue;
        n /= len;
        if (glm::dot(n, ray.direction) > 0.0)
            n = -n;
        best = SurfaceHit{dist, ray.origin + dist * ray.direction, n, t};
    }
    return best;
}

std::optional<PatchSampleHit> pickPatchSample(const Patch& patch, const Ray& ray)
{
    const glm::dvec3 n = glm::cross(patch.u, patch.v);
    const double denom = glm::dot(n, ray.direction);
    if (std::abs(denom) < 1e-14)
        return std::nullopt;
    const double dist = glm::dot(n, patch.corner - ray.origin) / denom;
    if (dist <= 0.0)
        return std::nullopt;
    const glm::dvec3 d = ray.origin + dist * ray.direction - patch.corner;
    // Coordinates in the (u, v) basis through the dual basis.
    const double uu = glm::dot(patch.u, patch.u), uv = glm::dot(patch.u, patch.v), vv = glm::dot(patch.v, patch.v);
    const double det = uu * vv - uv * uv;
    const double s = (vv * glm::dot(d, patch.u) - uv * glm::dot(d, patch.v)) / det;
    const double t = (uu * glm::dot(d, patch.v) - uv * glm::dot(d, patch.u)) / det;
    if (!(s >= 0.0 && s <= 1.0 && t >= 0.0 && t <= 1.0))
        return std::nullopt;
    PatchSampleHit hit;
    hit.distance = dist;
    hit.s = s;
    hit.t = t;
    hit.a = std::clamp(int(std::floor(s * patch.na)), 0, std::max(patch.na - 1, 0));   // s = 1 is the last cell's edge
    hit.b = std::clamp(int(std::floor(t * patch.nb)), 0, std::max(patch.nb - 1, 0));
    return hit;
}

std::optional<std::size_t> enclosingInstance(const Scene& scene, const WorldTriangles& triangles, const glm::dvec3& point)
{
    std::optional<std::size_t> inside;
    // Skew directions, so a ray does not run along the axis-aligned edges and faces of a level.
    for (const glm::dvec3 direction : {glm::dvec3(0.36, 0.80, 0.48), glm::dvec3(-0.58, -0.41, 0.70)}) {
        const glm::dvec3 d = glm::normalize(direction);
        const auto hit = pickSurface(triangles, Ray{point, d});
        if (!hit)
            return std::nullopt;
        const std::size_t instance = triangles.instanceOf[hit->triangle];
        if (!scene.meshes[scene.instances[instance].mesh].watertight)
            return std::nullopt;
        const glm::dvec3 p0(triangles.vertices[3 * hit->triangle]);
        const glm::dvec3 outward = glm::cross(glm::dvec3(triangles.vertices[3 * hit->triangle + 1]) - p0,
                                              glm::dvec3(triangles.vertices[3 * hit->triangle + 2]) - p0);
        if (glm::dot(outward, d) <= 0.0 || (inside && *inside != instance))
            return std::nullopt;   // entering a face, or two answers: not inside one solid
        inside = instance;
    }
    return inside;
}

std::optional<double> pickPatch(const Patch& patch, const Ray& ray)
{
    if (const auto hit = pickPatchSample(patch, ray))
        return hit->distance;
    return std::nullopt;
}

Patch patchOnSurface(const SurfaceHit& hit, double width, double height, int na, int nb, double offset)
{
    const glm::dvec3 n = glm::normalize(hit.normal);
    // Walls: u horizontal. Floors and ceilings: u along X (the up hint is then Z).
    const glm::dvec3 hint = std::abs(n.y) > 0.9 ? glm::dvec3(0.0, 0.0, n.y > 0.0 ? -1.0 : 1.0) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 uDir = glm::normalize(glm::cross(hint, n));
    const glm::dvec3 vDir = glm::cross(n, uDir);   // u x v = n
    Patch patch;
    patch.u = width * uDir;
    patch.v = height * vDir;
    patch.corner = hit.point + offset * n - 0.5 * (patch.u + patch.v);
    patch.na = na;
    patch.nb = nb;
    return patch;
}

} // namespace sightline::ui
