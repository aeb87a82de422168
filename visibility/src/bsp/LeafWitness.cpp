#include "visibility/bsp/LeafWitness.h"

#include <algorithm>
#include <atomic>
#include <mutex>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace sightline::bsp {

namespace {

bool isLiquid(int c) { return c == kContentsWater || c == kContentsSlime || c == kContentsLava; }

bool crossable(int from, int through, bool clearLiquids)
{
    if (through == from)
        return true;
    const auto clear = [](int c) { return c == kContentsEmpty || isLiquid(c); };
    return clearLiquids && clear(from) && clear(through);
}

std::uint64_t splitmix(std::uint64_t& state)
{
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
double unit(std::uint64_t& state) { return double(splitmix(state) >> 11) * 0x1.0p-53; }

/// Candidate ends inside each visleaf (index leaf - 1); each point checked to lie in its leaf.
std::vector<std::vector<glm::dvec3>> leafPoints(const QuakeBsp& bsp, const std::vector<LeafPortal>& portals,
                                                const WitnessOptions& options)
{
    const std::size_t n = std::size_t(bsp.visleafs);
    std::vector<std::vector<glm::dvec3>> corners(n);
    for (const LeafPortal& p : portals)
        for (int leaf : p.leaves)
            if (leaf >= 1 && leaf <= bsp.visleafs)
                for (std::size_t i = 0; i < p.winding.size(); ++i) {
                    corners[std::size_t(leaf) - 1].push_back(p.winding[i]);
                    corners[std::size_t(leaf) - 1].push_back(0.5 * (p.winding[i] + p.winding[(i + 1) % p.winding.size()]));
                }
    std::vector<std::vector<glm::dvec3>> points(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t l) {
        auto& c = corners[l];
        if (c.empty())
            return;
        glm::dvec3 centre(0.0);
        for (const glm::dvec3& v : c)
            centre += v;
        centre /= double(c.size());
        std::uint64_t state = options.seed * 0x2545f4914f6cdd1dull + l;
        auto keep = [&](const glm::dvec3& p) {
            if (leafAt(bsp, p) == int(l) + 1)
                points[l].push_back(p);
        };
        keep(centre);
        // Corners first (in a seeded order), then random points towards the centre.
        for (std::size_t i = c.size(); i > 1; --i)
            std::swap(c[i - 1], c[splitmix(state) % i]);
        for (std::size_t i = 0; i < c.size() && points[l].size() < std::size_t(options.pointsPerLeaf) / 2; ++i)
            keep(c[i] + (centre - c[i]) * 1e-3);
        for (int tries = 0; tries < 4 * options.pointsPerLeaf && points[l].size() < std::size_t(options.pointsPerLeaf); ++tries) {
            const glm::dvec3& a = c[splitmix(state) % c.size()];
            const glm::dvec3& b = c[splitmix(state) % c.size()];
            const double s = unit(state), t = unit(state);
            keep(centre + ((a + (b - a) * s) - centre) * (1.0 - 1e-3) * t);
        }
    });
    return points;
}

/// Open regions: leaves joined through portals a line of sight may cross get one label.
std::vector<int> regions(const QuakeBsp& bsp, const std::vector<LeafPortal>& portals, bool clearLiquids)
{
    const std::size_t n = std::size_t(bsp.visleafs);
    std::vector<int> parent(n + 1);
    for (std::size_t i = 0; i <= n; ++i)
        parent[i] = int(i);
    auto find = [&](int x) {
        while (parent[std::size_t(x)] != x)
            x = parent[std::size_t(x)] = parent[std::size_t(parent[std::size_t(x)])];
        return x;
    };
    for (const LeafPortal& p : portals)
        if (seesThrough(bsp, p, clearLiquids))
            parent[std::size_t(find(p.leaves[0]))] = find(p.leaves[1]);
    std::vector<int> label(n + 1);
    for (std::size_t i = 0; i <= n; ++i)
        label[i] = find(int(i));
    return label;
}

} // namespace

bool segmentOpen(const QuakeBsp& bsp, const glm::dvec3& a, const glm::dvec3& b, int contents, bool clearLiquids)
{
    struct Piece {
        int child;
        glm::dvec3 p, q;
    };
    std::vector<Piece> todo{{bsp.headnode, a, b}};
    while (!todo.empty()) {
        Piece piece = todo.back();
        todo.pop_back();
        while (piece.child >= 0) {
            const BspNode& node = bsp.nodes[std::size_t(piece.child)];
            const BspPlane& plane = bsp.planes[std::size_t(node.plane)];
            const double d1 = plane.side(piece.p), d2 = plane.side(piece.q);
            if (d1 > 0.0 && d2 > 0.0) {
                piece.child = node.children[0];
            } else if (d1 <= 0.0 && d2 <= 0.0) {
                piece.child = node.children[1];
            } else {
                const glm::dvec3 mid = piece.p + (piece.q - piece.p) * (d1 / (d1 - d2));
                const int near = d1 > 0.0 ? 0 : 1;
                todo.push_back({node.children[std::size_t(1 - near)], mid, piece.q});
                piece = {node.children[std::size_t(near)], piece.p, mid};
            }
        }
        const int leaf = QuakeBsp::leafOfChild(piece.child);
        if (!crossable(contents, bsp.leaves[std::size_t(leaf)].contents, clearLiquids))
            return false;
    }
    return true;
}

WitnessCount searchWitnesses(const QuakeBsp& bsp, const std::vector<LeafPortal>& treePortals,
                             const pvs::VisibilityRows& rows, bool culled, const WitnessOptions& options)
{
    const std::size_t n = std::size_t(bsp.visleafs);
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    std::vector<std::vector<glm::dvec3>> points;
    arena.execute([&] { points = leafPoints(bsp, treePortals, options); });
    const auto label = regions(bsp, treePortals, options.clearLiquids);
    std::atomic<std::size_t> pairs{0}, witnessed{0};
    std::mutex examplesLock;
    WitnessCount out;
    arena.execute([&] {
        tbb::parallel_for(std::size_t(0), n, [&](std::size_t a) {
            const int contents = bsp.leaves[a + 1].contents;
            if (contents == kContentsSolid || points[a].empty())
                return;
            std::size_t localPairs = 0, localWitnessed = 0;
            for (std::size_t b = a + 1; b < n; ++b) {
                if (label[a + 1] != label[b + 1] || points[b].empty())
                    continue;
                const bool kept = rows.visible(a, b) && rows.visible(b, a);
                if (kept == culled)
                    continue;
                ++localPairs;
                std::uint64_t state = options.seed ^ (a * 0x9e3779b97f4a7c15ull) ^ (b * 0xc2b2ae3d27d4eb4full);
                for (int s = 0; s < options.segmentsPerPair; ++s) {
                    const glm::dvec3& p = points[a][splitmix(state) % points[a].size()];
                    const glm::dvec3& q = points[b][splitmix(state) % points[b].size()];
                    if (segmentOpen(bsp, p, q, contents, options.clearLiquids)) {
                        ++localWitnessed;
                        if (culled) {
                            std::lock_guard lock(examplesLock);
                            out.examples.emplace_back(int(a) + 1, int(b) + 1);
                        }
                        break;
                    }
                }
            }
            pairs += localPairs;
            witnessed += localWitnessed;
        });
    });
    out.pairs = pairs;
    out.witnessed = witnessed;
    std::sort(out.examples.begin(), out.examples.end());
    if (out.examples.size() > 16)
        out.examples.resize(16);
    return out;
}

} // namespace sightline::bsp
