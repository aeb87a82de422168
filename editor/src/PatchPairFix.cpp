#include "editor/PatchPairFix.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "base/Error.h"

namespace sightline::ui {

namespace {

bool valid(const Patch& source, const Patch& receiver)
{
    try {
        validatePatchPair(source, receiver);
        return true;
    } catch (const Error&) {
        return false;
    }
}

std::array<glm::dvec3, 4> cornersOf(const Patch& p) { return {p.corner, p.corner + p.u, p.corner + p.v, p.corner + p.u + p.v}; }

std::string centimetres(double metres)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.0f cm", std::max(1.0, std::round(100.0 * metres)));
    return text;
}

/// `moving` moved along `other`'s normal until it is wholly on one side (`front`: the side `other`
/// faces), with the margin.
std::optional<PatchPairFix> moveOff(const Patch& moving, const Patch& other, bool front, double maxMove, const char* role,
                                    const char* otherRole)
{
    const glm::dvec3 n = other.normal();
    double low = INFINITY, high = -INFINITY;
    for (const glm::dvec3& c : cornersOf(moving)) {
        const double d = glm::dot(c - other.corner, n);
        low = std::min(low, d);
        high = std::max(high, d);
    }
    const double shift = front ? kPairFixMargin - low : -(high + kPairFixMargin);
    if (shift == 0.0 || std::abs(shift) > maxMove)
        return std::nullopt;
    PatchPairFix fix;
    fix.patch = moving;
    fix.patch.corner += shift * n;
    const double up = shift * n.y;
    const char* verb = up > 0.7 * std::abs(shift) ? "lift" : up < -0.7 * std::abs(shift) ? "lower" : "move";
    const char* where = verb[0] == 'l' && verb[1] == 'i' ? " above" : verb[0] == 'l' ? " below" : front ? " in front of" : " behind";
    fix.description = std::string(verb) + " the " + role + " " + centimetres(std::abs(shift)) + where + " the " + otherRole + "'s plane";
    return fix;
}

/// `moving` cut along the edge most across `other`'s plane to the part on one side (`front`: the
/// side `other` faces).
std::optional<PatchPairFix> shrink(const Patch& moving, const Patch& other, bool front, const char* role, const char* otherRole)
{
    const glm::dvec3 n = other.normal();
    const double sign = front ? 1.0 : -1.0;
    const bool alongU = std::abs(glm::dot(moving.u, n)) >= std::abs(glm::dot(moving.v, n));
    const glm::dvec3 e = alongU ? moving.u : moving.v, f = alongU ? moving.v : moving.u;
    // Signed distance (on the kept side positive) at corner + s e + t f: d0 + s de + t df.
    const double d0 = sign * glm::dot(moving.corner - other.corner, n), de = sign * glm::dot(e, n), df = sign * glm::dot(f, n);
    const double worstF = std::min(0.0, df);
    if (de == 0.0)
        return std::nullopt;
    double s0 = 0.0, s1 = 1.0;
    const double s = (kPairFixMargin - d0 - worstF) / de;   // where the kept part starts (de > 0) or ends
    (de > 0.0 ? s0 : s1) = std::clamp(s, 0.0, 1.0);
    if (s1 - s0 < 0.2)
        return std::nullopt;   // most of it would go
    PatchPairFix fix;
    fix.patch = moving;
    fix.patch.corner += s0 * e;
    (alongU ? fix.patch.u : fix.patch.v) = (s1 - s0) * e;
    fix.description = std::string("shrink the ") + role + " by " + centimetres((1.0 - (s1 - s0)) * glm::length(e)) + " to the " +
                      otherRole + "'s " + (sign > 0.0 ? "front" : "back");
    return fix;
}

} // namespace

std::optional<PatchPairFix> fixPatchPair(const Patch& source, const Patch& receiver, bool preferSource, double maxMove)
{
    if (valid(source, receiver))
        return std::nullopt;
    try {
        validatePatch(source, "source");
        validatePatch(receiver, "receiver");
    } catch (const Error&) {
        return std::nullopt;   // degenerate or out of range: nothing to fix here
    }
    for (const bool changeSource : {preferSource, !preferSource}) {
        const Patch& moving = changeSource ? source : receiver;
        const Patch& other = changeSource ? receiver : source;
        const char* role = changeSource ? "source" : "receiver";
        const char* otherRole = changeSource ? "receiver" : "source";
        // The side the other patch faces first: a patch belongs in the space the other looks into.
        for (auto candidate : {moveOff(moving, other, true, maxMove, role, otherRole), moveOff(moving, other, false, maxMove, role, otherRole),
                               shrink(moving, other, true, role, otherRole), shrink(moving, other, false, role, otherRole)}) {
            if (!candidate)
                continue;
            candidate->source = changeSource;
            if (valid(changeSource ? candidate->patch : source, changeSource ? receiver : candidate->patch))
                return candidate;
        }
    }
    return std::nullopt;
}

} // namespace sightline::ui
