#include "lighting/Indirect.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include <glm/geometric.hpp>

#include "base/Error.h"

namespace sightline {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kVplSize = 1e-3;      ///< a VPL's stand-in rectangle's side: only its normal and area matter
constexpr double kLiftMetres = 1e-4;   ///< VPLs and gathered points sit this far off their surface (ties)

/// Uniform doubles in [0, 1) from a fixed generator (std distributions differ between libraries).
struct Uniform {
    std::mt19937_64 engine;
    explicit Uniform(std::uint64_t seed) : engine(seed) {}
    double operator()() { return double(engine() >> 11) * (1.0 / 9007199254740992.0); }
};

/// A unit vector around `axis` with cos(angle) = c and azimuth phi.
glm::dvec3 around(const glm::dvec3& axis, double c, double phi)
{
    const glm::dvec3 helper = std::abs(axis.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 t = glm::normalize(glm::cross(axis, helper)), b = glm::cross(axis, t);
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    return c * axis + s * (std::cos(phi) * t + std::sin(phi) * b);
}

glm::dvec3 cosineWeighted(const glm::dvec3& normal, Uniform& rng)
{
    const double u = rng(), v = rng();
    return around(normal, std::sqrt(1.0 - u), 2.0 * kPi * v);
}

double spotWindow(const Light& light, double cosT)
{
    const double cosA = std::cos(light.innerAngle), cosB = std::cos(light.outerAngle);
    const double w = std::clamp((cosT - cosB) / (cosA - cosB), 0.0, 1.0);
    return w * w;
}

double rangeWindow(const Light& light, double d)
{
    if (light.range <= 0.0)
        return 1.0;
    const double r = d / light.range;
    const double w = std::clamp(1.0 - r * r * r * r, 0.0, 1.0);
    return w * w;
}

/// The power (W per unit colour) a light emits, for sharing out the photons.
double power(const Light& light, const DirectionalReach& reach)
{
    switch (light.type) {
    case LightType::Point: return 4.0 * kPi * light.intensity;
    case LightType::Spot: {
        // 2 pi I times the integral of the window over cos t in [cos b, 1] (midpoint rule).
        const double cosB = std::cos(light.outerAngle);
        double integral = 0.0;
        for (int k = 0; k < 256; ++k) {
            const double c = cosB + (k + 0.5) / 256.0 * (1.0 - cosB);
            integral += spotWindow(light, c) * (1.0 - cosB) / 256.0;
        }
        return 2.0 * kPi * light.intensity * integral;
    }
    case LightType::Directional: return light.intensity * kPi * reach.radius * reach.radius;
    case LightType::Area:
        return light.radiance * glm::length(glm::cross(light.area.u, light.area.v)) * kPi * (light.twoSided ? 2.0 : 1.0);
    }
    return 0.0;
}

struct Photon {
    glm::dvec3 origin, direction;   ///< direction unit
    glm::dvec3 flux;                ///< W per channel
    double length = 0.0;            ///< how far it may travel
};

/// One photon of `light`, which sends `count` in all.
Photon emit(const Light& light, int count, const DirectionalReach& reach, Uniform& rng)
{
    Photon p;
    const double share = 1.0 / count;
    switch (light.type) {
    case LightType::Point:
        p.origin = light.position;
        p.direction = around(glm::dvec3(0.0, 1.0, 0.0), 1.0 - 2.0 * rng(), 2.0 * kPi * rng());
        p.flux = light.colour * (4.0 * kPi * light.intensity * share);
        break;
    case LightType::Spot: {
        const double cosB = std::cos(light.outerAngle), c = 1.0 - rng() * (1.0 - cosB);
        p.origin = light.position;
        p.direction = around(light.direction, c, 2.0 * kPi * rng());
        p.flux = light.colour * (light.intensity * 2.0 * kPi * (1.0 - cosB) * spotWindow(light, c) * share);
        break;
    }
    case LightType::Directional: {
        const double r = reach.radius * std::sqrt(rng()), phi = 2.0 * kPi * rng();
        const glm::dvec3 offset = r * around(light.direction, 0.0, phi);
        p.origin = reach.centre - light.direction * (reach.radius + 1.0) + offset;
        p.direction = light.direction;
        p.flux = light.colour * (light.intensity * kPi * reach.radius * reach.radius * share);
        break;
    }
    case LightType::Area: {
        glm::dvec3 m = light.area.normal();
        double sides = 1.0;
        if (light.twoSided) {
            sides = 2.0;
            if (rng() < 0.5)
                m = -m;
        }
        p.origin = light.area.corner + rng() * light.area.u + rng() * light.area.v;
        p.direction = cosineWeighted(m, rng);
        p.flux = light.colour * (light.radiance * glm::length(glm::cross(light.area.u, light.area.v)) * kPi * sides * share);
        break;
    }
    }
    p.length = glm::length(p.origin - reach.centre) + 2.0 * reach.radius + 1.0;
    return p;
}

/// Photon counts per light in proportion to power, by largest remainders.
std::vector<int> photonCounts(const std::vector<Light>& lights, const DirectionalReach& reach, int total)
{
    std::vector<double> weights(lights.size());
    double sum = 0.0;
    for (std::size_t l = 0; l < lights.size(); ++l) {
        const glm::dvec3& c = lights[l].colour;
        weights[l] = power(lights[l], reach) * (c.x + c.y + c.z) / 3.0;
        sum += weights[l];
    }
    std::vector<int> counts(lights.size(), 0);
    if (!(sum > 0.0))
        return counts;
    std::vector<std::pair<double, std::size_t>> remainders;
    int given = 0;
    for (std::size_t l = 0; l < lights.size(); ++l) {
        const double exact = total * weights[l] / sum;
        counts[l] = int(exact);
        given += counts[l];
        remainders.push_back({exact - counts[l], l});
    }
    std::stable_sort(remainders.begin(), remainders.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (std::size_t k = 0; given < total && k < remainders.size(); ++k, ++given)
        ++counts[remainders[k].second];
    return counts;
}

/// A VPL at `position` on a surface of unit normal `normal` (towards where its light came from).
Light vplAt(const glm::dvec3& position, const glm::dvec3& normal, const glm::dvec3& reflected, double clampMetres)
{
    Light vpl;
    vpl.type = LightType::Area;
    const glm::dvec3 helper = std::abs(normal.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 u = glm::normalize(glm::cross(helper, normal)) * kVplSize;
    const glm::dvec3 v = glm::cross(normal, u);   // u x v along the normal
    vpl.area.u = u;
    vpl.area.v = v;
    vpl.area.na = vpl.area.nb = 1;
    vpl.area.corner = position + kLiftMetres * normal - 0.5 * (u + v);
    vpl.radiance = 1.0 / (kPi * kVplSize * kVplSize);
    vpl.colour = reflected;
    vpl.clampMetres = clampMetres;
    return vpl;
}

/// The first surface the segment origin -> origin + direction * length meets: its point, the
/// unit normal facing back along the segment and its albedo (`fallback` where its mesh has none).
/// False when it meets none.
bool firstSurface(const LightingScene& scene, const glm::dvec3& origin, const glm::dvec3& direction, double length,
                  double fallback, glm::dvec3& point, glm::dvec3& normal, glm::dvec3& albedo)
{
    const glm::dvec3 start = origin + direction * kLiftMetres;
    const pvs::RayHit hit = scene.firstHits().cast(glm::vec3(start), glm::vec3(direction * length), 1.0f);
    if (hit.triangle < 0)
        return false;
    normal = glm::dvec3(hit.normal);
    const double n = glm::length(normal);
    if (!(n > 0.0))
        return false;
    normal /= n;
    if (glm::dot(normal, direction) > 0.0)
        normal = -normal;
    point = start + direction * (length * double(hit.t));
    albedo = scene.albedo(hit.triangle, fallback);
    return true;
}

} // namespace

void validateIndirectOptions(const IndirectOptions& options)
{
    if (options.vpls < 1 || options.vpls > 1000000)
        throw Error("--indirect: the VPL count must be in [1, 1000000], got " + std::to_string(options.vpls));
    if (!(options.albedo >= 0.0 && options.albedo < 1.0))
        throw Error("--albedo must be in [0, 1), got " + std::to_string(options.albedo));
    if (!(options.clampMetres >= 0.0) || !std::isfinite(options.clampMetres))
        throw Error("--clamp must be a finite distance >= 0 (metres), got " + std::to_string(options.clampMetres));
}

VplSet traceVpls(const LightingScene& scene, const std::vector<Light>& lights, const IndirectOptions& options)
{
    validateIndirectOptions(options);
    const auto start = std::chrono::steady_clock::now();
    VplSet set;
    const std::vector<int> counts = photonCounts(lights, scene.reach(), options.vpls);
    Uniform rng(options.seed);
    for (std::size_t l = 0; l < lights.size(); ++l)
        for (int k = 0; k < counts[l]; ++k) {
            const Light& light = lights[l];
            const Photon photon = emit(light, counts[l], scene.reach(), rng);
            ++set.photons;
            set.emitted += photon.flux;
            glm::dvec3 point, normal, albedo;
            if (!firstSurface(scene, photon.origin, photon.direction, photon.length, options.albedo, point, normal, albedo))
                continue;   // left the scene
            glm::dvec3 flux = photon.flux;
            if (light.type == LightType::Point || light.type == LightType::Spot)
                flux *= rangeWindow(light, glm::length(point - photon.origin));
            if (flux == glm::dvec3(0.0))
                continue;
            set.vpls.push_back(vplAt(point, normal, albedo * flux, options.clampMetres));
        }
    set.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return set;
}

IndirectResult vplIrradiance(const LightingScene& scene, const VplSet& vpls, std::span<const ShadingPoint> points,
                             const IndirectOptions& options)
{
    IndirectResult result;
    DirectLightOptions direct;
    direct.threads = options.threads;
    result.irradiance = directIrradiance(scene, vpls.vpls, points, direct, &result.stats);
    if (options.clampMetres > 0.0) {
        std::vector<Light> unclamped = vpls.vpls;
        for (Light& vpl : unclamped)
            vpl.clampMetres = 0.0;
        const std::vector<glm::dvec3> full = directIrradiance(scene, unclamped, points, direct);
        double kept = 0.0, all = 0.0;
        for (std::size_t j = 0; j < points.size(); ++j)
            for (int c = 0; c < 3; ++c)
                kept += result.irradiance[j][c], all += full[j][c];
        result.clampLoss = all > 0.0 ? 1.0 - kept / all : 0.0;
    }
    return result;
}

std::vector<glm::dvec3> gatheredIndirect(const LightingScene& scene, const std::vector<Light>& lights,
                                         std::span<const ShadingPoint> points, int samples, const IndirectOptions& options)
{
    if (samples < 1)
        throw Error("the gathering reference needs at least one sample per point");
    std::vector<ShadingPoint> seen;
    std::vector<glm::dvec3> albedos;   ///< of the surface each gathered direction met
    std::vector<std::size_t> owner;
    for (std::size_t j = 0; j < points.size(); ++j) {
        Uniform rng(options.seed * 0x9E3779B97F4A7C15ull + j);
        const double length = glm::length(points[j].position - scene.reach().centre) + 2.0 * scene.reach().radius + 1.0;
        for (int k = 0; k < samples; ++k) {
            glm::dvec3 point, normal, albedo;
            if (firstSurface(scene, points[j].position, cosineWeighted(points[j].normal, rng), length, options.albedo, point, normal, albedo)) {
                seen.push_back({point + kLiftMetres * normal, normal});
                albedos.push_back(albedo);
                owner.push_back(j);
            }
        }
    }
    DirectLightOptions direct;
    direct.threads = options.threads;
    const std::vector<glm::dvec3> there = directIrradiance(scene, lights, seen, direct);
    std::vector<glm::dvec3> out(points.size(), glm::dvec3(0.0));
    for (std::size_t k = 0; k < seen.size(); ++k)
        out[owner[k]] += there[k] * albedos[k] / double(samples);
    return out;
}

} // namespace sightline
