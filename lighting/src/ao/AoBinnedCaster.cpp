#include "lighting/ao/AoBinnedCaster.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace sightline {

namespace {

struct Scratch {
    std::vector<float> px, py, pz;
    std::vector<std::uint32_t> facing, pointCell;
    std::vector<std::uint32_t> cellStart, cellFill;
    /// Facing points in cell order: projected origin (plane coordinates, depth along the direction).
    std::vector<float> bx, by, bz;
    std::vector<float> bside;   ///< +1: facing d, -1: facing -d
    std::vector<std::uint32_t> bindex;   ///< point index, top bit set when facing -d
    std::vector<std::int32_t> bblocked;
};

/// Eight lanes (GCC/Clang vector extensions: AVX registers in the AVX2 clone, two SSE halves
/// otherwise).
using V8 = float __attribute__((vector_size(32)));
using M8 = std::int32_t __attribute__((vector_size(32)));
constexpr std::size_t kLanes = 8;

// Vectors are passed only between functions inlined into testTriangles' clones, so GCC's note
// that an AVX vector return changes the ABI without AVX enabled does not apply (-Wpsabi, until
// the end of testTriangles).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
[[gnu::always_inline]] inline V8 load(const float* p)
{
    V8 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

/// Every triangle against the binned points of the cells its projected bounding box overlaps
/// (AoBinnedCaster.h): on x86-64 with GCC also compiled for AVX2, chosen at run time
/// (target_clones: eight lanes of the edge functions instead of four). FMA is not enabled: the exact negation of a shared
/// edge's function (file comment) needs the same rounding in both triangles, which it keeps, but
/// there is no gain worth the doubt.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void testTriangles(Scratch& s, const std::uint32_t* indices, std::size_t nt, int g, float lo, float scale, float reach)
{
    auto cellOf = [&](float x) { return std::clamp(int((x - lo) * scale), 0, g - 1); };
        for (std::size_t t = 0; t < nt; ++t) {
            const std::uint32_t i0 = indices[3 * t], i1 = indices[3 * t + 1], i2 = indices[3 * t + 2];
            const float x[3] = {s.px[i0], s.px[i1], s.px[i2]}, y[3] = {s.py[i0], s.py[i1], s.py[i2]};
            const float z[3] = {s.pz[i0], s.pz[i1], s.pz[i2]};
            const float area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
            if (!(area != 0.0f))   // seen edge-on (or NaN): blocks no ray but ties
                continue;
            const float sign = area > 0.0f ? 1.0f : -1.0f;
            float ea[3], eb[3], ec[3];
            for (int e = 0; e < 3; ++e) {
                // Edge e runs from corner e+1 to corner e+2 (opposite corner e). The coefficients
                // are exactly negated for the same edge traversed the other way (file comment).
                const int p0 = e == 2 ? 0 : e + 1, p1 = e == 0 ? 2 : e == 1 ? 0 : 1;
                ea[e] = sign * (y[p0] - y[p1]);
                eb[e] = sign * (x[p1] - x[p0]);
                ec[e] = sign * (x[p0] * y[p1] - x[p1] * y[p0]);
            }
            const int cx0 = cellOf(std::min({x[0], x[1], x[2]})), cx1 = cellOf(std::max({x[0], x[1], x[2]}));
            const int cy0 = cellOf(std::min({y[0], y[1], y[2]})), cy1 = cellOf(std::max({y[0], y[1], y[2]}));
            // The points of each row of cells, eight at a time: a row holds only a few points (about
            // 20 in a triangle's box over 2 or 3 rows), so a loop with a scalar tail ran mostly
            // scalar. A block may run past the row into the next cells' points (the arrays are
            // padded with NaN points, never inside): testing a point the triangle's box does not
            // cover changes nothing, since the test is exact per point and a point inside the
            // triangle lies in its box's cells anyway.
            const V8 a0 = V8{} + ea[0], b0 = V8{} + eb[0], c0 = V8{} + ec[0];
            const V8 a1 = V8{} + ea[1], b1 = V8{} + eb[1], c1 = V8{} + ec[1];
            const V8 a2 = V8{} + ea[2], b2 = V8{} + eb[2], c2 = V8{} + ec[2];
            const V8 z0 = V8{} + z[0], z1 = V8{} + z[1], z2 = V8{} + z[2], zero{}, far = V8{} + reach;
            for (int cy = cy0; cy <= cy1; ++cy) {
                const std::size_t row = std::size_t(cy) * std::size_t(g);
                const std::uint32_t begin = s.cellStart[row + std::size_t(cx0)], end = s.cellStart[row + std::size_t(cx1) + 1];
                for (std::uint32_t k = begin; k < end; k += 8) {
                    const V8 px = load(s.bx.data() + k), py = load(s.by.data() + k), pz = load(s.bz.data() + k);
                    const V8 e0 = a0 * px + b0 * py + c0;
                    const V8 e1 = a1 * px + b1 * py + c1;
                    const V8 e2 = a2 * px + b2 * py + c2;
                    const M8 inside = (e0 >= zero) & (e1 >= zero) & (e2 >= zero);
                    // The triangle's depth at the point, along the point's direction, beyond its origin.
                    const V8 depth = load(s.bside.data() + k) * (e0 * z0 + e1 * z1 + e2 * z2), sum = e0 + e1 + e2;
                    const M8 above = depth > pz * sum;
                    // Within reach (AoBinnedOptions::maxDistance; infinite: always). sum > 0 inside.
                    const M8 near = depth < (pz + far) * sum;
                    M8 blocked;
                    std::memcpy(&blocked, s.bblocked.data() + k, sizeof blocked);
                    blocked |= inside & above & near;
                    std::memcpy(s.bblocked.data() + k, &blocked, sizeof blocked);
                }
            }
        }
}
#pragma GCC diagnostic pop

void basisOf(const glm::vec3& d, glm::vec3& u, glm::vec3& v)
{
    const glm::vec3 helper = std::abs(d.x) < 0.6f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    u = glm::normalize(glm::cross(helper, d));
    v = glm::cross(d, u);
}

} // namespace

struct AoBinnedCaster::Impl {
    AoBinnedOptions options;
    glm::dvec3 centre{0.0};
    float radius = 0.0f;
    std::vector<glm::vec3> vertices;   ///< relative to centre
    std::vector<std::uint32_t> indices;
    tbb::enumerable_thread_specific<Scratch> scratch;

    /// Visible bits of direction d over all points into `out` (one bit per point). The facing
    /// points are binned by their projected origin; each triangle then tests the points of the
    /// cells its projected bounding box overlaps (no per-triangle records are stored, and a point
    /// already blocked is skipped).
    ///
    /// Antipodal directions d and -d share the plane, the projection and the triangles' edge
    /// functions: with `outOpposite`, the points facing -d are binned too (depth sign flipped) and
    /// both directions are answered by one pass over the triangles.
    void direction(const glm::vec3& d, const AoPoints& points, const std::vector<glm::vec3>& origins, std::uint64_t* out,
                   std::uint64_t* outOpposite)
    {
        Scratch& s = scratch.local();
        glm::vec3 u, v;
        basisOf(d, u, v);
        const std::size_t nv = vertices.size();
        s.px.resize(nv);
        s.py.resize(nv);
        s.pz.resize(nv);
        for (std::size_t i = 0; i < nv; ++i) {
            const glm::vec3 p = vertices[i];
            s.px[i] = u.x * p.x + u.y * p.y + u.z * p.z;
            s.py[i] = v.x * p.x + v.y * p.y + v.z * p.z;
            s.pz[i] = d.x * p.x + d.y * p.y + d.z * p.z;
        }
        const std::size_t nt = indices.size() / 3;
        const int g = std::max(1, int(std::sqrt(double(nt) * options.cellsPerTriangle)));
        const float lo = -radius, scale = float(g) / (2.0f * radius > 0 ? 2.0f * radius : 1.0f);
        auto cellOf = [&](float x) { return std::clamp(int((x - lo) * scale), 0, g - 1); };

        // Bin the facing points (counting sort by cell).
        const std::size_t np = points.size();
        s.cellStart.assign(std::size_t(g) * std::size_t(g) + 1, 0);
        s.pointCell.clear();
        s.facing.clear();
        for (std::size_t i = 0; i < np; ++i) {
            const glm::vec3 n = points.normals[i];
            const float c = n.x * d.x + n.y * d.y + n.z * d.z;
            // Facing directions only (zero normals face none).
            if (!(c > 0.0f || (outOpposite && c < 0.0f)))
                continue;
            const glm::vec3 o = origins[i];
            const float qx = u.x * o.x + u.y * o.y + u.z * o.z, qy = v.x * o.x + v.y * o.y + v.z * o.z;
            const auto cell = std::uint32_t(std::size_t(cellOf(qy)) * std::size_t(g) + std::size_t(cellOf(qx)));
            s.facing.push_back(c > 0.0f ? std::uint32_t(i) : std::uint32_t(i) | 0x80000000u);
            s.pointCell.push_back(cell);
            ++s.cellStart[cell + 1];
        }
        for (std::size_t c = 1; c < s.cellStart.size(); ++c)
            s.cellStart[c] += s.cellStart[c - 1];
        // Padded by a block of NaN points (never inside a triangle) for the eight-lane loop.
        const std::size_t nf = s.facing.size();
        const float nan = std::numeric_limits<float>::quiet_NaN();
        s.bx.assign(nf + kLanes, nan);
        s.by.assign(nf + kLanes, nan);
        s.bz.assign(nf + kLanes, nan);
        s.bside.assign(nf + kLanes, 1.0f);
        s.bblocked.assign(nf + kLanes, 0);
        s.bindex.resize(nf);
        s.cellFill.assign(s.cellStart.begin(), s.cellStart.end() - 1);
        for (std::size_t f = 0; f < s.facing.size(); ++f) {
            const std::uint32_t i = s.facing[f] & 0x7fffffffu;
            const float side = s.facing[f] & 0x80000000u ? -1.0f : 1.0f;
            const glm::vec3 o = origins[i];
            const std::uint32_t k = s.cellFill[s.pointCell[f]]++;
            s.bx[k] = u.x * o.x + u.y * o.y + u.z * o.z;
            s.by[k] = v.x * o.x + v.y * o.y + v.z * o.z;
            s.bz[k] = side * (d.x * o.x + d.y * o.y + d.z * o.z);   // depth along the point's own direction
            s.bside[k] = side;
            s.bindex[k] = s.facing[f];
            s.bblocked[k] = 0;
        }

        testTriangles(s, indices.data(), nt, g, lo, scale, float(options.maxDistance));
        for (std::size_t k = 0; k < nf; ++k)
            if (!s.bblocked[k]) {
                const std::uint32_t i = s.bindex[k] & 0x7fffffffu;
                (s.bindex[k] & 0x80000000u ? outOpposite : out)[i >> 6] |= std::uint64_t(1) << (i & 63);
            }
    }
};

AoBinnedCaster::AoBinnedCaster(const AoOccluders& occluders, AoBinnedOptions options) : impl_(std::make_unique<Impl>())
{
    impl_->options = options;
    if (!occluders.bounds.empty())
        impl_->centre = (glm::dvec3(occluders.bounds.min) + glm::dvec3(occluders.bounds.max)) * 0.5;
    double radius = 0.0;
    for (const glm::vec3& p : occluders.vertices) {
        const glm::dvec3 r = glm::dvec3(p) - impl_->centre;
        impl_->vertices.push_back(glm::vec3(r));
        radius = std::max(radius, glm::length(r));
    }
    impl_->radius = float(radius * 1.0001 + 1e-6);
    // Triangles in Morton order of their centroids, vertices renumbered by first use: consecutive
    // triangles then touch neighbouring grid cells and points in every projection (cache locality).
    const std::size_t nt = occluders.triangleCount();
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(nt);
    auto spread = [](std::uint64_t x) {   // 21 bits -> every third bit
        x &= 0x1fffff;
        x = (x | x << 32) & 0x1f00000000ffffull;
        x = (x | x << 16) & 0x1f0000ff0000ffull;
        x = (x | x << 8) & 0x100f00f00f00f00full;
        x = (x | x << 4) & 0x10c30c30c30c30c3ull;
        x = (x | x << 2) & 0x1249249249249249ull;
        return x;
    };
    for (std::uint32_t t = 0; t < nt; ++t) {
        glm::vec3 c(0.0f);
        for (int k = 0; k < 3; ++k)
            c += impl_->vertices[occluders.indices[3 * std::size_t(t) + std::size_t(k)]];
        const glm::vec3 q = glm::clamp((c / 3.0f / impl_->radius + 1.0f) * 0.5f, 0.0f, 1.0f) * 2097151.0f;
        order[t] = {spread(std::uint64_t(q.x)) | spread(std::uint64_t(q.y)) << 1 | spread(std::uint64_t(q.z)) << 2, t};
    }
    std::sort(order.begin(), order.end());
    std::vector<std::uint32_t> renumber(impl_->vertices.size(), ~0u);
    std::vector<glm::vec3> vertices;
    impl_->indices.reserve(3 * nt);
    for (const auto& [code, t] : order)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = occluders.indices[3 * std::size_t(t) + std::size_t(k)];
            if (renumber[v] == ~0u) {
                renumber[v] = std::uint32_t(vertices.size());
                vertices.push_back(impl_->vertices[v]);
            }
            impl_->indices.push_back(renumber[v]);
        }
    impl_->vertices = std::move(vertices);
}

AoBinnedCaster::~AoBinnedCaster() = default;

bool AoBinnedCaster::fill(const AoPoints& points, const AoDirectionSet& set, int first, int last, VisibilityMatrix& matrix,
                          const AoFillControl& control)
{
    if (first >= last)
        return true;
    const std::size_t np = points.size(), pointWords = (np + 63) / 64;
    std::vector<glm::vec3> origins(np);
    for (std::size_t i = 0; i < np; ++i)
        origins[i] = glm::vec3(glm::dvec3(points.origins[i]) - impl_->centre);
    std::vector<std::uint64_t> rows(std::size_t(last - first) * pointWords, 0);
    std::atomic<bool> stopped{false};
    tbb::task_arena arena(impl_->options.threads > 0 ? impl_->options.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(first, last, 1), [&](const tbb::blocked_range<int>& r) {
            for (int j = r.begin(); j < r.end(); ++j) {
                if (control.cancelled()) {
                    stopped = true;
                    return;
                }
                const int a = set.antipode[std::size_t(j)];
                const bool pair = a >= first && a < last;
                if (pair && a < j)
                    continue;   // answered with its antipode
                impl_->direction(set.directions[std::size_t(j)], points, origins, rows.data() + std::size_t(j - first) * pointWords,
                                 pair ? rows.data() + std::size_t(a - first) * pointWords : nullptr);
                control.finishedOne();
                if (pair)
                    control.finishedOne();
            }
        });
        // Transpose: each task owns 64 points' rows.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pointWords, 16), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t w = r.begin(); w < r.end(); ++w)
                for (int j = first; j < last; ++j) {
                    std::uint64_t bits = rows[std::size_t(j - first) * pointWords + w];
                    while (bits) {
                        const int b = std::countr_zero(bits);
                        bits &= bits - 1;
                        matrix.setVisible(w * 64 + std::size_t(b), j);
                    }
                }
        });
    });
    return !stopped;
}

} // namespace sightline
