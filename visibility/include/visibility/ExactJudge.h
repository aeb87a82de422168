#pragma once
// The judge of docs/design.md §2's "Exact" contract: an exact double-precision brute force that says,
// for any ray, whether it is blocked and whether it is a tie. The tests judge every method with
// it, and `bench` sorts each method's disagreements with the reference into ties and errors.
//
// A ray (receiver sample j -> source sample i) is blocked when its segment crosses a triangle
// strictly between its ends. It is a tie when its answer could change under a perturbation of
// kTieMetres (1e-5 m): the segment passes within kTieMetres of a triangle's edge or vertex (an
// edge tie), or one of its ends lies within kTieMetres of a triangle (an end tie: it meets, or
// nearly meets, the triangle at its own end). A ray that some triangle blocks with no tie is
// blocked, whatever the other triangles do; a ray no triangle blocks and none ties is free; every
// other ray is a tie, and either answer is allowed for it.
//
// Each triangle is tested with orientation predicates (signed volumes) in double, relative to the
// ray's receiver end, so a level 100 km from the origin is judged as well as one at the origin:
// rounding (1e-11 m there) is six orders of magnitude below the tie distance, so the predicates
// can only err on rays that are ties anyway.
//
// Brute force is slow, so the judge is asked only about chosen rays: those on which the methods
// under test disagree with each other, and a random sample (a method that is wrong in the same
// way as all the others is caught there). Triangles are culled per receiver sample by bounding
// boxes, which is independent of the shaft culling the samplers use.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vector_relational.hpp>

#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/Scene.h"
#include "visibility/SourceJitter.h"

namespace sightline {

inline constexpr double kTieMetres = 1e-5;

enum class RayKind : std::uint8_t {
    Free,      ///< no triangle blocks it, none is within the tie distance
    Blocked,   ///< some triangle blocks it with a margin above the tie distance
    EdgeTie,   ///< not clearly blocked; passes within the tie distance of a triangle's edge or vertex
    EndTie,    ///< not clearly blocked; an end lies within the tie distance of a triangle
};

inline const char* toString(RayKind kind)
{
    switch (kind) {
    case RayKind::Free: return "free";
    case RayKind::Blocked: return "blocked";
    case RayKind::EdgeTie: return "edge tie";
    case RayKind::EndTie: return "end tie";
    }
    return "?";
}

namespace judge_detail {

/// Squared distance between segments p0p1 and q0q1 (Ericson, Real-Time Collision Detection, 5.1.9).
inline double segmentSegmentDistance2(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& q0,
                                      const glm::dvec3& q1)
{
    const glm::dvec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
    double s = 0.0, t = 0.0;
    if (a <= 0.0 && e <= 0.0)
        return glm::dot(r, r);
    if (a <= 0.0) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = glm::dot(d1, r);
        if (e <= 0.0) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = glm::dot(d1, d2), denominator = a * e - b * b;
            s = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0.0) {
                t = 0.0;
                s = std::clamp(-c / a, 0.0, 1.0);
            } else if (t > 1.0) {
                t = 1.0;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    const glm::dvec3 between = (p0 + d1 * s) - (q0 + d2 * t);
    return glm::dot(between, between);
}

/// Squared distance from p to triangle abc (Ericson 5.1.5, closest point by Voronoi regions).
inline double pointTriangleDistance2(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    const auto d2 = [&](const glm::dvec3& q) { return glm::dot(p - q, p - q); };
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2v = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2v <= 0.0)
        return d2(a);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3)
        return d2(b);
    const double vc = d1 * d4 - d3 * d2v;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
        return d2(a + ab * (d1 / (d1 - d3)));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6)
        return d2(c);
    const double vb = d5 * d2v - d1 * d6;
    if (vb <= 0.0 && d2v >= 0.0 && d6 <= 0.0)
        return d2(a + ac * (d2v / (d2v - d6)));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
        return d2(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    const double sum = va + vb + vc;
    if (!(sum > 0.0))   // degenerate triangle: the nearest of its edges
        return std::min({segmentSegmentDistance2(p, p, a, b), segmentSegmentDistance2(p, p, b, c),
                         segmentSegmentDistance2(p, p, c, a)});
    return d2(a + ab * (vb / sum) + ac * (vc / sum));
}

inline double orient(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d)
{
    return glm::dot(glm::cross(b - a, c - a), d - a);
}

} // namespace judge_detail

/// One segment against one triangle, everything relative to the segment's start.
struct TriangleVerdict {
    bool crosses = false;   ///< strictly between the ends, strictly inside
    bool edgeTie = false;
    bool endTie = false;
};

inline TriangleVerdict judgeTriangle(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a,
                                     const glm::dvec3& b, const glm::dvec3& c)
{
    TriangleVerdict v;
    constexpr double tie2 = kTieMetres * kTieMetres;
    v.endTie = judge_detail::pointTriangleDistance2(p, a, b, c) < tie2 || judge_detail::pointTriangleDistance2(q, a, b, c) < tie2;
    v.edgeTie = judge_detail::segmentSegmentDistance2(p, q, a, b) < tie2 || judge_detail::segmentSegmentDistance2(p, q, b, c) < tie2 ||
                judge_detail::segmentSegmentDistance2(p, q, c, a) < tie2;
    const double sp = judge_detail::orient(a, b, c, p), sq = judge_detail::orient(a, b, c, q);
    if (!((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)))
        return v;
    const double e0 = judge_detail::orient(p, q, a, b), e1 = judge_detail::orient(p, q, b, c), e2 = judge_detail::orient(p, q, c, a);
    v.crosses = (e0 > 0.0 && e1 > 0.0 && e2 > 0.0) || (e0 < 0.0 && e1 < 0.0 && e2 < 0.0);
    return v;
}

/// Where a method's map differs from the exact answer.
struct Verdict {
    std::uint64_t judged = 0;          ///< rays the judge was asked about
    std::uint64_t wronglyBlocked = 0;  ///< method blocked, exactly free (not a tie)
    std::uint64_t wronglyFree = 0;     ///< method free, exactly blocked (not a tie)
    std::uint64_t edgeTies = 0;        ///< disagreements (with the exact rounding-free answer) on edge ties
    std::uint64_t endTies = 0;         ///< ... on end ties
    std::vector<std::pair<int, int>> examples;   ///< (receiver j, source i) of some non-tie errors

    std::uint64_t nonTie() const { return wronglyBlocked + wronglyFree; }
};

class ExactJudge {
public:
    /// `displaced` (may be null): a bumpy receiver's sample positions by bit index (ReceiverHeights).
    ExactJudge(const WorldTriangles& triangles, const Patch& source, const Patch& receiver,
               const SourceJitter& jitter = {}, const std::vector<glm::dvec3>* displaced = nullptr)
        : source_(source), receiver_(receiver), jitter_(jitter)
    {
        receiverEnds_.resize(std::size_t(receiver.sampleCount()));
        for (int j = 0; j < receiver.sampleCount(); ++j)
            receiverEnds_[std::size_t(j)] = displaced ? (*displaced)[std::size_t(j)] : receiver.sample(j);
        // Bounding boxes of every segment's possible ends: the source (with a cell's jitter) and
        // the receiver samples, padded by the tie distance.
        glm::dvec3 lo(1e300), hi(-1e300);
        for (int k = 0; k < 4; ++k) {
            const glm::dvec3 corner = source.cornerPoint(k);
            const glm::dvec3 cellPad = (glm::abs(source.u) / double(source.na) + glm::abs(source.v) / double(source.nb));
            lo = glm::min(lo, corner - cellPad), hi = glm::max(hi, corner + cellPad);
        }
        sourceLo_ = lo, sourceHi_ = hi;
        for (const glm::dvec3& r : receiverEnds_)
            lo = glm::min(lo, r), hi = glm::max(hi, r);
        const glm::dvec3 pad(2.0 * kTieMetres + 1e-9 * glm::length(hi - lo));
        lo -= pad, hi += pad;
        for (std::size_t t = 0; t < triangles.size(); ++t) {
            const glm::dvec3 a(triangles.vertices[3 * t]), b(triangles.vertices[3 * t + 1]), c(triangles.vertices[3 * t + 2]);
            const glm::dvec3 tlo = glm::min(a, glm::min(b, c)), thi = glm::max(a, glm::max(b, c));
            if (glm::any(glm::lessThan(thi, lo)) || glm::any(glm::greaterThan(tlo, hi)))
                continue;
            triangles_.push_back({a, b, c, tlo, thi});
        }
    }

    std::size_t candidateTriangles() const { return triangles_.size(); }

    /// The exact answer for ray (receiver sample j, source sample i).
    RayKind ray(int j, int i) const
    {
        const std::vector<std::uint32_t> candidates = candidatesFor(j);
        return rayAmong(j, i, candidates);
    }

    /// Judges `map` on the given rays (receiver j, source i). Rays may repeat across calls.
    Verdict judge(const HiddenSampleMap& map, const std::vector<std::pair<int, int>>& rays,
                  std::size_t maxExamples = 8) const
    {
        Verdict verdict;
        forEachRay(rays, [&](int j, int i, RayKind kind) {
            ++verdict.judged;
            const bool blocked = map.blocked(j, i);
            switch (kind) {
            case RayKind::Free:
            case RayKind::Blocked:
                if (blocked != (kind == RayKind::Blocked)) {
                    (blocked ? verdict.wronglyBlocked : verdict.wronglyFree) += 1;
                    if (verdict.examples.size() < maxExamples)
                        verdict.examples.emplace_back(j, i);
                }
                break;
            case RayKind::EdgeTie: ++verdict.edgeTies; break;
            case RayKind::EndTie: ++verdict.endTies; break;
            }
        });
        return verdict;
    }

    /// The exact kinds of the given rays, in their order.
    std::vector<RayKind> kinds(const std::vector<std::pair<int, int>>& rays) const
    {
        std::vector<RayKind> out;
        out.reserve(rays.size());
        forEachRay(rays, [&](int, int, RayKind kind) { out.push_back(kind); });
        return out;
    }

    glm::dvec3 sourceEnd(int j, int i) const { return source_.sample(i) + jitter_.shift(source_, j); }
    const glm::dvec3& receiverEnd(int j) const { return receiverEnds_[std::size_t(j)]; }

private:
    struct Candidate {
        glm::dvec3 a, b, c, lo, hi;
    };

    /// Triangles whose box meets the box of receiver sample j's segments (padded).
    std::vector<std::uint32_t> candidatesFor(int j) const
    {
        const glm::dvec3& r = receiverEnds_[std::size_t(j)];
        const glm::dvec3 lo = glm::min(sourceLo_, r), hi = glm::max(sourceHi_, r);
        const glm::dvec3 pad(2.0 * kTieMetres + 1e-9 * glm::length(hi - lo));
        std::vector<std::uint32_t> out;
        for (std::size_t t = 0; t < triangles_.size(); ++t) {
            const Candidate& c = triangles_[t];
            if (glm::any(glm::lessThan(c.hi, lo - pad)) || glm::any(glm::greaterThan(c.lo, hi + pad)))
                continue;
            out.push_back(std::uint32_t(t));
        }
        return out;
    }

    RayKind rayAmong(int j, int i, const std::vector<std::uint32_t>& candidates) const
    {
        const glm::dvec3& origin = receiverEnds_[std::size_t(j)];
        const glm::dvec3 p(0.0), q = sourceEnd(j, i) - origin;
        const glm::dvec3 lo = glm::min(p, q) - glm::dvec3(2.0 * kTieMetres), hi = glm::max(p, q) + glm::dvec3(2.0 * kTieMetres);
        bool edgeTie = false, endTie = false, crossedWithTie = false;
        for (std::uint32_t t : candidates) {
            const Candidate& c = triangles_[t];
            if (glm::any(glm::lessThan(c.hi - origin, lo)) || glm::any(glm::greaterThan(c.lo - origin, hi)))
                continue;
            const TriangleVerdict v = judgeTriangle(p, q, c.a - origin, c.b - origin, c.c - origin);
            if (v.crosses && !v.edgeTie && !v.endTie)
                return RayKind::Blocked;
            crossedWithTie = crossedWithTie || v.crosses;
            edgeTie = edgeTie || v.edgeTie;
            endTie = endTie || v.endTie;
        }
        (void)crossedWithTie;
        if (endTie)
            return RayKind::EndTie;
        if (edgeTie)
            return RayKind::EdgeTie;
        return RayKind::Free;
    }

    template <typename Visit>
    void forEachRay(const std::vector<std::pair<int, int>>& rays, Visit&& visit) const
    {
        // Grouped by receiver sample: one candidate list per group.
        std::vector<std::size_t> order(rays.size());
        for (std::size_t k = 0; k < order.size(); ++k)
            order[k] = k;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return rays[x].first < rays[y].first; });
        std::vector<RayKind> kinds(rays.size());
        int current = -1;
        std::vector<std::uint32_t> candidates;
        for (std::size_t k : order) {
            const auto [j, i] = rays[k];
            if (j != current)
                candidates = candidatesFor(j), current = j;
            kinds[k] = rayAmong(j, i, candidates);
        }
        for (std::size_t k = 0; k < rays.size(); ++k)
            visit(rays[k].first, rays[k].second, kinds[k]);
    }

    Patch source_, receiver_;
    SourceJitter jitter_;
    std::vector<glm::dvec3> receiverEnds_;
    glm::dvec3 sourceLo_{0.0}, sourceHi_{0.0};
    std::vector<Candidate> triangles_;
};

/// The rays worth judging: every ray on which any two of `maps` differ, plus `sampled` rays drawn
/// at random (seeded) from the whole map, so a mistake all methods share is caught too.
inline std::vector<std::pair<int, int>> raysToJudge(const std::vector<const HiddenSampleMap*>& maps, std::size_t sampled,
                                                    unsigned seed)
{
    std::vector<std::pair<int, int>> rays;
    if (maps.empty())
        return rays;
    const HiddenSampleMap& first = *maps.front();
    const int words = first.wordsPerRow();
    for (int j = 0; j < first.receiverCount(); ++j)
        for (int w = 0; w < words; ++w) {
            std::uint64_t differ = 0;
            const std::uint64_t base = first.row(j)[std::size_t(w)];
            for (const HiddenSampleMap* m : maps)
                differ |= m->row(j)[std::size_t(w)] ^ base;
            for (; differ; differ &= differ - 1)
                rays.emplace_back(j, 64 * w + std::countr_zero(differ));
        }
    std::mt19937 rng(seed);
    for (std::size_t k = 0; k < sampled; ++k)
        rays.emplace_back(int(rng() % std::uint32_t(first.receiverCount())), int(rng() % std::uint32_t(first.sourceCount())));
    return rays;
}

} // namespace sightline
