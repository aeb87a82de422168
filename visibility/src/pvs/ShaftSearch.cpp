#include "visibility/pvs/ShaftSearch.h"

#include <algorithm>
#include <cmath>

#include "visibility/pvs/FirstHitCaster.h"
#include "visibility/pvs/PvsBake.h"

namespace sightline::pvs {

namespace {

/// The segments a pair of quads holds: the product of their areas.
double pairMeasure(const Quad& f, const Quad& g)
{
    return glm::length(glm::cross(f.u, f.v)) * glm::length(glm::cross(g.u, g.v));
}

constexpr double kHopelessGaps = 4.0;     // blockers below this many smallest gaps are hopeless
constexpr int kBlockersPerRay = 6;        // triangles along a central segment tried as blockers
constexpr double kBeforeTarget = 1e-7;    // a hit this close to the target face is not "before" it

/// An axis-aligned rectangle: a box flat on `axis`.
struct Rect {
    Bounds box;
    int axis = 0;
};

Rect face(const Bounds& box, int axis, bool positive)
{
    Rect r{box, axis};
    r.box.min[axis] = r.box.max[axis] = positive ? box.max[axis] : box.min[axis];
    return r;
}

/// Clips `r` to the closed side of the plane x[axis] = plane given by `sign` (+1: x >= plane);
/// a rectangle in the plane itself is dropped (its segments leave or enter through a neighbouring
/// face too). False when nothing of positive area is left.
bool clipToSide(Rect& r, int axis, float plane, int sign)
{
    if (r.axis == axis) {
        const float x = r.box.min[axis];
        return sign > 0 ? x > plane : x < plane;
    }
    if (sign > 0)
        r.box.min[axis] = std::max(r.box.min[axis], plane);
    else
        r.box.max[axis] = std::min(r.box.max[axis], plane);
    return r.box.max[axis] > r.box.min[axis];
}

Quad quadOf(const Rect& r)
{
    const int b = (r.axis + 1) % 3, c = (r.axis + 2) % 3;
    Quad q;
    q.corner = glm::dvec3(r.box.min);
    q.u[b] = double(r.box.max[b]) - double(r.box.min[b]);
    q.v[c] = double(r.box.max[c]) - double(r.box.min[c]);
    return q;
}

/// Exit parameter of origin + t d from `box` (t in units of d), 0 when the line misses it.
double exitParameter(const Bounds& box, const glm::dvec3& origin, const glm::dvec3& d)
{
    double t0 = 0.0, t1 = INFINITY;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (origin[k] < box.min[k] || origin[k] > box.max[k])
                return 0.0;
            continue;
        }
        double a = (box.min[k] - origin[k]) / d[k], b = (box.max[k] - origin[k]) / d[k];
        if (a > b)
            std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    return t1 >= t0 ? t1 : 0.0;
}

struct Stream {
    std::uint64_t state;
    double next()
    {
        state = mixSeed(state, 0x2545f4914f6cdd1dull);
        return double(state >> 11) * (1.0 / 9007199254740992.0);
    }
};

} // namespace

void SearchStats::add(const SearchStats& o)
{
    shafts += o.shafts;
    casts += o.casts;
    planeProofs += o.planeProofs;
    solidProofs += o.solidProofs;
    openShafts += o.openShafts;
    residueRays += o.residueRays;
    residueWitnesses += o.residueWitnesses;
}

bool boxesMeet(const Bounds& a, const Bounds& b)
{
    for (int k = 0; k < 3; ++k)
        if (a.max[k] < b.min[k] || b.max[k] < a.min[k])
            return false;
    return true;
}

bool boxesOverlapInside(const Bounds& a, const Bounds& b)
{
    for (int k = 0; k < 3; ++k)
        if (!(a.max[k] > b.min[k] && b.max[k] > a.min[k]))
            return false;
    return true;
}

std::vector<std::pair<Quad, Quad>> coveringFacePairs(const Bounds& cell, const Bounds& target)
{
    std::vector<std::pair<Quad, Quad>> out;
    if (boxesMeet(cell, target))
        return out;
    for (int fa = 0; fa < 3; ++fa)
        for (int fs = 0; fs < 2; ++fs)
            for (int ga = 0; ga < 3; ++ga)
                for (int gs = 0; gs < 2; ++gs) {
                    Rect f = face(cell, fa, fs != 0), g = face(target, ga, gs != 0);
                    const int b = (ga + 1) % 3, c = (ga + 2) % 3;
                    if (!(target.max[b] > target.min[b]) || !(target.max[c] > target.min[c]))
                        continue;   // a face of no area (a flat box's side)
                    if (!clipToSide(g, fa, f.box.min[fa], fs ? 1 : -1))
                        continue;
                    if (!clipToSide(f, ga, g.box.min[ga], gs ? 1 : -1))
                        continue;
                    out.emplace_back(quadOf(f), quadOf(g));
                }
    return out;
}

ShaftSearch::ShaftSearch(const FirstHitCaster& caster, const ShaftProver& prover, const std::vector<std::int32_t>& objectOfInstance)
    : caster_(caster), prover_(prover), objectOf_(objectOfInstance)
{
}

bool ShaftSearch::witnessRay(const SearchTarget& target, const glm::dvec3& from, const glm::dvec3& to, SearchStats& stats) const
{
    const glm::dvec3 d = to - from;
    ++stats.casts;
    if (target.object < 0)
        return caster_.cast(glm::vec3(from), glm::vec3(d), float(1.0 - kBeforeTarget)).instance < 0;
    const double exit = exitParameter(target.box, from, d);
    if (!(exit > 0.0))
        return false;
    const RayHit hit = caster_.cast(glm::vec3(from), glm::vec3(d), float(exit * (1.0 + 1e-5)));
    return hit.instance >= 0 && objectOf_[std::size_t(hit.instance)] == target.object;
}

void ShaftSearch::chooseSplit(const Quad& f, const Quad& g, const glm::dvec3& at, const glm::dvec3& normal, double t,
                              Split* split)
{
    // The spread of the sub-shaft's segments at parameter t: how far apart they pass there.
    split->spread = (1.0 - t) * f.extent() + t * g.extent();
    const glm::dvec3 edges[4] = {0.5 * f.u, 0.5 * f.v, 0.5 * g.u, 0.5 * g.v};
    double best = -1.0;
    const double length = glm::length(normal);
    const glm::dvec3 a = f.centre(), b = g.centre();
    if (length > 0.0) {
        // Split where it narrows the segments' crossing with the blocker's plane the most: at a
        // grazing plane a short edge can move the crossing far (a wall seen along its face).
        const glm::dvec3 n = normal / length;
        auto crossing = [&](const glm::dvec3& p, const glm::dvec3& q, glm::dvec3& out) {
            const double den = glm::dot(n, q - p);
            if (std::abs(den) < 1e-12 * glm::length(q - p))
                return false;
            out = p + (glm::dot(n, at - p) / den) * (q - p);
            return true;
        };
        glm::dvec3 base;
        if (crossing(a, b, base)) {
            for (int e = 0; e < 4; ++e) {
                glm::dvec3 moved;
                const bool ok = e < 2 ? crossing(a + edges[e], b, moved) : crossing(a, b + edges[e], moved);
                const double shift = ok ? glm::length(moved - base) : INFINITY;
                if (shift > best) {
                    best = shift;
                    split->edge = e;
                }
            }
            return;
        }
    }
    for (int e = 0; e < 4; ++e) {
        const double shift = (e < 2 ? 1.0 - t : t) * glm::length(edges[e]);
        if (shift > best) {
            best = shift;
            split->edge = e;
        }
    }
}

ShaftSearch::Outcome ShaftSearch::evaluate(const Bounds& cell, const SearchTarget& target, const Quad& f, const Quad& g,
                                           Split* split, SearchStats& stats) const
{
    const glm::dvec3 a = f.centre(), b = g.centre(), d = b - a;
    const glm::vec3 origin(a), direction(d);
    const double rf = f.radius(), rg = g.radius();
    const double exit = target.object >= 0 ? std::max(exitParameter(target.box, a, d), 1.0) : 1.0;
    // The central segment: a witness, or the triangles it meets before the target's face, each
    // tried as a blocker of the whole sub-shaft as soon as it is found (a closed solid once the
    // next triangle along the segment tells where its chord ends).
    struct Blocker {
        double t = 0.0;
        std::size_t triangle = 0;
        std::uint32_t instance = 0;
    };
    Blocker solid;          // a solid met, waiting for its chord's end
    bool solidPending = false;
    double largest = 0.0;   // the largest blocker met (a region, triangle or solid's size)
    float tnear = 0.0f;
    for (int k = 0;; ++k) {
        ++stats.casts;
        const float tfar = k == 0 && target.object >= 0 ? float(exit * (1.0 + 1e-5)) : float(1.0 - kBeforeTarget);
        const RayHit hit = caster_.cast(origin, direction, tnear, tfar);
        const bool before = hit.instance >= 0 && double(hit.t) < 1.0 - kBeforeTarget;
        if (k == 0) {
            if (hit.instance >= 0 && target.object >= 0 && objectOf_[std::size_t(hit.instance)] == target.object)
                return Outcome::Witness;
            if (!before) {   // reached the target's face: a box target is reached; an object was missed
                split->reach = 1.0;
                return target.object < 0 && hit.instance < 0 ? Outcome::Witness : Outcome::Open;
            }
            chooseSplit(f, g, a + double(hit.t) * d, glm::dvec3(hit.normal), double(hit.t), split);
            split->reach = double(hit.t);
        }
        if (solidPending) {
            solidPending = false;
            const double t = 0.5 * (solid.t + (before ? double(hit.t) : 1.0));
            const double r = (1.0 - t) * rf + t * rg + 1e-6;
            if (prover_.ballInsideSolid(solid.triangle, a + t * d, r)) {
                ++stats.solidProofs;
                return Outcome::Proven;
            }
        }
        if (!before || k == kBlockersPerRay)
            break;
        const Blocker blocker{double(hit.t), std::size_t(hit.triangle), std::uint32_t(hit.instance)};
        largest = std::max(largest, prover_.blockerSize(blocker.triangle));
        if (!target.own || !target.own(blocker.instance)) {
            if (prover_.planeBlocks(blocker.triangle, f, g, target.own)) {
                ++stats.planeProofs;
                return Outcome::Proven;
            }
            if (prover_.isSolid(blocker.triangle)) {
                const Bounds& bounds = prover_.solidBounds(blocker.triangle);
                // Both ends may be inside it: no crossing guaranteed. Else try its chord.
                if (!(boxesOverlapInside(cell, bounds) && boxesOverlapInside(target.box, bounds))) {
                    solid = blocker;
                    solidPending = true;
                }
            }
        }
        // Next triangle along the segment: a little beyond this one.
        tnear = std::nextafter(std::max(hit.t * (1.0f + 1e-6f), hit.t + 1e-7f), INFINITY);
    }
    // Blockers all much smaller than the gap we split to (leaves of a plant) never prove a
    // sub-shaft, however finely it is split: leave it open now.
    split->hopeless = largest < kHopelessGaps * split->smallestGap;
    return Outcome::Open;
}

Reach ShaftSearch::residue(const SearchTarget& target, const std::vector<std::pair<Quad, Quad>>& open, double total,
                           const SearchLimits& limits, std::uint64_t seed, SearchStats& stats) const
{
    // Rays spread over the open sub-shafts by their share of the pair's segments (area x area), as
    // many as `residueRays` would put there if spread over the whole pair, at least 64: where the
    // proofs left room, sampling is dense.
    std::vector<double> cumulative;
    double openMeasure = 0.0;
    for (const auto& [f, g] : open)
        cumulative.push_back(openMeasure += pairMeasure(f, g));
    const double share = total > 0.0 ? openMeasure / total : 1.0;
    const int rays = std::min(limits.residueRays, std::max(64, int(std::ceil(limits.residueRays * share))));
    Stream random{seed};
    for (int i = 0; i < rays && openMeasure > 0.0; ++i) {
        const double u = (i + random.next()) / rays * openMeasure;
        const std::size_t k = std::min<std::size_t>(
            std::size_t(std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin()), open.size() - 1);
        const auto& [f, g] = open[k];
        const glm::dvec3 from = f.at(random.next(), random.next()), to = g.at(random.next(), random.next());
        ++stats.residueRays;
        if (witnessRay(target, from, to, stats)) {
            ++stats.residueWitnesses;
            return Reach::Visible;
        }
    }
    return Reach::Unknown;
}

Reach ShaftSearch::search(const Bounds& cell, const SearchTarget& target, const SearchLimits& limits, std::uint64_t seed,
                          SearchStats* statsOut) const
{
    if (boxesMeet(cell, target.box))
        return Reach::Visible;
    SearchStats stats;
    // Two orders, taken in turn: the sub-shaft whose parent's central segment got farthest
    // before a blocker (nearest to a witness: visible pairs end early), and the largest one (a
    // hidden pair is proven only when every sub-shaft is). Ties in order of creation.
    struct Entry {
        Quad f, g;
        double reach, size;
        bool done;
    };
    std::vector<Entry> entries;
    std::vector<std::uint32_t> byReach, bySize;
    auto reachFirst = [&](std::uint32_t x, std::uint32_t y) {
        return entries[x].reach != entries[y].reach ? entries[x].reach < entries[y].reach : x > y;
    };
    auto sizeFirst = [&](std::uint32_t x, std::uint32_t y) {
        return entries[x].size != entries[y].size ? entries[x].size < entries[y].size : x > y;
    };
    const auto measure = pairMeasure;
    std::size_t pending = 0;
    auto push = [&](const Quad& f, const Quad& g, double reach) {
        entries.push_back({f, g, reach, measure(f, g), false});
        byReach.push_back(std::uint32_t(entries.size() - 1));
        std::push_heap(byReach.begin(), byReach.end(), reachFirst);
        bySize.push_back(std::uint32_t(entries.size() - 1));
        std::push_heap(bySize.begin(), bySize.end(), sizeFirst);
        ++pending;
    };
    auto pop = [&](bool reachTurn) {
        std::vector<std::uint32_t>& heap = reachTurn ? byReach : bySize;
        for (;;) {
            if (reachTurn)
                std::pop_heap(heap.begin(), heap.end(), reachFirst);
            else
                std::pop_heap(heap.begin(), heap.end(), sizeFirst);
            const std::uint32_t k = heap.back();
            heap.pop_back();
            if (!entries[k].done) {
                entries[k].done = true;
                --pending;
                return k;
            }
        }
    };
    double total = 0.0;
    for (const auto& [f, g] : coveringFacePairs(cell, target.box)) {
        push(f, g, 2.0);
        total += measure(f, g);
    }
    std::vector<std::pair<Quad, Quad>> open;
    Reach answer = Reach::Hidden;
    while (pending > 0) {
        if (stats.shafts >= std::uint64_t(limits.maxShafts))
            break;
        const std::uint32_t k = pop(stats.shafts % 2 == 0);
        const Quad f = entries[k].f, g = entries[k].g;
        ++stats.shafts;
        Split split;
        split.smallestGap = limits.smallestGap;
        chooseSplit(f, g, glm::dvec3(0.0), glm::dvec3(0.0), 0.5, &split);
        const Outcome outcome = evaluate(cell, target, f, g, &split, stats);
        if (outcome == Outcome::Witness) {
            answer = Reach::Visible;
            break;
        }
        if (outcome == Outcome::Proven)
            continue;
        if (split.spread <= limits.smallestGap || split.hopeless) {
            open.emplace_back(f, g);
            continue;
        }
        const Quad& q = split.edge < 2 ? f : g;
        const auto [q0, q1] = split.edge % 2 == 0 ? Quad{q.corner, 0.5 * q.u, q.v}.splitPair(q.corner + 0.5 * q.u)
                                                  : Quad{q.corner, q.u, 0.5 * q.v}.splitPair(q.corner + 0.5 * q.v);
        if (split.edge < 2) {
            push(q0, g, split.reach);
            push(q1, g, split.reach);
        } else {
            push(f, q0, split.reach);
            push(f, q1, split.reach);
        }
    }
    if (answer == Reach::Hidden) {
        for (const Entry& e : entries)
            if (!e.done)
                open.emplace_back(e.f, e.g);
        if (!open.empty()) {
            stats.openShafts += open.size();
            answer = residue(target, open, total, limits, seed, stats);
        }
    }
    if (statsOut)
        statsOut->add(stats);
    return answer;
}

} // namespace sightline::pvs
