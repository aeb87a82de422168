#pragma once
// An independent brute-force judge of the lights contract (docs/lights.md): every (point, light
// sample) term computed from the contract's formulas in double, and every shadow segment tested
// against every triangle with ExactJudge.h's orientation predicates and tie distances (not the
// samplers' code). A segment some triangle crosses with no tie is blocked; one no triangle crosses
// or ties is free; the rest are ties, which may go either way. So the exact answer at a point is an
// interval [lit, lit + ties]: a method agrees with the contract when its value lies inside it
// (up to float summation).

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "lighting/DirectLight.h"
#include "lighting/Light.h"
#include "visibility/ExactJudge.h"
#include "visibility/Scene.h"

namespace sightline::test {

struct LitInterval {
    glm::dvec3 lit{0.0};    ///< terms whose segments are free
    glm::dvec3 ties{0.0};   ///< terms whose segments are ties
};

class LightsJudge {
public:
    explicit LightsJudge(const Scene& scene) : triangles_(worldTriangles(scene)), bounds_(scene.bounds()) {}

    /// The contract's term, written out again from the formulas (not LightEmission.cpp's code).
    static double term(const Light& light, const glm::dvec3& s, const glm::dvec3& x, const glm::dvec3& n)
    {
        if (light.type == LightType::Directional)
            return light.intensity * std::max(0.0, glm::dot(n, -light.direction));
        const double d = glm::length(s - x);
        if (d == 0.0)
            return 0.0;
        const glm::dvec3 l = (s - x) / d;
        if (light.type == LightType::Area) {
            const glm::dvec3 m = glm::normalize(glm::cross(light.area.u, light.area.v));
            const double area = glm::length(glm::cross(light.area.u, light.area.v));
            const double facing = light.twoSided ? std::abs(glm::dot(m, -l)) : std::max(0.0, glm::dot(m, -l));
            return light.radiance * area / light.area.sampleCount() * facing * std::max(0.0, glm::dot(n, l)) / (d * d);
        }
        double value = light.intensity * std::max(0.0, glm::dot(n, l)) / (d * d);
        if (light.range > 0.0)
            value *= std::pow(std::clamp(1.0 - std::pow(d / light.range, 4.0), 0.0, 1.0), 2.0);
        if (light.type == LightType::Spot) {
            const double cosT = glm::dot(light.direction, -l);
            value *= std::pow(std::clamp((cosT - std::cos(light.outerAngle)) /
                                             (std::cos(light.innerAngle) - std::cos(light.outerAngle)), 0.0, 1.0), 2.0);
        }
        return value;
    }

    /// The exact kind of segment p -> q.
    RayKind segment(const glm::dvec3& p, const glm::dvec3& q) const
    {
        const glm::dvec3 lo = glm::min(p, q) - kTieMetres, hi = glm::max(p, q) + kTieMetres;
        bool tie = false;
        for (std::size_t t = 0; t < triangles_.size(); ++t) {
            const glm::dvec3 a(triangles_.vertices[3 * t]), b(triangles_.vertices[3 * t + 1]), c(triangles_.vertices[3 * t + 2]);
            if (std::min({a.x, b.x, c.x}) > hi.x || std::max({a.x, b.x, c.x}) < lo.x || std::min({a.y, b.y, c.y}) > hi.y ||
                std::max({a.y, b.y, c.y}) < lo.y || std::min({a.z, b.z, c.z}) > hi.z || std::max({a.z, b.z, c.z}) < lo.z)
                continue;
            const TriangleVerdict v = judgeTriangle(p, q, a, b, c);
            if (v.crosses && !v.edgeTie && !v.endTie)
                return RayKind::Blocked;
            tie = tie || v.edgeTie || v.endTie;
        }
        return tie ? RayKind::EdgeTie : RayKind::Free;
    }

    LitInterval at(const std::vector<Light>& lights, const ShadingPoint& point) const
    {
        LitInterval out;
        const glm::dvec3 centre = 0.5 * (glm::dvec3(bounds_.min) + glm::dvec3(bounds_.max));
        const double radius = bounds_.empty() ? 1.0 : glm::length(glm::dvec3(bounds_.max) - glm::dvec3(bounds_.min)) + 1.0;
        for (const Light& light : lights) {
            std::vector<glm::dvec3> samples;
            if (light.type == LightType::Area)
                for (int i = 0; i < light.area.sampleCount(); ++i)
                    samples.push_back(light.area.sample(i));
            else if (light.type == LightType::Directional)
                samples.push_back(point.position - light.direction * (glm::length(point.position - centre) + radius));
            else
                samples.push_back(light.position);
            for (const glm::dvec3& s : samples) {
                const double w = term(light, s, point.position, point.normal);
                if (!(w > 0.0))
                    continue;
                const RayKind kind = segment(point.position, s);
                if (kind == RayKind::Free)
                    out.lit += light.colour * w;
                else if (kind != RayKind::Blocked)
                    out.ties += light.colour * w;
            }
        }
        return out;
    }

    /// Whether `value` lies in the interval, each channel within `relative` of its scale.
    static bool agrees(const LitInterval& exact, const glm::dvec3& value, double relative = 1e-6)
    {
        for (int c = 0; c < 3; ++c) {
            const double slack = relative * std::max(exact.lit[c] + exact.ties[c], 1e-12);
            if (value[c] < exact.lit[c] - slack || value[c] > exact.lit[c] + exact.ties[c] + slack)
                return false;
        }
        return true;
    }

private:
    WorldTriangles triangles_;
    Bounds bounds_;
};

} // namespace sightline::test
