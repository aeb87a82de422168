#include "visibility/suggest/DistanceGrid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "base/Error.h"

namespace sightline::suggest {

namespace {

constexpr float kFar = 1e20f;

/// Felzenszwalb & Huttenlocher's 1D squared distance transform of `f` (n samples) into `d`.
void transform1d(const float* f, float* d, int n, std::vector<int>& v, std::vector<float>& z)
{
    v.assign(std::size_t(n), 0);
    z.assign(std::size_t(n) + 1, 0.0f);
    const auto meet = [&](int q, int p) {   // where the parabolas rooted at q and p cross
        return ((f[q] + float(q) * float(q)) - (f[p] + float(p) * float(p))) / (2.0f * float(q - p));
    };
    int k = 0;
    v[0] = 0;
    z[0] = -std::numeric_limits<float>::infinity();
    z[1] = std::numeric_limits<float>::infinity();
    for (int q = 1; q < n; ++q) {
        float s = meet(q, v[std::size_t(k)]);
        while (s <= z[std::size_t(k)]) {   // z[0] is -inf: stops at k = 0
            --k;
            s = meet(q, v[std::size_t(k)]);
        }
        ++k;
        v[std::size_t(k)] = q;
        z[std::size_t(k)] = s;
        z[std::size_t(k) + 1] = std::numeric_limits<float>::infinity();
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
        while (z[std::size_t(k) + 1] < float(q))
            ++k;
        const int p = v[std::size_t(k)];
        d[q] = float(q - p) * float(q - p) + f[p];
    }
}

/// Sutherland-Hodgman against the box's six faces.
std::vector<glm::dvec3> clippedToBox(std::vector<glm::dvec3> polygon, glm::dvec3 lo, glm::dvec3 hi)
{
    for (int axis = 0; axis < 3; ++axis)
        for (const int side : {-1, 1}) {
            const double bound = side < 0 ? lo[axis] : hi[axis];
            std::vector<glm::dvec3> out;
            for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
                const glm::dvec3 a = polygon[i], b = polygon[(i + 1) % n];
                const double fa = side * (a[axis] - bound), fb = side * (b[axis] - bound);
                if (fa <= 0.0)
                    out.push_back(a);
                if ((fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0))
                    out.push_back(a + (b - a) * (fa / (fa - fb)));
            }
            polygon = std::move(out);
            if (polygon.empty())
                return polygon;
        }
    return polygon;
}

} // namespace

DistanceGrid::DistanceGrid(const WorldTriangles& triangles, glm::dvec3 lo, glm::dvec3 hi, double voxel, int maxCells)
{
    const glm::dvec3 size = hi - lo;
    const auto finite = [](glm::dvec3 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); };
    if (!finite(lo) || !finite(hi) || !(size.x > 0 && size.y > 0 && size.z > 0))
        throw Error("distance grid: the box is empty or not finite");
    voxel_ = std::max(voxel, std::max({size.x, size.y, size.z}) / double(maxCells));
    lo_ = lo;
    cells_ = glm::max(glm::ivec3(glm::ceil(size / voxel_)), glm::ivec3(1));
    squared_.assign(std::size_t(cells_.x) * cells_.y * cells_.z, kFar);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::dvec3 a(triangles.vertices[3 * t]), b(triangles.vertices[3 * t + 1]), c(triangles.vertices[3 * t + 2]);
        const glm::dvec3 tlo = glm::min(a, glm::min(b, c)), thi = glm::max(a, glm::max(b, c));
        if (glm::any(glm::lessThan(thi, lo)) || glm::any(glm::greaterThan(tlo, hi)))
            continue;
        const std::vector<glm::dvec3> inside = clippedToBox({a, b, c}, lo, hi);
        for (std::size_t k = 1; k + 1 < inside.size(); ++k)
            mark(inside[0], inside[k], inside[k + 1]);
    }
    transform();
}

glm::ivec3 DistanceGrid::cellOf(glm::dvec3 p) const
{
    return glm::clamp(glm::ivec3(glm::floor((p - lo_) / voxel_)), glm::ivec3(0), cells_ - 1);
}

void DistanceGrid::mark(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    // Samples at under half a voxel along both edges from a: every voxel the triangle crosses
    // holds one.
    const double step = 0.45 * voxel_;
    const int nb = std::max(1, int(std::ceil(glm::length(b - a) / step)));
    const int nc = std::max(1, int(std::ceil(glm::length(c - a) / step)));
    const int n = std::max(nb, nc);
    for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
            const glm::dvec3 p = a + (double(i) / n) * (b - a) + (double(j) / n) * (c - a);
            squared_[index(cellOf(p))] = 0.0f;
        }
}

void DistanceGrid::transform()
{
    std::vector<int> v;
    std::vector<float> z, f, d;
    const glm::ivec3 n = cells_;
    auto pass = [&](int axis) {
        const int length = n[axis];
        f.resize(std::size_t(length));
        d.resize(std::size_t(length));
        const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        for (int u = 0; u < n[a1]; ++u)
            for (int w = 0; w < n[a2]; ++w) {
                glm::ivec3 c(0);
                c[a1] = u;
                c[a2] = w;
                for (int q = 0; q < length; ++q) {
                    c[axis] = q;
                    f[std::size_t(q)] = squared_[index(c)];
                }
                transform1d(f.data(), d.data(), length, v, z);
                for (int q = 0; q < length; ++q) {
                    c[axis] = q;
                    squared_[index(c)] = d[std::size_t(q)];
                }
            }
    };
    for (int axis = 0; axis < 3; ++axis)
        pass(axis);
    for (float& s : squared_)
        s = s >= 0.5f * kFar ? std::numeric_limits<float>::infinity() : float(std::sqrt(double(s)) * voxel_);
}

double DistanceGrid::distance(glm::dvec3 p) const
{
    return double(squared_[index(cellOf(p))]);
}

} // namespace sightline::suggest
