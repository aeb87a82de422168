#include "visibility/Patch.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

#include "base/Error.h"
#include "visibility/ExactSegment.h"

namespace sightline {

namespace {

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::array<glm::dvec3, 4> corners(const Patch& p)
{
    return {p.corner, p.corner + p.u, p.corner + p.u + p.v, p.corner + p.v};
}

/// Which side of `plane`'s plane `other` lies on: +1 or -1 when all four corners are strictly on
/// one side, 0 when it touches or crosses the plane. "Strictly" allows for rounding: a corner
/// closer than a relative 1e-9 of the scene's size counts as touching.
int sideOf(const Patch& plane, const Patch& other)
{
    const glm::dvec3 n = plane.normal();
    const double scale = std::max({glm::length(plane.u), glm::length(plane.v), glm::length(other.u),
                                   glm::length(other.v), glm::length(other.corner - plane.corner)});
    const double eps = 1e-9 * scale;
    int positive = 0, negative = 0;
    for (const glm::dvec3& c : corners(other)) {
        const double d = glm::dot(c - plane.corner, n);
        if (d > eps)
            ++positive;
        else if (d < -eps)
            ++negative;
    }
    if (positive == 4)
        return 1;
    if (negative == 4)
        return -1;
    return 0;
}

} // namespace

glm::dvec3 Patch::normal() const { return glm::normalize(glm::cross(u, v)); }

void validatePatch(const Patch& p, const std::string& role)
{
    if (!finite(p.corner) || !finite(p.u) || !finite(p.v))
        throw Error(role + " patch has a non-finite corner or edge vector");
    for (const glm::dvec3& c : corners(p))
        if (std::max({std::abs(c.x), std::abs(c.y), std::abs(c.z)}) > kMaxCoordinateMetres)
            throw Error(role + " patch reaches beyond " + std::to_string(int(kMaxCoordinateMetres)) +
                        " m from the origin; Sightline accepts coordinates up to that");
    const double lu = glm::length(p.u), lv = glm::length(p.v);
    if (lu <= 0.0 || lv <= 0.0)
        throw Error(role + " patch is degenerate: an edge vector has zero length");
    // |u x v| / (|u||v|) = sin(angle between edges).
    if (glm::length(glm::cross(p.u, p.v)) <= 1e-9 * lu * lv)
        throw Error(role + " patch is degenerate: edge vectors u and v are parallel");
    if (p.na < 1 || p.nb < 1)
        throw Error(role + " patch needs at least 1x1 samples, got " + std::to_string(p.na) + "x" +
                    std::to_string(p.nb));
    if (role == "source") {
        if (static_cast<long long>(p.na) * p.nb > kMaxSourceSamples)
            throw Error("source patch has " + std::to_string(p.na) + "x" + std::to_string(p.nb) +
                        " samples; at most " + std::to_string(kMaxSourceSamples) + " are supported");
    } else if (p.na > kMaxReceiverSide || p.nb > kMaxReceiverSide) {
        throw Error(role + " patch has " + std::to_string(p.na) + "x" + std::to_string(p.nb) +
                    " samples; at most " + std::to_string(kMaxReceiverSide) + " per side are supported");
    }
}

void validatePatchPair(const Patch& source, const Patch& receiver)
{
    validatePatch(source, "source");
    validatePatch(receiver, "receiver");
    if (sideOf(source, receiver) == 0)
        throw Error("invalid patch pair: the receiver touches or crosses the source's plane");
    if (sideOf(receiver, source) == 0)
        throw Error("invalid patch pair: the source touches or crosses the receiver's plane");
}

} // namespace sightline
