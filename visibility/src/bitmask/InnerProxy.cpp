#include "InnerProxy.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string_view>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "../raycast/RayPackets.h"

namespace sightline::bitmask {

namespace {

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

/// Distance from p to segment ab in the plane.
double segmentDistance(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b)
{
    const glm::dvec2 ab = b - a, ap = p - a;
    const double length2 = glm::dot(ab, ab);
    const double t = length2 > 0.0 ? std::clamp(glm::dot(ap, ab) / length2, 0.0, 1.0) : 0.0;
    return glm::length(ap - t * ab);
}

/// Where the line {(x, p.x, p.y)} crosses the triangle, as its x; false when it misses. Sets
/// `unsure` when the line passes within kColumnClearanceMetres of an edge (the count could round
/// either way there).
bool columnCrossing(const glm::dvec2& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double& x,
                    bool& unsure)
{
    const glm::dvec2 A(a.y, a.z), B(b.y, b.z), C(c.y, c.z);
    const glm::dvec2 lo = glm::min(A, glm::min(B, C)) - kColumnClearanceMetres;
    const glm::dvec2 hi = glm::max(A, glm::max(B, C)) + kColumnClearanceMetres;
    if (p.x < lo.x || p.y < lo.y || p.x > hi.x || p.y > hi.y)
        return false;
    if (segmentDistance(p, A, B) < kColumnClearanceMetres || segmentDistance(p, B, C) < kColumnClearanceMetres ||
        segmentDistance(p, C, A) < kColumnClearanceMetres) {
        unsure = true;
        return false;
    }
    const double e0 = cross2(B - A, p - A), e1 = cross2(C - B, p - B), e2 = cross2(A - C, p - C);
    if (!((e0 > 0.0 && e1 > 0.0 && e2 > 0.0) || (e0 < 0.0 && e1 < 0.0 && e2 < 0.0)))
        return false;
    // Clear of every edge and inside: the projection has area, so the plane is not parallel to x.
    const glm::dvec3 n = glm::cross(b - a, c - a);
    x = a.x - (n.y * (p.x - a.y) + n.z * (p.y - a.z)) / n.x;
    return true;
}

/// `v` rounded to float toward `toward` (never past v away from it).
float roundToward(double v, double toward)
{
    float f = float(v);
    if (toward > v && double(f) < v)
        f = std::nextafter(f, std::numeric_limits<float>::infinity());
    if (toward < v && double(f) > v)
        f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}

/// The voxels of innerProxyTriangles: cubes of side h from lo, nx x ny x nz of them.
struct VoxelGrid {
    glm::dvec3 lo;
    double h = 0.0;
    int nx = 0, ny = 0, nz = 0;

    /// Index of voxel (x, y, z), x fastest.
    std::size_t at(int x, int y, int z) const
    {
        return (std::size_t(z) * std::size_t(ny) + std::size_t(y)) * std::size_t(nx) + std::size_t(x);
    }
};

/// Marks in `touched` the voxels some triangle's grown box touches, and lists in `column` (per
/// y, z) the triangles whose grown box reaches each x column.
void touchVoxels(const glm::vec3* vertices, std::size_t triangleCount, const VoxelGrid& grid,
                 std::vector<char>& touched, std::vector<std::vector<std::uint32_t>>& column)
{
    const glm::dvec3& lo = grid.lo;
    const auto cellOf = [&](double v, double origin, int n) { return std::clamp(int(std::floor((v - origin) / grid.h)), 0, n - 1); };
    for (std::size_t t = 0; t < triangleCount; ++t) {
        const glm::dvec3 a(vertices[3 * t]), b(vertices[3 * t + 1]), c(vertices[3 * t + 2]);
        const glm::dvec3 tlo = glm::min(a, glm::min(b, c)) - kInnerMarginMetres;
        const glm::dvec3 thi = glm::max(a, glm::max(b, c)) + kInnerMarginMetres;
        const int x0 = cellOf(tlo.x, lo.x, grid.nx), x1 = cellOf(thi.x, lo.x, grid.nx);
        const int y0 = cellOf(tlo.y, lo.y, grid.ny), y1 = cellOf(thi.y, lo.y, grid.ny);
        const int z0 = cellOf(tlo.z, lo.z, grid.nz), z1 = cellOf(thi.z, lo.z, grid.nz);
        for (int z = z0; z <= z1; ++z)
            for (int y = y0; y <= y1; ++y) {
                column[std::size_t(z) * std::size_t(grid.ny) + std::size_t(y)].push_back(std::uint32_t(t));
                for (int x = x0; x <= x1; ++x)
                    touched[grid.at(x, y, z)] = 1;
            }
    }
}

/// Per voxel, 1 where it is untouched and its centre has parity 1 (counted along its x column,
/// columns that pass too close to an edge left out).
std::vector<char> innerVoxels(const glm::vec3* vertices, const VoxelGrid& grid, const std::vector<char>& touched,
                              const std::vector<std::vector<std::uint32_t>>& column)
{
    const glm::dvec3& lo = grid.lo;
    const double h = grid.h;
    std::vector<char> inside(touched.size(), 0);
    std::vector<double> crossings;
    for (int z = 0; z < grid.nz; ++z)
        for (int y = 0; y < grid.ny; ++y) {
            const glm::dvec2 p(lo.y + (y + 0.5) * h, lo.z + (z + 0.5) * h);
            crossings.clear();
            bool unsure = false;
            for (std::uint32_t t : column[std::size_t(z) * std::size_t(grid.ny) + std::size_t(y)]) {
                double x = 0.0;
                if (columnCrossing(p, glm::dvec3(vertices[3 * t]), glm::dvec3(vertices[3 * t + 1]),
                                   glm::dvec3(vertices[3 * t + 2]), x, unsure))
                    crossings.push_back(x);
                if (unsure)
                    break;
            }
            if (unsure)
                continue;
            std::sort(crossings.begin(), crossings.end());
            for (int x = 0; x < grid.nx; ++x) {
                if (touched[grid.at(x, y, z)])
                    continue;
                // No crossing lies in an untouched voxel, so the centre's side is unambiguous.
                const double centre = lo.x + (x + 0.5) * h;
                const auto above = crossings.end() - std::upper_bound(crossings.begin(), crossings.end(), centre);
                inside[grid.at(x, y, z)] = char(above % 2);
            }
        }
    return inside;
}

/// Merges the faces set in `mask` (nu x nv, cleared as it goes) on the plane `planeF` across
/// `axis` greedily into rectangles (runs, then rows of equal runs), and appends each as two
/// triangles facing `outward` along the axis.
void appendRectangles(const VoxelGrid& grid, int axis, int nu, int nv, float planeF, int outward,
                      std::vector<char>& mask, std::vector<glm::vec3>& triangles)
{
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    const glm::dvec3& lo = grid.lo;
    const double h = grid.h;
    const auto maskAt = [&](int u, int v) -> char& { return mask[std::size_t(v) * std::size_t(nu) + std::size_t(u)]; };
    for (int v = 0; v < nv; ++v)
        for (int u = 0; u < nu; ++u) {
            if (!maskAt(u, v))
                continue;
            int u1 = u;
            while (u1 + 1 < nu && maskAt(u1 + 1, v))
                ++u1;
            int v1 = v;
            const auto runFree = [&](int vv) {
                for (int uu = u; uu <= u1; ++uu)
                    if (!maskAt(uu, vv))
                        return false;
                return true;
            };
            while (v1 + 1 < nv && runFree(v1 + 1))
                ++v1;
            for (int vv = v; vv <= v1; ++vv)
                for (int uu = u; uu <= u1; ++uu)
                    maskAt(uu, vv) = 0;
            // The rectangle, shrunk by the rounding to float.
            const double u0m = lo[ua] + double(u) * h, u1m = lo[ua] + double(u1 + 1) * h;
            const double v0m = lo[va] + double(v) * h, v1m = lo[va] + double(v1 + 1) * h;
            const float uLo = roundToward(u0m, u1m), uHi = roundToward(u1m, u0m);
            const float vLo = roundToward(v0m, v1m), vHi = roundToward(v1m, v0m);
            if (!(uLo < uHi && vLo < vHi))
                continue;
            const auto corner = [&](float cu, float cv) {
                glm::vec3 p;
                p[axis] = planeF, p[ua] = cu, p[va] = cv;
                return p;
            };
            // (ua, va, axis) is right-handed: counter-clockwise in (u, v) faces +axis.
            std::array<glm::vec3, 4> q{corner(uLo, vLo), corner(uHi, vLo), corner(uHi, vHi), corner(uLo, vHi)};
            if (outward < 0)
                std::swap(q[1], q[3]);
            triangles.insert(triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        }
}

/// The union's boundary: per plane between two layers of voxels, the faces with an inner
/// voxel on one side only, merged greedily into rectangles (runs, then rows of equal runs).
std::vector<glm::vec3> boundaryFaces(const VoxelGrid& grid, const std::vector<char>& inside)
{
    std::vector<glm::vec3> triangles;
    const std::array<int, 3> n{grid.nx, grid.ny, grid.nz};
    std::vector<char> mask;
    for (int axis = 0; axis < 3; ++axis) {
        const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
        const int nu = n[std::size_t(ua)], nv = n[std::size_t(va)];
        const auto innerAt = [&](int k, int u, int v) {
            if (k < 0 || k >= n[std::size_t(axis)])
                return false;
            std::array<int, 3> c{};
            c[std::size_t(axis)] = k, c[std::size_t(ua)] = u, c[std::size_t(va)] = v;
            return inside[grid.at(c[0], c[1], c[2])] == 1;
        };
        for (int k = 0; k <= n[std::size_t(axis)]; ++k)
            for (const int outward : {+1, -1}) {
                // outward +1: the inner voxel below the plane (layer k - 1), the outer above.
                mask.assign(std::size_t(nu) * std::size_t(nv), 0);
                for (int v = 0; v < nv; ++v)
                    for (int u = 0; u < nu; ++u) {
                        const bool below = innerAt(k - 1, u, v), above = innerAt(k, u, v);
                        mask[std::size_t(v) * std::size_t(nu) + std::size_t(u)] = outward > 0 ? below && !above : above && !below;
                    }
                // The plane, moved toward the inner side by the rounding to float.
                const double plane = grid.lo[axis] + double(k) * grid.h;
                const float planeF = roundToward(plane, plane - double(outward));
                appendRectangles(grid, axis, nu, nv, planeF, outward, mask, triangles);
            }
    }
    return triangles;
}

} // namespace

std::vector<glm::vec3> innerProxyTriangles(const glm::vec3* vertices, std::size_t triangleCount, int resolution)
{
    if (triangleCount == 0 || resolution < 1)
        return {};
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (std::size_t k = 0; k < 3 * triangleCount; ++k) {
        lo = glm::min(lo, glm::dvec3(vertices[k]));
        hi = glm::max(hi, glm::dvec3(vertices[k]));
    }
    const glm::dvec3 extent = hi - lo;
    const double h = std::max({extent.x, extent.y, extent.z}) / double(resolution);
    if (!(h > 2.0 * kInnerMarginMetres))
        return {};
    const auto cells = [&](double e) { return std::clamp(int(std::ceil(e / h)), 1, resolution); };
    const int nx = cells(extent.x), ny = cells(extent.y), nz = cells(extent.z);
    const VoxelGrid grid{lo, h, nx, ny, nz};

    // Voxels some triangle's grown box touches, and each column's triangles.
    std::vector<char> touched(std::size_t(nx) * std::size_t(ny) * std::size_t(nz), 0);
    std::vector<std::vector<std::uint32_t>> column(std::size_t(ny) * std::size_t(nz));
    touchVoxels(vertices, triangleCount, grid, touched, column);

    // Parity of the untouched voxels, column by column.
    const std::vector<char> inside = innerVoxels(vertices, grid, touched, column);

    return boundaryFaces(grid, inside);
}

std::vector<std::vector<glm::vec3>> boundaryCaps(const glm::vec3* vertices, std::size_t triangleCount)
{
    // Weld equal positions (as closedAndOutward does), then keep the undirected edges an odd
    // number of triangles share.
    const std::size_t n = 3 * triangleCount;
    std::vector<std::uint32_t> first;   // per welded id: a vertex slot holding it
    const std::vector<std::uint32_t> weld = weldPositions(vertices, n, &first);
    std::vector<std::uint64_t> edges;
    edges.reserve(n);
    for (std::size_t t = 0; t < triangleCount; ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t a = weld[3 * t + std::size_t(k)], b = weld[3 * t + std::size_t((k + 1) % 3)];
            if (a != b)
                edges.push_back(std::min(a, b) << 32 | std::max(a, b));
        }
    std::sort(edges.begin(), edges.end());
    std::vector<std::uint64_t> boundary;
    for (std::size_t k = 0; k < edges.size();) {
        std::size_t end = k;
        while (end < edges.size() && edges[end] == edges[k])
            ++end;
        if ((end - k) % 2 == 1)
            boundary.push_back(edges[k]);
        k = end;
    }
    if (boundary.empty())
        return {};

    // Its connected parts (union-find over the welded ids).
    std::vector<std::uint32_t> parent(first.size());
    for (std::size_t k = 0; k < parent.size(); ++k)
        parent[k] = std::uint32_t(k);
    const auto root = [&](std::uint32_t x) {
        while (parent[x] != x)
            x = parent[x] = parent[parent[x]];
        return x;
    };
    for (std::uint64_t e : boundary)
        parent[root(std::uint32_t(e >> 32))] = root(std::uint32_t(e & 0xffffffffu));
    std::vector<std::uint32_t> partOf(first.size(), ~0u);
    std::vector<std::vector<std::uint64_t>> parts;
    for (std::uint64_t e : boundary) {
        const std::uint32_t r = root(std::uint32_t(e >> 32));
        if (partOf[r] == ~0u) {
            partOf[r] = std::uint32_t(parts.size());
            parts.emplace_back();
        }
        parts[partOf[r]].push_back(e);
    }

    // Each part's cone from the centroid of its vertices: its boundary is the part (the spokes
    // to each vertex come twice, as every vertex of a mod-2 boundary has even degree).
    std::vector<std::vector<glm::vec3>> caps;
    for (const std::vector<std::uint64_t>& part : parts) {
        glm::dvec3 sum(0.0);
        for (std::uint64_t e : part)
            sum += glm::dvec3(vertices[first[e >> 32]]) + glm::dvec3(vertices[first[e & 0xffffffffu]]);
        const glm::vec3 apex(sum / double(2 * part.size()));
        std::vector<glm::vec3>& cap = caps.emplace_back();
        for (std::uint64_t e : part)
            cap.insert(cap.end(), {apex, vertices[first[e >> 32]], vertices[first[e & 0xffffffffu]]});
    }
    return caps;
}

namespace {
float roundDown(double v) { return roundToward(v, -std::numeric_limits<double>::infinity()); }
float roundUp(double v) { return roundToward(v, std::numeric_limits<double>::infinity()); }
} // namespace

Bounds grownCapBox(const Bounds& capBounds)
{
    Bounds grown;
    for (int k = 0; k < 3; ++k) {
        grown.min[k] = roundDown(double(capBounds.min[k]) - kCapBoxGrowthMetres);
        grown.max[k] = roundUp(double(capBounds.max[k]) + kCapBoxGrowthMetres);
    }
    return grown;
}

bool segmentMeetsBox(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& lo, const glm::dvec3& hi)
{
    // Both ends past one face: most segments, without a division.
    for (int k = 0; k < 3; ++k)
        if ((p[k] < lo[k] && q[k] < lo[k]) || (p[k] > hi[k] && q[k] > hi[k]))
            return false;
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        const double d = q[k] - p[k];
        if (d == 0.0) {
            if (p[k] < lo[k] || p[k] > hi[k])
                return false;
            continue;
        }
        double ta = (lo[k] - p[k]) / d, tb = (hi[k] - p[k]) / d;
        if (ta > tb)
            std::swap(ta, tb);
        t0 = std::max(t0, ta), t1 = std::min(t1, tb);
        if (t0 > t1)
            return false;
    }
    return true;
}

std::uint64_t triangleFingerprint(const glm::vec3* vertices, std::size_t triangleCount)
{
    const std::string_view bytes(reinterpret_cast<const char*>(vertices), 3 * triangleCount * sizeof(glm::vec3));
    return std::uint64_t(std::hash<std::string_view>{}(bytes)) ^ (std::uint64_t(triangleCount) * 0x9e3779b97f4a7c15ULL);
}

bool InnerProxy::builtFor(const glm::vec3* vertices, std::size_t triangleCount, std::uint64_t fingerprintOfThem) const
{
    return fingerprint == fingerprintOfThem && builtFrom.size() == 3 * triangleCount &&
           std::memcmp(builtFrom.data(), vertices, builtFrom.size() * sizeof(glm::vec3)) == 0;
}

InnerProxy buildInnerProxy(const glm::vec3* vertices, std::size_t triangleCount, int resolution)
{
    InnerProxy proxy;
    proxy.builtFrom.assign(vertices, vertices + 3 * triangleCount);
    proxy.fingerprint = triangleFingerprint(vertices, triangleCount);
    if (triangleCount < kProxyMinTriangles)
        return proxy;
    // An open mesh, closed by its caps, if they are few and small.
    const std::vector<std::vector<glm::vec3>> caps = boundaryCaps(vertices, triangleCount);
    std::vector<glm::vec3> surface;
    if (!caps.empty()) {
        if (caps.size() > kProxyMaxCaps)
            return proxy;
        Bounds meshBounds;
        for (std::size_t k = 0; k < 3 * triangleCount; ++k)
            meshBounds.extend(vertices[k]);
        const auto volume = [](const Bounds& b, double grow) {
            const glm::dvec3 e = glm::dvec3(b.max) - glm::dvec3(b.min) + 2.0 * grow;
            return e.x * e.y * e.z;
        };
        double capVolume = 0.0;
        for (const std::vector<glm::vec3>& cap : caps) {
            Bounds box;
            for (const glm::vec3& v : cap)
                box.extend(v);
            capVolume += volume(box, kCapBoxGrowthMetres);
            proxy.capBoxes.push_back(box);
        }
        if (capVolume > kProxyMaxCapVolumeShare * volume(meshBounds, 0.0)) {
            proxy.capBoxes.clear();
            return proxy;
        }
        surface.assign(vertices, vertices + 3 * triangleCount);
        for (const std::vector<glm::vec3>& cap : caps)
            surface.insert(surface.end(), cap.begin(), cap.end());
    }
    std::vector<glm::vec3> faces = caps.empty() ? innerProxyTriangles(vertices, triangleCount, resolution)
                                                : innerProxyTriangles(surface.data(), surface.size() / 3, resolution);
    if (double(faces.size() / 3) > kProxyMaxFaceShare * double(triangleCount))
        return proxy;
    for (const glm::vec3& v : faces)
        proxy.faceBounds.extend(v);
    proxy.faces = std::move(faces);
    return proxy;
}

namespace {

/// Whether `b` lies farther than kInnerMarginMetres from box [lo, hi] along some axis.
bool apart(const Bounds& b, const glm::dvec3& lo, const glm::dvec3& hi)
{
    const glm::dvec3 bmin(b.min), bmax(b.max);
    for (int k = 0; k < 3; ++k)
        if (bmax[k] + kInnerMarginMetres < lo[k] || bmin[k] - kInnerMarginMetres > hi[k])
            return true;
    return false;
}

} // namespace

namespace {

/// Where the segments from `r` that meet box [lo, hi] may end on the source grid: the bounds,
/// in fractional columns and rows (sample (a, b) at (a, b)), of the box corners' shadows from
/// `r` on the source plane; none unless the box lies wholly between the plane and `r` (then a
/// segment from `r` to the plane meets the box only inside the corners' shadows' hull).
std::optional<std::array<double, 4>> shadowColumnsRows(const Patch& source, const glm::dvec3& r, const glm::dvec3& lo,
                                                       const glm::dvec3& hi)
{
    const glm::dvec3 n = glm::cross(source.u, source.v);
    const double rd = glm::dot(n, r - source.corner);
    const double uu = glm::dot(source.u, source.u), uv = glm::dot(source.u, source.v), vv = glm::dot(source.v, source.v);
    const double det = uu * vv - uv * uv;
    if (!(det > 0.0))
        return std::nullopt;
    std::array<double, 4> out{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                              std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
        const double cd = glm::dot(n, corner - source.corner);
        // Strictly between, by a relative margin far above rounding.
        if (!(rd > 0.0 ? cd > 1e-9 * rd && cd < (1.0 - 1e-9) * rd : cd < 1e-9 * rd && cd > (1.0 - 1e-9) * rd))
            return std::nullopt;
        const glm::dvec3 p = r + rd / (rd - cd) * (corner - r) - source.corner;
        const double pu = glm::dot(p, source.u), pv = glm::dot(p, source.v);
        const double alpha = (pu * vv - pv * uv) / det, beta = (pv * uu - pu * uv) / det;
        const double a = alpha * source.na - 0.5, b = beta * source.nb - 0.5;
        out[0] = std::min(out[0], a), out[1] = std::max(out[1], a);
        out[2] = std::min(out[2], b), out[3] = std::max(out[3], b);
    }
    if (!std::isfinite(out[0] + out[1] + out[2] + out[3]))
        return std::nullopt;
    return out;
}

/// The grid indices from a fractional bound, one more each way for rounding, clamped to the
/// grid (in double first: a shadow may reach far past it).
int firstIndex(double from) { return int(std::clamp(std::floor(from) - 1.0, 0.0, 1e9)); }
int lastIndex(double to, int n) { return int(std::clamp(std::ceil(to) + 1.0, -1.0, double(n - 1))); }

/// Sets in `candidates` (a row of a HiddenSampleMap) the source samples whose segments from the
/// receiver end `r` may meet box [lo, hi], a superset widened by a column and a row each way
/// for rounding; `shift` and `offset` are r's jitter (world, and in cells).
void markSegmentsThatMayMeet(const Patch& source, const glm::dvec3& r, const glm::dvec3& shift, const glm::dvec2& offset,
                             const glm::dvec3& lo, const glm::dvec3& hi, std::vector<std::uint64_t>& candidates)
{
    const auto mark = [&](int row, int a0, int a1) {
        for (int a = a0; a <= a1; ++a) {
            const int i = row * source.na + a;
            candidates[std::size_t(i >> 6)] |= std::uint64_t(1) << (i & 63);
        }
    };
    // A box wholly between r and the source plane: the samples in its shadow.
    if (const auto shadow = shadowColumnsRows(source, r, lo, hi)) {
        const int a0 = firstIndex((*shadow)[0] - offset.x), a1 = lastIndex((*shadow)[1] - offset.x, source.na);
        const int b0 = firstIndex((*shadow)[2] - offset.y), b1 = lastIndex((*shadow)[3] - offset.y, source.nb);
        for (int row = b0; row <= b1; ++row)
            mark(row, a0, a1);
        return;
    }
    // Else those not past the same face of the box as r: along each axis where r lies outside
    // the box, the samples on or past the box's far side; per source row one run of columns
    // (each face's plane cuts a row once).
    glm::dvec3 from(-std::numeric_limits<double>::infinity()), to(std::numeric_limits<double>::infinity());
    for (int k = 0; k < 3; ++k) {
        if (r[k] < lo[k])
            from[k] = lo[k] - shift[k];
        else if (r[k] > hi[k])
            to[k] = hi[k] - shift[k];
    }
    for (int row = 0; row < source.nb; ++row) {
        const glm::dvec3 base = source.corner + (row + 0.5) / source.nb * source.v;
        double aLo = -1.0, aHi = double(source.na);   // in columns: sample a sits at a
        bool empty = false;
        for (int k = 0; k < 3 && !empty; ++k)
            for (const auto& [bound, atLeast] : {std::pair(from[k], true), std::pair(to[k], false)}) {
                if (std::isinf(bound))
                    continue;
                // base + t u with t = (a + 0.5) / na, on the kept side of the bound.
                const double uk = source.u[k];
                if (uk == 0.0) {
                    empty = empty || (atLeast ? base[k] < bound : base[k] > bound);
                    continue;
                }
                const double a = (bound - base[k]) / uk * source.na - 0.5;
                if ((uk > 0.0) == atLeast)
                    aLo = std::max(aLo, a);
                else
                    aHi = std::min(aHi, a);
            }
        if (!empty && aLo <= aHi + 2.0)
            mark(row, firstIndex(aLo), lastIndex(aHi, source.na));
    }
}

} // namespace

ProxyPass::ProxyPass(const Shaft& shaft_, const ShaftHull& hull_, const std::array<glm::dvec3, 4>& sourceCorners_,
                     const std::vector<glm::dvec3>& receiverPoints, const PatchPair& patches_, bool culling_, bool narrow_)
    : shaft(shaft_), hull(hull_), patches(patches_), sourceCorners(sourceCorners_), culling(culling_), narrow(narrow_)
{
    sourceLo = receiverLo = glm::dvec3(std::numeric_limits<double>::infinity());
    sourceHi = receiverHi = -sourceLo;
    axis = glm::dvec3(0.0);
    for (const glm::dvec3& c : sourceCorners)
        sourceLo = glm::min(sourceLo, c), sourceHi = glm::max(sourceHi, c), axis -= 0.25 * c;
    for (const glm::dvec3& p : receiverPoints)
        receiverLo = glm::min(receiverLo, p), receiverHi = glm::max(receiverHi, p),
        axis += p / double(receiverPoints.size());
    axis = glm::normalize(axis);
}

bool proxyApplies(const Bounds& meshBounds, const ProxyPass& pass)
{
    return !meshBounds.empty() && apart(meshBounds, pass.sourceLo, pass.sourceHi) &&
           apart(meshBounds, pass.receiverLo, pass.receiverHi) && !pass.hull.excludesBox(meshBounds.min, meshBounds.max);
}

namespace {

/// Of the offered proxies, those that keep the grown boxes of the caps the shaft may meet within
/// kProxyCapBoxesPerSource and kProxyMaxCapBoxesPerCall, in `proxies`; those boxes in `capBoxes`.
void proxiesWithinCapBudget(const std::vector<std::shared_ptr<const InnerProxy>>& offered, const ProxyPass& pass,
                            const HiddenSampleMap& map, std::vector<std::shared_ptr<const InnerProxy>>& proxies,
                            std::vector<std::pair<glm::dvec3, glm::dvec3>>& capBoxes)
{
    const double boxesAllowed = std::clamp(kProxyCapBoxesPerSource * map.sourceCount(), 2.0, kProxyMaxCapBoxesPerCall);
    for (const std::shared_ptr<const InnerProxy>& proxy : offered) {
        std::vector<std::pair<glm::dvec3, glm::dvec3>> inShaft;
        for (const Bounds& box : proxy->capBoxes)
            if (const Bounds grown = grownCapBox(box); !pass.hull.excludesBox(grown.min, grown.max))
                inShaft.emplace_back(glm::dvec3(grown.min), glm::dvec3(grown.max));
        if (double(capBoxes.size() + inShaft.size()) > boxesAllowed)
            continue;
        capBoxes.insert(capBoxes.end(), inShaft.begin(), inShaft.end());
        proxies.push_back(proxy);
    }
}

/// The proxies' faces as one soup whose instances are the proxies, and per face whether it makes
/// at least kProxyFaceAxisCos with the pass's axis.
void proxyFaceSoup(const std::vector<std::shared_ptr<const InnerProxy>>& proxies, const ProxyPass& pass,
                   WorldTriangles& faces, std::vector<char>& across)
{
    for (std::size_t p = 0; p < proxies.size(); ++p) {
        const std::vector<glm::vec3>& f = proxies[p]->faces;
        faces.vertices.insert(faces.vertices.end(), f.begin(), f.end());
        faces.instanceOf.insert(faces.instanceOf.end(), f.size() / 3, std::uint32_t(p));
        for (std::size_t k = 0; k < f.size(); k += 3) {
            const glm::dvec3 a(f[k]), b(f[k + 1]), c(f[k + 2]);
            across.push_back(glm::dot(glm::normalize(glm::cross(b - a, c - a)), pass.axis) >= kProxyFaceAxisCos);
        }
    }
}

/// Prepares the faces in the shaft as `occluders`, culled where the pass allows it.
void prepareFaceOccluders(const std::vector<std::shared_ptr<const InnerProxy>>& proxies, const WorldTriangles& faces,
                          const ProxyPass& pass, OccluderSet& occluders)
{
    TriangleFilter filter;
    filter.triangles = &faces;
    filter.hull = &pass.hull;
    filter.sourceCorners = pass.sourceCorners;
    filter.instanceOutside.resize(proxies.size());
    for (std::size_t p = 0; p < proxies.size(); ++p)
        filter.instanceOutside[p] = pass.hull.excludesBox(proxies[p]->faceBounds.min, proxies[p]->faceBounds.max);
    // The receiver lies outside every proxy's mesh: §7's culling holds for the faces.
    if (pass.culling)
        filter.cullable.assign(proxies.size(), 1);
    occluders.prepare(pass.shaft, filter);
}

/// How many of the occluders the pass backprojects (0: it does not run), setting in `leave` those
/// it leaves out (kProxyAllFacesPairsPerRay, kProxyPairsPerRay).
std::size_t facesToUse(const OccluderSet& occluders, const std::vector<char>& across, const HiddenSampleMap& map,
                       std::vector<char>& leave)
{
    std::uint64_t pairsAll = 0, pairsAcross = 0;
    for (std::size_t k = 0; k < occluders.occluders.size(); ++k) {
        const Occluder& o = *occluders.occluders[k];
        const std::uint64_t pairs = std::uint64_t(o.a1 - o.a0 + 1) * std::uint64_t(o.b1 - o.b0 + 1);
        pairsAll += pairs;
        if (across[occluders.triangleOf[k]])
            pairsAcross += pairs;
        else
            leave[k] = 1;
    }
    const double rays = double(map.rayCount());
    std::size_t used = occluders.occluders.size();
    if (double(pairsAll) <= kProxyAllFacesPairsPerRay * rays) {
        std::fill(leave.begin(), leave.end(), 0);
    } else {
        used -= std::size_t(std::count(leave.begin(), leave.end(), 1));
        if (double(pairsAcross) > kProxyPairsPerRay * rays)
            used = 0;
    }
    return used;
}

/// ORs into `map` the rays the binned faces block, less those that meet one of `capBoxes`.
void seedLessCapRays(const ProxyPass& pass, const TileBins& bins,
                     const std::vector<std::pair<glm::dvec3, glm::dvec3>>& capBoxes, HiddenSampleMap& map)
{
    // With caps in the shaft: the proxies' answer less the rays that meet a cap's box. Only the
    // rays they blocked are tested: per receiver sample, the boxes its segments may reach (they
    // lie in the box of the sample and the source rectangle), the source samples that may meet
    // them (markSegmentsThatMayMeet), and of those, each by the slab test.
    HiddenSampleMap seeded(map.sourceCount(), map.receiverNa(), map.receiverNb());
    bitmaskPass(pass.shaft, bins, seeded, pass.narrow);
    const Patch& source = pass.patches.source;
    const SourceJitter& jitter = pass.patches.jitter;
    const raycast::SampleEnds ends(source, pass.patches.receiver, pass.patches.heights);
    tbb::parallel_for(tbb::blocked_range<int>(0, map.receiverCount(), 16), [&](const tbb::blocked_range<int>& range) {
        std::vector<std::size_t> near;
        std::vector<std::uint64_t> candidates;
        for (int j = range.begin(); j != range.end(); ++j) {
            const glm::dvec3 r = ends.receiverEnd(j);
            const glm::dvec3 lo = glm::min(r, pass.sourceLo), hi = glm::max(r, pass.sourceHi);
            near.clear();
            for (std::size_t b = 0; b < capBoxes.size(); ++b)
                if (!glm::any(glm::lessThan(hi, capBoxes[b].first)) && !glm::any(glm::greaterThan(lo, capBoxes[b].second)))
                    near.push_back(b);
            const std::span<std::uint64_t> out = map.row(j);
            const std::span<std::uint64_t> in = seeded.row(j);
            if (!near.empty()) {
                const glm::dvec3 shift = jitter.shift(source, j);
                candidates.assign(in.size(), 0);
                for (std::size_t b : near)
                    markSegmentsThatMayMeet(source, r, shift, jitter.offset(j), capBoxes[b].first, capBoxes[b].second,
                                            candidates);
                for (std::size_t w = 0; w < in.size(); ++w)
                    for (std::uint64_t bits = in[w] & candidates[w]; bits; bits &= bits - 1) {
                        const int i = int(64 * w) + std::countr_zero(bits);
                        const glm::dvec3 s = ends.source[std::size_t(i)] + shift;
                        for (std::size_t b : near)
                            if (segmentMeetsBox(r, s, capBoxes[b].first, capBoxes[b].second)) {
                                in[w] &= ~(std::uint64_t(1) << (i & 63));
                                break;
                            }
                    }
            }
            for (std::size_t w = 0; w < out.size(); ++w)
                out[w] |= in[w];
        }
    });
}

} // namespace

std::size_t seedFromInnerProxies(const std::vector<std::shared_ptr<const InnerProxy>>& offered, const ProxyPass& pass,
                                 OccluderSet& occluders, TileBins& bins, HiddenSampleMap& map)
{
    // The grown boxes of the caps the shaft may meet; a proxy that would take them past
    // kProxyCapBoxesPerSource and kProxyMaxCapBoxesPerCall sits the call out.
    std::vector<std::shared_ptr<const InnerProxy>> proxies;
    std::vector<std::pair<glm::dvec3, glm::dvec3>> capBoxes;
    proxiesWithinCapBudget(offered, pass, map, proxies, capBoxes);

    // One soup whose instances are the proxies; per face, whether the shaft's rays leave R
    // through it (kProxyFaceAxisCos).
    WorldTriangles faces;
    std::vector<char> across;
    proxyFaceSoup(proxies, pass, faces, across);
    if (faces.size() == 0)
        return 0;
    prepareFaceOccluders(proxies, faces, pass, occluders);
    // Every face where its pairs are few for the rays, else the faces across the axis alone.
    std::vector<char> leave(occluders.occluders.size(), 0);
    const std::size_t used = facesToUse(occluders, across, map, leave);
    if (used == 0)
        return 0;
    bins.build(pass.shaft, occluders, leave, std::vector<char>(proxies.size(), 1), faces);
    if (capBoxes.empty())
        bitmaskPass(pass.shaft, bins, map, pass.narrow);
    else
        seedLessCapRays(pass, bins, capBoxes, map);
    return used;
}

} // namespace sightline::bitmask
