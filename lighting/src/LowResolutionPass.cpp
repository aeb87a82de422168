#include "lighting/LowResolutionPass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>

#include <glm/common.hpp>

#include "base/Error.h"

namespace sightline {

namespace {

/// 0, stride, 2 stride, ... and the last texel: a tile's coarse rows or columns.
std::vector<int> coarseLines(int size, int stride)
{
    std::vector<int> lines;
    for (int s = 0; s < size; s += stride)
        lines.push_back(s);
    if (size > 0 && lines.back() != size - 1)
        lines.push_back(size - 1);
    return lines;
}

/// The interval [lines[i], lines[i + 1]] that holds s (the last one for the last texel).
std::size_t intervalOf(const std::vector<int>& lines, int s)
{
    const auto above = std::upper_bound(lines.begin(), lines.end(), s);
    return std::min(std::size_t(above - lines.begin()) - 1, lines.size() - 2);
}

} // namespace

bool cornersDisagree(const std::array<float, 4>& values)
{
    const auto [low, high] = std::minmax_element(values.begin(), values.end());
    if (*high <= 0.0f)
        return false;   // unlit all round
    return *low <= 0.0f || *high - *low > kRefineRelative * *high;
}

namespace {

/// Groups of texels from tiles too small for a block: by cube and by the axis their normal leans
/// to most. The first of each group is its coarse point.
class SmallTileGroups {
public:
    SmallTileGroups(std::span<const ShadingPoint> points, double cell) : points_(points), cell_(cell) {}

    /// Puts point `p` in its group; true when it opens one (it is then coarse).
    bool add(std::uint32_t p)
    {
        const ShadingPoint& x = points_[p];
        const glm::dvec3 n = glm::abs(x.normal);
        const int axis = n.x >= n.y && n.x >= n.z ? 0 : n.y >= n.z ? 1 : 2;
        const Key key{std::int64_t(std::floor(x.position.x / cell_)), std::int64_t(std::floor(x.position.y / cell_)),
                      std::int64_t(std::floor(x.position.z / cell_)), 2 * axis + (x.normal[axis] < 0.0 ? 1 : 0)};
        const auto [at, opened] = groups_.try_emplace(key, Group{p, {}});
        if (!opened)
            at->second.members.push_back(p);
        return opened;
    }

    /// A block per group with members: four corners its first point, each member copying it.
    void addBlocks(LowResolutionPlan& plan) const
    {
        for (const auto& [key, group] : groups_) {
            if (group.members.empty())
                continue;
            LowResolutionPlan::Block block;
            block.corners.fill(group.first);
            block.first = std::uint32_t(plan.fine.size());
            for (const std::uint32_t p : group.members)
                plan.fine.push_back({p, {1.0f, 0.0f, 0.0f, 0.0f}});
            block.count = std::uint32_t(group.members.size());
            plan.blocks.push_back(block);
        }
    }

private:
    using Key = std::array<std::int64_t, 4>;
    struct Group {
        std::uint32_t first;
        std::vector<std::uint32_t> members;
    };
    std::span<const ShadingPoint> points_;
    double cell_;
    std::map<Key, Group> groups_;
};

} // namespace

LowResolutionPlan lowResolutionPlan(const AoTexelLayout& layout, const std::vector<std::size_t>& pointOfTexel, int stride,
                                    std::span<const ShadingPoint> points)
{
    if (stride < 2)
        throw Error("the low-resolution pass needs a stride of at least 2 texels, got " + std::to_string(stride));
    LowResolutionPlan plan;
    plan.points = std::size_t(std::count_if(pointOfTexel.begin(), pointOfTexel.end(), [](std::size_t p) { return p != SIZE_MAX; }));
    const auto pointAt = [&](const AoTexelTile& tile, int s, int t) {
        return pointOfTexel[tile.firstPoint + std::size_t(t) * std::size_t(tile.width) + std::size_t(s)];
    };
    std::optional<SmallTileGroups> groups;
    if (!points.empty()) {
        if (points.size() != plan.points || !(layout.density > 0.0))
            throw Error("the low-resolution plan's points number " + std::to_string(points.size()) + " for " +
                        std::to_string(plan.points) + " texels");
        groups.emplace(points, double(stride) / layout.density);
    }
    for (const AoTexelTile& tile : layout.tiles) {
        if (tile.width == 0 || tile.height == 0)
            continue;
        const std::vector<int> columns = coarseLines(tile.width, stride), rows = coarseLines(tile.height, stride);
        const bool small = columns.size() < 2 || rows.size() < 2 || (tile.width <= stride && tile.height <= stride);
        if (small) {   // grouped in space, or else every texel exact
            for (int t = 0; t < tile.height; ++t)
                for (int s = 0; s < tile.width; ++s)
                    if (const std::size_t p = pointAt(tile, s, t); p != SIZE_MAX && (!groups || groups->add(std::uint32_t(p))))
                        plan.coarse.push_back(std::uint32_t(p));
            continue;
        }
        for (const int t : rows)
            for (const int s : columns)
                if (const std::size_t p = pointAt(tile, s, t); p != SIZE_MAX)
                    plan.coarse.push_back(std::uint32_t(p));
        // Each texel off the coarse grid in the block of its intervals.
        const std::size_t blocksAcross = columns.size() - 1;
        std::vector<std::vector<std::uint32_t>> members(blocksAcross * (rows.size() - 1));
        for (int t = 0; t < tile.height; ++t) {
            const bool onRow = std::binary_search(rows.begin(), rows.end(), t);
            for (int s = 0; s < tile.width; ++s) {
                const std::size_t p = pointAt(tile, s, t);
                if (p == SIZE_MAX || (onRow && std::binary_search(columns.begin(), columns.end(), s)))
                    continue;
                members[intervalOf(rows, t) * blocksAcross + intervalOf(columns, s)].push_back(std::uint32_t(p));
            }
        }
        for (std::size_t j = 0; j + 1 < rows.size(); ++j)
            for (std::size_t i = 0; i < blocksAcross; ++i) {
                std::vector<std::uint32_t>& inside = members[j * blocksAcross + i];
                if (inside.empty())
                    continue;
                const int s0 = columns[i], s1 = columns[i + 1], t0 = rows[j], t1 = rows[j + 1];
                const std::array<std::size_t, 4> corners = {pointAt(tile, s0, t0), pointAt(tile, s1, t0), pointAt(tile, s0, t1),
                                                            pointAt(tile, s1, t1)};
                if (std::find(corners.begin(), corners.end(), SIZE_MAX) != corners.end()) {
                    plan.coarse.insert(plan.coarse.end(), inside.begin(), inside.end());   // no four corners: exact
                    continue;
                }
                LowResolutionPlan::Block block;
                for (int c = 0; c < 4; ++c)
                    block.corners[std::size_t(c)] = std::uint32_t(corners[std::size_t(c)]);
                block.first = std::uint32_t(plan.fine.size());
                // The members were collected row by row, so their texel coordinates come back the same way.
                std::size_t k = 0;
                for (int t = t0; t <= t1; ++t)
                    for (int s = s0; s <= s1; ++s) {
                        if (k == inside.size() || pointAt(tile, s, t) != inside[k])
                            continue;
                        const float fs = float(s - s0) / float(s1 - s0), ft = float(t - t0) / float(t1 - t0);
                        plan.fine.push_back({inside[k], {(1 - fs) * (1 - ft), fs * (1 - ft), (1 - fs) * ft, fs * ft}});
                        ++k;
                    }
                block.count = std::uint32_t(plan.fine.size()) - block.first;
                plan.blocks.push_back(block);
            }
    }
    if (groups)
        groups->addBlocks(plan);
    return plan;
}

} // namespace sightline
