#include "lighting/LightTree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace sightline {

namespace {

/// A number in [0, 1) from a node and the seed (splitmix64's finaliser).
double unitHash(std::uint64_t node, std::uint64_t seed)
{
    std::uint64_t z = node * 0x9E3779B97F4A7C15ull + seed;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return double(z >> 11) * 0x1.0p-53;
}

/// The squared distance between two boxes (0 where they overlap).
double boxDistance2(const glm::dvec3& alo, const glm::dvec3& ahi, const glm::dvec3& blo, const glm::dvec3& bhi)
{
    const glm::dvec3 gap = glm::max(glm::max(alo - bhi, blo - ahi), glm::dvec3(0.0));
    return glm::dot(gap, gap);
}

} // namespace

LightTree::LightTree(const std::vector<Light>& lights, std::uint64_t seed) : lights_(lights), inTree_(lights.size(), false)
{
    for (std::size_t l = 0; l < lights.size(); ++l)
        if (lights[l].type == LightType::Point) {
            inTree_[l] = true;
            order_.push_back(std::uint32_t(l));
        }
    if (!order_.empty()) {
        nodes_.reserve(2 * order_.size());
        build(0, std::uint32_t(order_.size()), seed);
    }
}

std::int32_t LightTree::build(std::uint32_t first, std::uint32_t count, std::uint64_t seed)
{
    const std::int32_t index = std::int32_t(nodes_.size());
    nodes_.emplace_back();
    Node node;
    node.first = first, node.count = count;
    node.lo = node.hi = lights_[order_[first]].position;
    for (std::uint32_t k = first; k < first + count; ++k) {
        const Light& light = lights_[order_[k]];
        node.lo = glm::min(node.lo, light.position), node.hi = glm::max(node.hi, light.position);
        node.colourSum += light.intensity * light.colour;
        node.weight += light.intensity * std::max({light.colour.r, light.colour.g, light.colour.b});
        node.range = std::max(node.range, light.range > 0.0 ? light.range : std::numeric_limits<double>::infinity());
    }
    if (count == 1) {
        node.representative = order_[first];
        nodes_[std::size_t(index)] = node;
        return index;
    }
    const glm::dvec3 extent = node.hi - node.lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const std::uint32_t half = count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                     [&](std::uint32_t a, std::uint32_t b) { return lights_[a].position[axis] < lights_[b].position[axis]; });
    node.left = build(first, half, seed);
    node.right = build(first + half, count - half, seed);
    const Node& left = nodes_[std::size_t(node.left)];
    const Node& right = nodes_[std::size_t(node.right)];
    const double total = left.weight + right.weight;
    const bool takeLeft = total > 0.0 ? unitHash(std::uint64_t(index), seed) * total < left.weight : true;
    node.representative = takeLeft ? left.representative : right.representative;
    nodes_[std::size_t(index)] = node;
    return index;
}

LightTree::Entry LightTree::entryOf(const Node& node) const
{
    Entry entry;
    entry.representative = node.representative;
    entry.count = node.count;
    entry.standIn = lights_[node.representative];
    if (node.count > 1) {
        // term x colour = intensity_r G_r x colourSum / intensity_r = G_r x colourSum.
        const double intensity = entry.standIn.intensity;
        entry.standIn.colour = intensity > 0.0 ? node.colourSum / intensity : glm::dvec3(0.0);
        entry.standIn.range = std::isfinite(node.range) ? node.range : 0.0;
    }
    return entry;
}

void LightTree::cut(const glm::dvec3& lo, const glm::dvec3& hi, double error, std::size_t maxEntries, std::vector<Entry>& out) const
{
    out.clear();
    if (nodes_.empty())
        return;
    const glm::dvec3 centre = 0.5 * (lo + hi);
    // A node's bound on what it gives any point of the box, and its estimate at the box's centre.
    const auto bound = [&](const Node& node) {
        const double d2 = boxDistance2(node.lo, node.hi, lo, hi);
        if (d2 >= node.range * node.range)
            return 0.0;
        return d2 > 0.0 ? node.weight / d2 : std::numeric_limits<double>::infinity();
    };
    const auto estimate = [&](const Node& node) {
        const glm::dvec3 to = lights_[node.representative].position - centre;
        const double d2 = std::max(glm::dot(to, to), 1e-4);
        return d2 >= node.range * node.range ? 0.0 : node.weight / d2;
    };
    using Item = std::pair<double, std::int32_t>;   // (bound, node)
    std::priority_queue<Item> open;
    std::vector<std::int32_t> leaves;
    double total = 0.0;
    const auto add = [&](std::int32_t index) {
        const Node& node = nodes_[std::size_t(index)];
        const double b = bound(node);
        if (b == 0.0)
            return;   // beyond every range of its lights
        total += estimate(node);
        if (node.count == 1)
            leaves.push_back(index);
        else
            open.push({b, index});
    };
    add(0);
    while (!open.empty() && open.top().first > error * total && leaves.size() + open.size() < maxEntries) {
        const std::int32_t index = open.top().second;
        open.pop();
        const Node& node = nodes_[std::size_t(index)];
        total -= estimate(node);
        add(node.left);
        add(node.right);
    }
    for (const std::int32_t index : leaves)
        out.push_back(entryOf(nodes_[std::size_t(index)]));
    for (; !open.empty(); open.pop())
        out.push_back(entryOf(nodes_[std::size_t(open.top().second)]));
}

} // namespace sightline
