#include "lights/TriangleBoxTree.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <glm/common.hpp>

namespace sightline::lights {

namespace {

constexpr std::uint32_t kLeafTriangles = 4;

bool overlaps(const glm::vec3& lo, const glm::vec3& hi, const glm::dvec3& qlo, const glm::dvec3& qhi)
{
    return double(lo.x) <= qhi.x && double(hi.x) >= qlo.x && double(lo.y) <= qhi.y && double(hi.y) >= qlo.y &&
           double(lo.z) <= qhi.z && double(hi.z) >= qlo.z;
}

} // namespace

TriangleBoxTree::TriangleBoxTree(const WorldTriangles& triangles) : triangles_(triangles), order_(triangles.size())
{
    std::iota(order_.begin(), order_.end(), 0u);
    if (order_.empty())
        return;
    std::vector<glm::vec3> centres(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
        centres[t] = (triangles.vertices[3 * t] + triangles.vertices[3 * t + 1] + triangles.vertices[3 * t + 2]) / 3.0f;
    nodes_.reserve(2 * triangles.size() / kLeafTriangles + 2);
    nodes_.emplace_back();
    build(0, 0, std::uint32_t(order_.size()), centres);
}

void TriangleBoxTree::build(std::uint32_t index, std::uint32_t first, std::uint32_t count, const std::vector<glm::vec3>& centres)
{
    glm::vec3 lo(INFINITY), hi(-INFINITY), clo(INFINITY), chi(-INFINITY);
    for (std::uint32_t k = first; k < first + count; ++k) {
        const std::size_t t = order_[k];
        for (int c = 0; c < 3; ++c)
            lo = glm::min(lo, triangles_.vertices[3 * t + std::size_t(c)]), hi = glm::max(hi, triangles_.vertices[3 * t + std::size_t(c)]);
        clo = glm::min(clo, centres[t]), chi = glm::max(chi, centres[t]);
    }
    nodes_[index].lo = lo, nodes_[index].hi = hi;
    if (count <= kLeafTriangles) {
        nodes_[index].first = first, nodes_[index].count = count;
        return;
    }
    const glm::vec3 extent = chi - clo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const std::uint32_t mid = first + count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + first + count,
                     [&](std::uint32_t a, std::uint32_t b) { return centres[a][axis] < centres[b][axis]; });
    const std::uint32_t left = std::uint32_t(nodes_.size());
    nodes_.emplace_back();
    nodes_.emplace_back();
    nodes_[index].first = left, nodes_[index].count = 0;
    build(left, first, mid - first, centres);
    build(left + 1, mid, first + count - mid, centres);
}

bool TriangleBoxTree::anyInside(const ShaftHull& hull, const glm::dvec3& lo, const glm::dvec3& hi) const
{
    if (nodes_.empty())
        return false;
    std::uint32_t stack[64];
    int depth = 0;
    stack[depth++] = 0;
    while (depth > 0) {
        const Node& node = nodes_[stack[--depth]];
        if (!overlaps(node.lo, node.hi, lo, hi) || hull.excludesBox(node.lo, node.hi))
            continue;
        if (node.count == 0) {
            stack[depth++] = node.first;
            stack[depth++] = node.first + 1;
            continue;
        }
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
            const std::size_t t = order_[k];
            const glm::vec3& a = triangles_.vertices[3 * t];
            const glm::vec3& b = triangles_.vertices[3 * t + 1];
            const glm::vec3& c = triangles_.vertices[3 * t + 2];
            if (overlaps(glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c)), lo, hi) && !hull.excludes(a, b, c))
                return true;
        }
    }
    return false;
}

} // namespace sightline::lights
