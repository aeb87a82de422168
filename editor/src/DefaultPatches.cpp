#include "editor/DefaultPatches.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <glm/geometric.hpp>

#include "base/Error.h"
#include "visibility/pvs/FirstHitCaster.h"

namespace sightline::ui {

namespace {

/// Floor points spread evenly by area: the k-th of `count` at area fraction (k + 0.5) / count,
/// placed in its triangle by the R2 low-discrepancy sequence (deterministic, no seed to keep).
std::vector<glm::dvec3> floorPoints(const WorldTriangles& triangles, const std::vector<std::size_t>& floors, int count)
{
    std::vector<double> cumulative;
    double total = 0.0;
    for (const std::size_t t : floors) {
        const glm::dvec3 a(triangles.vertices[3 * t]), b(triangles.vertices[3 * t + 1]), c(triangles.vertices[3 * t + 2]);
        total += 0.5 * glm::length(glm::cross(b - a, c - a));
        cumulative.push_back(total);
    }
    std::vector<glm::dvec3> points;
    if (!(total > 0.0))
        return points;
    constexpr double g1 = 0.7548776662466927, g2 = 0.5698402909980532;   // R2: 1/phi2, 1/phi2^2
    for (int k = 0; k < count; ++k) {
        const double at = (double(k) + 0.5) / double(count) * total;
        const std::size_t i = std::size_t(std::lower_bound(cumulative.begin(), cumulative.end(), at) - cumulative.begin());
        const std::size_t t = floors[std::min(i, floors.size() - 1)];
        double r1 = std::fmod(0.5 + g1 * double(k + 1), 1.0), r2 = std::fmod(0.5 + g2 * double(k + 1), 1.0);
        if (r1 + r2 > 1.0) {
            r1 = 1.0 - r1;
            r2 = 1.0 - r2;
        }
        const glm::dvec3 a(triangles.vertices[3 * t]), b(triangles.vertices[3 * t + 1]), c(triangles.vertices[3 * t + 2]);
        points.push_back(a + r1 * (b - a) + r2 * (c - a));
    }
    return points;
}

/// Triangles whose winding faces `sign` up (sign +1) or down (-1), within about 45 degrees.
std::vector<std::size_t> floorTriangles(const WorldTriangles& triangles, double sign)
{
    std::vector<std::size_t> floors;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::dvec3 a(triangles.vertices[3 * t]), b(triangles.vertices[3 * t + 1]), c(triangles.vertices[3 * t + 2]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        if (glm::length(n) > 0.0 && sign * n.y > 0.7 * glm::length(n))
            floors.push_back(t);
    }
    return floors;
}

struct Candidate {
    glm::dvec3 centre;
    bool enclosed = false;   ///< something above and on every side
    int backFaces = 0;       ///< surfaces around it seen from behind: inside a solid, or outside the rooms
};

/// A patch of `side` metres centred at `centre`, upright, facing `towards` across the level.
Patch uprightFacing(const glm::dvec3& centre, const glm::dvec3& towards, double side)
{
    glm::dvec3 n = towards - centre;
    n.y = 0.0;
    n = glm::length(n) > 1e-9 ? glm::normalize(n) : glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 up(0.0, 1.0, 0.0);
    Patch patch;
    patch.u = side * glm::cross(up, n);   // u x v faces n
    patch.v = side * up;
    patch.corner = centre - 0.5 * (patch.u + patch.v);
    return patch;
}

/// The points `overFloor` over `floorPoints` whose floor is what stands straight below (no table,
/// no low ceiling between) and that have `clearance` up and around, with what they see around.
std::vector<Candidate> candidatesOverFloors(const pvs::FirstHitCaster& caster, const std::vector<glm::dvec3>& floorPoints,
                                            double overFloor, double clearance, float reach)
{
    static const glm::dvec3 around[] = {{1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}, {0.7071, 0, 0.7071},
                                        {-0.7071, 0, 0.7071}, {0.7071, 0, -0.7071}, {-0.7071, 0, -0.7071}, {0, 1, 0}};
    const glm::dvec3 down(0.0, -1.0, 0.0);
    std::vector<Candidate> candidates;
    for (const glm::dvec3& onFloor : floorPoints) {
        const glm::dvec3 centre = onFloor + glm::dvec3(0.0, overFloor, 0.0);
        const pvs::RayHit floor = caster.cast(glm::vec3(centre), glm::vec3(down), reach);
        if (floor.instance < 0 || std::abs(double(floor.t) - overFloor) > 0.01 + 1e-4 * overFloor)
            continue;
        Candidate candidate{centre, true, glm::dot(glm::dvec3(floor.normal), down) > 0.0 ? 1 : 0};
        bool open = true;
        for (const glm::dvec3& d : around) {
            const pvs::RayHit hit = caster.cast(glm::vec3(centre), glm::vec3(d), reach);
            open = open && (hit.instance < 0 || double(hit.t) >= clearance);
            candidate.enclosed = candidate.enclosed && hit.instance >= 0;
            candidate.backFaces += hit.instance >= 0 && glm::dot(glm::dvec3(hit.normal), d) > 0.0;
        }
        if (open)
            candidates.push_back(candidate);
    }
    return candidates;
}

/// Whether the patches `s` and `r` (upright, facing each other) see each other along the line
/// between their centres and those between their matching corners: a pair whose view is not cut
/// down to a sliver of a doorway.
bool seesAcross(const pvs::FirstHitCaster& caster, const glm::dvec3& s, const glm::dvec3& r, double side, int lines)
{
    const Patch a = uprightFacing(s, r, side), b = uprightFacing(r, s, side);
    // b's corners matching a's: b is a turned half a turn about the vertical, so its u runs the
    // other way.
    const glm::dvec3 from[5] = {s, a.corner, a.corner + a.u, a.corner + a.v, a.corner + a.u + a.v};
    const glm::dvec3 to[5] = {r, b.corner + b.u, b.corner, b.corner + b.u + b.v, b.corner + b.v};
    for (int k = 0; k < lines; ++k) {
        // Kept a hair off the corners: the line from a corner, not along the patch's own edge.
        const glm::dvec3 p = glm::mix(from[k], s, 0.02), q = glm::mix(to[k], r, 0.02);
        if (caster.cast(glm::vec3(p), glm::vec3(q - p), 1.0f).instance >= 0)
            return false;
    }
    return true;
}

/// The farthest pair of candidates that sees across (seesAcross, all five lines; else the centre
/// line alone; else the farthest pair), ordered as the plain pair: the source towards the low end
/// of the level's longer axis.
std::pair<glm::dvec3, glm::dvec3> farthestClearPair(const pvs::FirstHitCaster& caster, const std::vector<Candidate>& candidates,
                                                    const std::pair<Patch, Patch>& plain, double side)
{
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t a = 0; a < candidates.size(); ++a)
        for (std::size_t b = a + 1; b < candidates.size(); ++b)
            pairs.emplace_back(a, b);
    const auto distance = [&](const std::pair<std::size_t, std::size_t>& p) {
        return glm::length(candidates[p.second].centre - candidates[p.first].centre);
    };
    std::sort(pairs.begin(), pairs.end(), [&](const auto& x, const auto& y) { return distance(x) > distance(y); });
    std::pair<std::size_t, std::size_t> best = pairs.front();
    bool found = false;
    for (const int lines : {5, 1}) {
        for (const auto& pair : pairs) {
            if (distance(pair) < 2.0 * side)
                break;   // side by side is no pair to look across
            if (seesAcross(caster, candidates[pair.first].centre, candidates[pair.second].centre, side, lines)) {
                best = pair;
                found = true;
                break;
            }
        }
        if (found)
            break;
    }
    glm::dvec3 s = candidates[best.first].centre, r = candidates[best.second].centre;
    if (glm::dot(r - s, plain.second.centre() - plain.first.centre()) < 0.0)
        std::swap(s, r);
    return {s, r};
}

} // namespace

std::pair<Patch, Patch> defaultPatches(const Bounds& level, double side)
{
    glm::dvec3 lo(-2.0, 0.0, -2.0), hi(2.0, 3.0, 2.0);
    if (!level.empty()) {
        lo = glm::dvec3(level.min);
        hi = glm::dvec3(level.max);
    }
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double height = std::min(lo.y + 1.5, hi.y - 0.5 * side);
    const bool alongX = hi.x - lo.x >= hi.z - lo.z;
    const double margin = 0.1 * (alongX ? hi.x - lo.x : hi.z - lo.z) + 0.05;
    glm::dvec3 s(centre.x, height, centre.z), r = s;
    (alongX ? s.x : s.z) = (alongX ? lo.x : lo.z) + margin;
    (alongX ? r.x : r.z) = (alongX ? hi.x : hi.z) - margin;
    return {uprightFacing(s, r, side), uprightFacing(r, s, side)};
}

std::pair<Patch, Patch> defaultPatchesInOpenSpace(const Scene& level, double side)
{
    const Bounds bounds = level.bounds();
    const std::pair<Patch, Patch> plain = defaultPatches(bounds, side);
    if (bounds.empty())
        return plain;
    std::optional<pvs::FirstHitCaster> caster;
    try {
        caster.emplace(level);
    } catch (const Error&) {
        return plain;   // coordinates past the exact contract's range: the plain pair
    }
    const WorldTriangles triangles = worldTriangles(level);
    // The floors: triangles facing up; a level wound the other way has only downward ones.
    std::vector<std::size_t> floors = floorTriangles(triangles, 1.0);
    if (floors.empty())
        floors = floorTriangles(triangles, -1.0);
    const double overFloor = plain.first.centre().y - double(bounds.min.y);
    // Many points: in furnished rooms most stand under a table or beside a plant.
    std::vector<Candidate> candidates =
        candidatesOverFloors(*caster, floorPoints(triangles, floors, 2048), overFloor, std::max(0.5 * side, 0.1) + 0.1,
                             2.0f * glm::length(bounds.max - bounds.min));
    // A room's surfaces face into it: candidates that see some from behind stand inside a solid
    // block (a Quake map has no faces inside its brushes) or in the void around the rooms. Those
    // that see the fewest (none, in a level wound one way) are kept, then the enclosed ones.
    if (candidates.empty())
        return plain;
    const int fewest = std::min_element(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
                           return a.backFaces < b.backFaces;
                       })->backFaces;
    std::erase_if(candidates, [fewest](const Candidate& c) { return c.backFaces > fewest; });
    const auto keepIfTwo = [&candidates](auto&& keep) {
        if (std::count_if(candidates.begin(), candidates.end(), keep) >= 2)
            std::erase_if(candidates, [&keep](const Candidate& c) { return !keep(c); });
    };
    keepIfTwo([](const Candidate& c) { return c.enclosed; });
    // Under the level's top: on a terrain, 1.5 m over the highest hill would float above the level.
    keepIfTwo([&](const Candidate& c) { return c.centre.y + 0.5 * side <= double(bounds.max.y); });
    if (candidates.size() < 2)
        return plain;
    // An even spread of at most 256 (pairs are tested farthest first, each an Embree ray or five).
    if (const std::size_t stride = (candidates.size() + 255) / 256; stride > 1) {
        std::vector<Candidate> spread;
        for (std::size_t k = 0; k < candidates.size(); k += stride)
            spread.push_back(candidates[k]);
        candidates = std::move(spread);
    }
    const auto [s, r] = farthestClearPair(*caster, candidates, plain, side);
    return {uprightFacing(s, r, side), uprightFacing(r, s, side)};
}

} // namespace sightline::ui
