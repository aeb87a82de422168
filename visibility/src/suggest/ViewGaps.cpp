#include "visibility/suggest/ViewGaps.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <unordered_map>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "visibility/Error.h"
#include "visibility/suggest/DistanceGrid.h"

namespace sightline::suggest {

namespace {

/// Union-find over the occupied voxels.
struct Groups {
    std::vector<std::uint32_t> parent;
    std::uint32_t find(std::uint32_t a)
    {
        while (parent[a] != a)
            a = parent[a] = parent[parent[a]];
        return a;
    }
    void join(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

} // namespace

std::vector<ViewGap> findViewGaps(const WorldTriangles& triangles, const Patch& source, const Patch& receiver,
                                  const ReceiverHeights& heights, const HiddenSampleMap& map, const GapSettings& settings)
{
    const std::uint64_t unblocked = map.rayCount() - map.blockedCount();
    if (unblocked > kMaxGapRays)
        throw Error("openings are found among at most " + std::to_string(kMaxGapRays) + " unblocked rays, and this pair has " +
                    std::to_string(unblocked) + ": use fewer samples on the patches");
    const int sources = source.sampleCount(), receivers = receiver.sampleCount();
    std::vector<glm::dvec3> receiverAt(static_cast<std::size_t>(receivers));
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (int j = 0; j < receivers; ++j) {
        receiverAt[std::size_t(j)] = displacedReceiverSample(source, receiver, heights, j);
        lo = glm::min(lo, receiverAt[std::size_t(j)]);
        hi = glm::max(hi, receiverAt[std::size_t(j)]);
    }
    for (int k = 0; k < 4; ++k) {
        lo = glm::min(lo, source.cornerPoint(k));
        hi = glm::max(hi, source.cornerPoint(k));
    }
    const double longest = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    const double voxel = longest / double(std::max(settings.cells, 8));
    const glm::dvec3 pad(2.0 * voxel);
    const DistanceGrid grid(triangles, lo - pad, hi + pad, voxel, settings.cells + 8);

    // Each unblocked ray's tightest point, away from its ends by a few voxels (or a tenth of it),
    // binned into cells wide enough that the tightest points of neighbouring rays through one
    // opening (as far apart as the patches' samples) fall into touching cells.
    double spacing = 2.0 * grid.voxel();
    for (const Patch* patch : {&source, &receiver})
        spacing = std::max({spacing, glm::length(patch->u) / patch->na, glm::length(patch->v) / patch->nb});
    const glm::dvec3 origin = lo - pad;
    const glm::ivec3 n = glm::ivec3(glm::ceil((hi + pad - origin) / spacing)) + 1;
    std::unordered_map<std::uint64_t, std::uint32_t> voxelGroup;   // cell -> index into `cells`
    struct Cell {
        glm::ivec3 at;
        glm::dvec3 sum{0.0};
        std::uint64_t rays = 0;
        double clearance = 0.0;
        std::vector<std::uint64_t> raySample;
    };
    std::vector<Cell> cells;
    const auto key = [&](glm::ivec3 c) { return (std::uint64_t(c.z) * std::uint64_t(n.y) + std::uint64_t(c.y)) * std::uint64_t(n.x) + std::uint64_t(c.x); };
    const int steps = std::max(settings.steps, 8);
    for (int j = 0; j < receivers; ++j)
        for (int i = 0; i < sources; ++i) {
            if (map.blocked(j, i))
                continue;
            const glm::dvec3 s = source.sample(i), r = receiverAt[std::size_t(j)];
            const double length = glm::length(r - s);
            const double margin = std::min(0.1, 3.0 * grid.voxel() / std::max(length, 1e-12));
            double best = std::numeric_limits<double>::infinity();
            glm::dvec3 at = 0.5 * (s + r);
            for (int k = 0; k <= steps; ++k) {
                const double t = margin + (1.0 - 2.0 * margin) * double(k) / steps;
                const glm::dvec3 p = s + t * (r - s);
                const double d = grid.distance(p);
                if (d < best) {
                    best = d;
                    at = p;
                }
            }
            const glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor((at - origin) / spacing)), glm::ivec3(0), n - 1);
            auto [it, fresh] = voxelGroup.try_emplace(key(c), std::uint32_t(cells.size()));
            if (fresh)
                cells.push_back(Cell{c, glm::dvec3(0.0), 0, 0.0, {}});
            Cell& cell = cells[it->second];
            cell.sum += at;
            ++cell.rays;
            cell.clearance = std::max(cell.clearance, std::isfinite(best) ? best : 0.0);
            if (cell.raySample.size() < kGapRaySample)
                cell.raySample.push_back(std::uint64_t(j) * std::uint64_t(sources) + std::uint64_t(i));
        }

    // Neighbouring cells (26-connected) are one opening.
    Groups groups{std::vector<std::uint32_t>(cells.size())};
    std::iota(groups.parent.begin(), groups.parent.end(), 0u);
    for (std::uint32_t a = 0; a < cells.size(); ++a)
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const glm::ivec3 c = cells[a].at + glm::ivec3(dx, dy, dz);
                    if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, n)))
                        continue;
                    if (const auto it = voxelGroup.find(key(c)); it != voxelGroup.end())
                        groups.join(a, it->second);
                }
    std::unordered_map<std::uint32_t, std::size_t> gapOf;
    std::vector<ViewGap> gaps;
    for (std::uint32_t a = 0; a < cells.size(); ++a) {
        const Cell& cell = cells[a];
        auto [it, fresh] = gapOf.try_emplace(groups.find(a), gaps.size());
        if (fresh) {
            ViewGap gap;
            gap.min = glm::dvec3(std::numeric_limits<double>::infinity());
            gap.max = -gap.min;
            gaps.push_back(gap);
        }
        ViewGap& gap = gaps[it->second];
        const glm::dvec3 mean = cell.sum / double(cell.rays);
        gap.centre += cell.sum;
        gap.rays += cell.rays;
        gap.min = glm::min(gap.min, mean);
        gap.max = glm::max(gap.max, mean);
        gap.clearance = std::max(gap.clearance, cell.clearance);
        for (std::uint64_t ray : cell.raySample)
            if (gap.raySample.size() < kGapRaySample)
                gap.raySample.push_back(ray);
    }
    for (ViewGap& gap : gaps)
        gap.centre /= double(gap.rays);
    std::sort(gaps.begin(), gaps.end(), [](const ViewGap& a, const ViewGap& b) { return a.rays > b.rays; });
    return gaps;
}

} // namespace sightline::suggest
