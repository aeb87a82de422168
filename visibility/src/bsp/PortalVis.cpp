#include "visibility/bsp/PortalVis.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <deque>
#include <numeric>
#include <limits>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "base/Error.h"

namespace sightline::bsp {

namespace {

/// A fixed-size bit set over the directed portals.
class PortalBits {
public:
    explicit PortalBits(std::size_t bits = 0) : words_((bits + 63) / 64, 0) {}
    bool test(std::size_t i) const { return (words_[i / 64] >> (i % 64)) & 1u; }
    void set(std::size_t i) { words_[i / 64] |= std::uint64_t(1) << (i % 64); }
    std::size_t count() const
    {
        std::size_t n = 0;
        for (std::uint64_t w : words_)
            n += std::size_t(std::popcount(w));
        return n;
    }
    /// this = a & b; whether it has a bit `not` lacks.
    bool assignAndHasBeyond(const PortalBits& a, const PortalBits& b, const PortalBits& notIn)
    {
        std::uint64_t beyond = 0;
        for (std::size_t k = 0; k < words_.size(); ++k) {
            words_[k] = a.words_[k] & b.words_[k];
            beyond |= words_[k] & ~notIn.words_[k];
        }
        return beyond != 0;
    }
    template <class F>
    void forEach(F f) const
    {
        for (std::size_t k = 0; k < words_.size(); ++k)
            for (std::uint64_t w = words_[k]; w; w &= w - 1)
                f(k * 64 + std::size_t(std::countr_zero(w)));
    }

private:
    std::vector<std::uint64_t> words_;
};

/// A portal crossed one way: from leaf `from` into leaf `into`, its plane's normal pointing into `into`.
struct DirectedPortal {
    int from = 0, into = 0;
    glm::dvec3 n{0.0};
    double d = 0.0;
    Winding w;
    glm::dvec3 centre{0.0};
    double radius = 0.0;
};

std::vector<DirectedPortal> directedPortals(const std::vector<LeafPortal>& open)
{
    std::vector<DirectedPortal> out;
    out.reserve(2 * open.size());
    for (const LeafPortal& p : open) {
        glm::dvec3 centre(0.0);
        for (const glm::dvec3& v : p.winding)
            centre += v;
        centre /= double(p.winding.size());
        double radius = 0.0;
        for (const glm::dvec3& v : p.winding)
            radius = std::max(radius, glm::length(v - centre));
        out.push_back({p.leaves[1], p.leaves[0], p.plane.normal, p.plane.dist, p.winding, centre, radius});
        out.push_back({p.leaves[0], p.leaves[1], -p.plane.normal, -p.plane.dist, p.winding, centre, radius});
    }
    return out;
}

/// Whether any of `w` lies more than `margin` in front of (n, d) (sign +1) or behind it (sign -1).
bool reaches(const DirectedPortal& q, const glm::dvec3& n, double d, double sign, double margin)
{
    const double centre = sign * (glm::dot(n, q.centre) - d);
    if (centre > q.radius + margin)
        return true;
    if (centre < -q.radius)
        return false;
    for (const glm::dvec3& v : q.w)
        if (sign * (glm::dot(n, v) - d) > margin)
            return true;
    return false;
}

/// A half-space kept by a cut: n.x - d >= -kPortalOnPlane.
struct Cut {
    glm::dvec3 n;
    double d;
};

/// Chops `w` in place to the front of `cut` (points within kPortalOnPlane kept), building the new
/// winding in `spare`; fewer than three points left: empty. Whether `w` changed.
bool chopInPlace(Winding& w, const Cut& cut, Winding& spare)
{
    constexpr std::size_t kOnStack = 64;
    double onStack[kOnStack];
    std::vector<double> onHeap;
    double* dist = w.size() <= kOnStack ? onStack : (onHeap.resize(w.size()), onHeap.data());
    bool behind = false;
    for (std::size_t i = 0; i < w.size(); ++i) {
        dist[i] = glm::dot(cut.n, w[i]) - cut.d;
        behind |= dist[i] < -kPortalOnPlane;
    }
    if (!behind)
        return false;
    const auto side = [](double x) { return x > kPortalOnPlane ? 1 : x < -kPortalOnPlane ? -1 : 0; };
    spare.clear();
    for (std::size_t i = 0; i < w.size(); ++i) {
        const std::size_t j = (i + 1) % w.size();
        const int si = side(dist[i]), sj = side(dist[j]);
        if (si >= 0)
            spare.push_back(w[i]);
        if (si != 0 && sj != 0 && si != sj)
            spare.push_back(w[i] + (w[j] - w[i]) * (dist[i] / (dist[i] - dist[j])));
    }
    if (spare.size() < 3)
        spare.clear();
    w.swap(spare);
    return true;
}

/// Whether anything is left of `w` after every cut.
bool applyCuts(const std::vector<Cut>& cuts, Winding& w, Winding& spare)
{
    for (const Cut& cut : cuts) {
        chopInPlace(w, cut, spare);
        if (w.empty())
            return false;
    }
    return true;
}

/// The cuts that lines through `a` then `b` (flip: through `b` then `a`) make beyond them: for
/// each plane through an edge of `a` and a corner of `b` with `a` wholly on one side and `b` on
/// the other, the lines cross it once, so beyond their second winding they stay on its side. The
/// sides are measured by the windings' extents along the normal, so no epsilon decides them.
void appendSeparators(const Winding& a, const Winding& b, bool flip, std::vector<Cut>& cuts)
{
    constexpr double kSeparated = 1e-7;   // rounding of dot products at Quake's coordinates
    const std::size_t na = a.size();
    for (std::size_t i = 0; i < na; ++i) {
        const glm::dvec3& v1 = a[i];
        const glm::dvec3 edge = a[(i + 1) % na] - v1;
        for (const glm::dvec3& corner : b) {
            const glm::dvec3 n = glm::cross(edge, corner - v1);   // not normalised until kept
            const double length = glm::length(n);
            if (length < 1e-9)
                continue;
            const double tolerance = kSeparated * length;
            double aMin = std::numeric_limits<double>::max(), aMax = -aMin;
            for (const glm::dvec3& v : a) {
                const double x = glm::dot(n, v);
                aMin = std::min(aMin, x), aMax = std::max(aMax, x);
            }
            // The plane holds an edge of `a`, so `a` lies on one side of it unless the plane cuts
            // it; `b` must then lie wholly on the other. Most planes fail on b's first corners.
            const double onPlane = glm::dot(n, corner);
            const bool aBelow = aMax - onPlane <= tolerance, aAbove = onPlane - aMin <= tolerance;
            if (aBelow == aAbove)
                continue;   // a on both sides, or a in the plane: no separation
            double bMin = std::numeric_limits<double>::max(), bMax = -bMin;
            bool separated = true;
            for (const glm::dvec3& v : b) {
                const double x = glm::dot(n, v);
                bMin = std::min(bMin, x), bMax = std::max(bMax, x);
                if (aBelow ? x < aMax - tolerance : x > aMin + tolerance) {
                    separated = false;
                    break;
                }
            }
            if (!separated)
                continue;
            // Lines from the first winding through the second keep going the same way along n.
            const glm::dvec3 unit = n / length;
            if (aBelow)
                cuts.push_back(flip ? Cut{-unit, -aMax / length} : Cut{unit, bMin / length});
            else
                cuts.push_back(flip ? Cut{unit, aMin / length} : Cut{-unit, -bMax / length});
        }
    }
}

class PortalFlow {
public:
    PortalFlow(int leafCount, const std::vector<LeafPortal>& open, const PortalVisOptions& options)
        : leafCount_(leafCount), options_(options), portals_(directedPortals(open)), leaving_(std::size_t(leafCount) + 1),
          arena_(options.threads > 0 ? options.threads : tbb::task_arena::automatic)
    {
        const double bytes = double(portals_.size()) * double(portals_.size()) / 8.0 * 2.0;
        if (bytes > double(pvs::kMaxRowTableBytes))
            throw Error("vis: " + std::to_string(portals_.size()) + " directed portals need " +
                        std::to_string(std::size_t(bytes) >> 20) + " MiB of portal sets, more than the " +
                        std::to_string(pvs::kMaxRowTableBytes >> 20) + " MiB allowed");
        for (std::size_t k = 0; k < portals_.size(); ++k) {
            const DirectedPortal& q = portals_[k];
            if (q.from < 1 || q.from > leafCount || q.into < 1 || q.into > leafCount || q.w.size() < 3)
                throw Error("vis: portal " + std::to_string(k / 2) + " does not join two of the level's " +
                            std::to_string(leafCount) + " visleafs");
            leaving_[std::size_t(q.from)].push_back(k);
        }
        mightSee_.assign(portals_.size(), PortalBits(portals_.size()));
        seen_.assign(portals_.size(), PortalBits(portals_.size()));
    }

    pvs::VisibilityRows run(PortalVisStats* stats)
    {
        std::vector<std::size_t> steps(portals_.size(), 0);
        std::vector<char> overBudget(portals_.size(), 0);
        forEachPortal(0, portals_.size(), [&](std::size_t p) { flood(p); });
        // Vis's order: the portals that might see least go first, and a finished portal's chains
        // stand in for its flood in later walks (every line through it is in them). Batches of a
        // fixed size use only the batches before them, so the rows do not depend on the threads.
        std::vector<std::size_t> order(portals_.size());
        std::iota(order.begin(), order.end(), std::size_t(0));
        std::vector<std::size_t> floodSize(portals_.size());
        for (std::size_t p = 0; p < portals_.size(); ++p)
            floodSize[p] = mightSee_[p].count();
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return floodSize[a] < floodSize[b]; });
        done_.assign(portals_.size(), 0);
        constexpr std::size_t kBatch = 64;
        for (std::size_t first = 0; first < order.size(); first += kBatch) {
            const std::size_t last = std::min(order.size(), first + kBatch);
            forEachPortal(first, last, [&](std::size_t k) { steps[order[k]] = chains(order[k], overBudget[order[k]]); });
            for (std::size_t k = first; k < last; ++k)
                done_[order[k]] = 1;
        }
        if (stats) {
            *stats = {};
            stats->directedPortals = portals_.size();
            for (std::size_t p = 0; p < portals_.size(); ++p) {
                stats->floodPortals += mightSee_[p].count();
                stats->visiblePortals += seen_[p].count();
                stats->steps += steps[p];
                stats->portalsOverBudget += std::size_t(overBudget[p]);
            }
        }
        return rows();
    }

private:
    template <class F>
    void forEachPortal(std::size_t first, std::size_t last, F f)
    {
        arena_.execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 1), [&](const auto& range) {
                for (std::size_t p = range.begin(); p != range.end(); ++p)
                    f(p);
            });
        });
    }

    /// Vis's "might see": the portals reachable from p's far leaf through portals that lie (partly)
    /// in front of p and have p (partly) behind them, the only ones a line through p can cross next.
    void flood(std::size_t p)
    {
        const DirectedPortal& source = portals_[p];
        PortalBits& reached = mightSee_[p];
        std::vector<int> todo{source.into};
        while (!todo.empty()) {
            const int leaf = todo.back();
            todo.pop_back();
            for (std::size_t q : leaving_[std::size_t(leaf)]) {
                if (q == p || reached.test(q))
                    continue;
                const DirectedPortal& next = portals_[q];
                if (!reaches(next, source.n, source.d, 1.0, kPortalOnPlane) ||
                    !reaches(source, next.n, next.d, -1.0, kPortalOnPlane))
                    continue;
                reached.set(q);
                todo.push_back(next.into);
            }
        }
    }

    struct Step {
        const Winding* source;
        const Winding* pass;     ///< the last portal crossed, cut; null before the first
        const Winding* before;   ///< the portal crossed before `pass`, cut; null before the second
        const PortalBits* might;
    };

    /// What one depth of the walk reuses from one portal to the next (no allocation once warm).
    struct Frame {
        explicit Frame(std::size_t portals) : might(portals) {}
        PortalBits might;
        Winding narrowed, source, pass, spare;
        std::vector<Cut> sharedCuts, ownCuts;   ///< separators of the step's source and pass; of a cut source
        bool sharedReady = false;
    };

    std::size_t chains(std::size_t p, char& overBudget)
    {
        const DirectedPortal& start = portals_[p];
        std::size_t steps = 0;
        const Step head{&start.w, nullptr, nullptr, &mightSee_[p]};
        std::deque<Frame> frames;   // one per depth; a deque keeps the shallower ones where they are
        if (!walk(p, start.into, head, 0, frames, steps)) {
            seen_[p] = mightSee_[p];   // the flood is safe, only looser
            overBudget = 1;
        }
        return steps;
    }

    /// Crosses every portal leaving `leaf` that a line through the chain so far can still cross.
    /// False when the step budget ran out.
    bool walk(std::size_t p, int leaf, const Step& prev, std::size_t depth, std::deque<Frame>& frames, std::size_t& steps)
    {
        const DirectedPortal& start = portals_[p];
        PortalBits& seen = seen_[p];
        if (frames.size() <= depth)
            frames.emplace_back(portals_.size());
        Frame& f = frames[depth];
        f.sharedReady = false;
        const Winding* origin = prev.source;   // narrowed on first use (below)
        for (std::size_t q : leaving_[std::size_t(leaf)]) {
            if (!prev.might->test(q))
                continue;
            if (++steps > options_.stepsPerPortal)
                return false;
            const PortalBits& beyond = done_[q] ? seen_[q] : mightSee_[q];
            const bool more = f.might.assignAndHasBeyond(*prev.might, beyond, seen);
            if (!more && seen.test(q))
                continue;   // nothing this way that is not already seen
            if (origin == prev.source && prev.before) {
                // The chain's lines run backwards from the last portal through the one before
                // reach the source: cut it to that anti-penumbra too, once per leaf, when a
                // portal leaving it needs the source.
                f.narrowed.assign(prev.source->begin(), prev.source->end());
                f.ownCuts.clear();
                appendSeparators(*prev.pass, *prev.before, false, f.ownCuts);
                appendSeparators(*prev.before, *prev.pass, true, f.ownCuts);
                if (!applyCuts(f.ownCuts, f.narrowed, f.spare))
                    return true;   // no line through the whole chain
                origin = &f.narrowed;
            }
            const DirectedPortal& next = portals_[q];
            f.pass.assign(next.w.begin(), next.w.end());
            chopInPlace(f.pass, {start.n, start.d}, f.spare);
            if (f.pass.empty())
                continue;
            f.source.assign(origin->begin(), origin->end());
            const bool sourceCut = chopInPlace(f.source, {-next.n, -next.d}, f.spare);
            if (f.source.empty())
                continue;
            if (prev.pass) {
                // Separators of the uncut source hold for any part of it: shared by every portal
                // that leaves the source whole, computed again only for one that cuts it.
                std::vector<Cut>* cuts = &f.sharedCuts;
                if (sourceCut) {
                    f.ownCuts.clear();
                    appendSeparators(f.source, *prev.pass, false, f.ownCuts);
                    appendSeparators(*prev.pass, f.source, true, f.ownCuts);
                    cuts = &f.ownCuts;
                } else if (!f.sharedReady) {
                    f.sharedCuts.clear();
                    appendSeparators(*origin, *prev.pass, false, f.sharedCuts);
                    appendSeparators(*prev.pass, *origin, true, f.sharedCuts);
                    f.sharedReady = true;
                }
                if (!applyCuts(*cuts, f.pass, f.spare))
                    continue;
            }
            seen.set(q);
            if (!walk(p, next.into, Step{&f.source, &f.pass, prev.pass, &f.might}, depth + 1, frames, steps))
                return false;
        }
        return true;
    }

    pvs::VisibilityRows rows() const
    {
        const std::size_t n = std::size_t(leafCount_);
        pvs::VisibilityRows out(n, n);
        for (std::size_t leaf = 1; leaf <= n; ++leaf) {
            out.set(leaf - 1, leaf - 1, true);
            for (std::size_t p : leaving_[leaf]) {
                out.set(leaf - 1, std::size_t(portals_[p].into) - 1, true);
                seen_[p].forEach([&](std::size_t q) { out.set(leaf - 1, std::size_t(portals_[q].into) - 1, true); });
            }
        }
        return out;
    }

    int leafCount_ = 0;
    PortalVisOptions options_;
    std::vector<DirectedPortal> portals_;
    std::vector<std::vector<std::size_t>> leaving_;   ///< per leaf 0..visleafs
    std::vector<PortalBits> mightSee_, seen_;
    std::vector<char> done_;   ///< per directed portal: its chains are final (written before a batch, read during it)
    tbb::task_arena arena_;
};

} // namespace

pvs::VisibilityRows portalVis(int leafCount, const std::vector<LeafPortal>& open, const PortalVisOptions& options,
                              PortalVisStats* stats)
{
    if (leafCount < 0)
        throw Error("vis: a negative leaf count");
    return PortalFlow(leafCount, open, options).run(stats);
}

pvs::VisibilityRows portalVis(const QuakeBsp& bsp, const std::vector<LeafPortal>& open, const PortalVisOptions& options,
                              PortalVisStats* stats)
{
    return portalVis(bsp.visleafs, open, options, stats);
}

} // namespace sightline::bsp
