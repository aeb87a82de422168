#include "visibility/pvs/ShaftProof.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

#include <glm/geometric.hpp>

#include "base/UnionFind.h"

namespace sightline::pvs {

namespace {

constexpr double kSideMargin = 1e-7;    // metres: f and g keep at least this far from the plane
constexpr double kEdgeMargin = 1e-6;    // metres: a boundary edge this close to the hull fails it
constexpr std::size_t kMaxSolidTriangles = 4096;        // larger closed parts are planes only
constexpr std::size_t kMaxInstanceTriangles = 1 << 20;  // instances above this: no solids looked for

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }
double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p) { return cross2(b - a, p - a); }

double pointSegmentDistance(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b)
{
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

bool segmentsCross(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d)
{
    const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    return ((o1 <= 0.0 && o2 >= 0.0) || (o1 >= 0.0 && o2 <= 0.0)) && ((o3 <= 0.0 && o4 >= 0.0) || (o3 >= 0.0 && o4 <= 0.0)) &&
           !(o1 == 0.0 && o2 == 0.0 && o3 == 0.0 && o4 == 0.0 &&
             // collinear: overlap only if their projections overlap
             (std::max(a.x, b.x) < std::min(c.x, d.x) || std::max(c.x, d.x) < std::min(a.x, b.x) ||
              std::max(a.y, b.y) < std::min(c.y, d.y) || std::max(c.y, d.y) < std::min(a.y, b.y)));
}

double segmentSegmentDistance(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d)
{
    if (segmentsCross(a, b, c, d))
        return 0.0;
    return std::min({pointSegmentDistance(a, c, d), pointSegmentDistance(b, c, d), pointSegmentDistance(c, a, b),
                     pointSegmentDistance(d, a, b)});
}

bool insideConvex(const std::vector<glm::dvec2>& hull, const glm::dvec2& p)
{
    for (std::size_t i = 0; i < hull.size(); ++i)
        if (orient(hull[i], hull[(i + 1) % hull.size()], p) < 0.0)
            return false;
    return true;
}

/// Distance from the segment ab to the convex polygon `hull` (counter-clockwise; 1 or 2 points
/// allowed), 0 when they meet.
double segmentHullDistance(const glm::dvec2& a, const glm::dvec2& b, const std::vector<glm::dvec2>& hull)
{
    if (hull.size() == 1)
        return pointSegmentDistance(hull[0], a, b);
    if (hull.size() == 2)
        return segmentSegmentDistance(a, b, hull[0], hull[1]);
    if (insideConvex(hull, a) || insideConvex(hull, b))
        return 0.0;
    double d = INFINITY;
    for (std::size_t i = 0; i < hull.size(); ++i)
        d = std::min(d, segmentSegmentDistance(a, b, hull[i], hull[(i + 1) % hull.size()]));
    return d;
}

/// Whether the segment ab comes within `margin` of the convex polygon `hull` (counter-clockwise,
/// at least 3 points), tested by separating axes (the hull's edge normals and the segment's):
/// with the margin added to each axis this tests against the hull grown into a polygon with
/// sharp corners, which contains the rounded one, so "near" is never missed.
bool segmentNearHull(const glm::dvec2& a, const glm::dvec2& b, const std::vector<glm::dvec2>& hull, double margin)
{
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const glm::dvec2 e = hull[(i + 1) % hull.size()] - hull[i];
        const double len = glm::length(e);
        if (!(len > 0.0))
            continue;
        const glm::dvec2 n(e.y / len, -e.x / len);   // outward for a counter-clockwise hull
        const double c = glm::dot(n, hull[i]) + margin;
        if (glm::dot(n, a) > c && glm::dot(n, b) > c)
            return false;
    }
    const glm::dvec2 s = b - a;
    const double len = glm::length(s);
    if (len > 0.0) {
        const glm::dvec2 m(s.y / len, -s.x / len);
        bool above = true, below = true;
        for (const glm::dvec2& h : hull) {
            const double x = glm::dot(m, h - a);
            above = above && x > margin;
            below = below && x < -margin;
        }
        if (above || below)
            return false;
    }
    return true;
}

/// Whether the segment ab comes within `margin` of the convex polygon `hull` (any size).
bool segmentNear(const glm::dvec2& a, const glm::dvec2& b, const std::vector<glm::dvec2>& hull, double margin)
{
    if (hull.size() >= 3)
        return segmentNearHull(a, b, hull, margin);
    return segmentHullDistance(a, b, hull) <= margin;
}

/// Closed point-in-triangle test (either winding).
bool insideTriangle(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c)
{
    const double o1 = orient(a, b, p), o2 = orient(b, c, p), o3 = orient(c, a, p);
    return (o1 >= 0.0 && o2 >= 0.0 && o3 >= 0.0) || (o1 <= 0.0 && o2 <= 0.0 && o3 <= 0.0);
}

glm::dvec2 drop(const glm::dvec3& p, int axis) { return {p[(axis + 1) % 3], p[(axis + 2) % 3]}; }

/// Solid angle of triangle abc seen from the origin (Van Oosterom & Strackee 1983), signed by
/// winding.
double solidAngle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double numerator = glm::dot(a, glm::cross(b, c));
    const double denominator = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    return 2.0 * std::atan2(numerator, denominator);
}


/// An axis-aligned triangle keyed by its plane (axis, facing, coordinate: exact float values).
struct PlaneKey {
    int axis, facing;
    float offset;
    std::uint32_t triangle;
};

/// The axis-aligned triangles of `vertices` (3 per triangle) with a non-zero area, sorted by
/// plane so that each plane's triangles are a run.
std::vector<PlaneKey> axisAlignedTriangles(const std::vector<glm::vec3>& vertices)
{
    std::vector<PlaneKey> keys;
    for (std::size_t t = 0; 3 * t < vertices.size(); ++t) {
        const glm::vec3* p = &vertices[3 * t];
        for (int k = 0; k < 3; ++k)
            if (p[0][k] == p[1][k] && p[1][k] == p[2][k]) {
                const double area = cross2(drop(glm::dvec3(p[1]) - glm::dvec3(p[0]), k), drop(glm::dvec3(p[2]) - glm::dvec3(p[0]), k));
                if (area != 0.0)
                    keys.push_back({k, area > 0.0 ? 1 : -1, p[0][k], std::uint32_t(t)});
                break;
            }
    }
    std::sort(keys.begin(), keys.end(), [](const PlaneKey& a, const PlaneKey& b) {
        return std::tie(a.axis, a.facing, a.offset, a.triangle) < std::tie(b.axis, b.facing, b.offset, b.triangle);
    });
    return keys;
}

/// A plane's edges, in its 2-D coordinates (axis + 1, axis + 2). Axis-aligned ones (the usual
/// case: walls cut into quads, tile grids) are kept as intervals on their line, so that a
/// T-junction (one wall cut at a door height, its neighbour not) still joins the two and is not
/// taken for a boundary.
struct PlaneLine {
    int kind;          // 0: u = c, 1: v = c
    float c, lo, hi;   // the line and the interval on it
    int side;          // +1 / -1: where the triangle lies
    std::uint32_t local;
};
struct PlaneOtherEdge {
    float a0, a1, b0, b1;   // sorted end points
    int side;
    std::uint32_t local;
};
using BoundaryPieces = std::vector<std::pair<std::uint32_t, std::array<glm::dvec2, 2>>>;   // (local triangle, edge)

void planeEdges(const std::vector<glm::vec3>& vertices, const std::vector<std::uint32_t>& triangles, int axis,
                std::vector<PlaneLine>& lines, std::vector<PlaneOtherEdge>& others)
{
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    for (std::size_t k = 0; k < triangles.size(); ++k) {
        const glm::vec3* p = &vertices[3 * triangles[k]];
        for (int e = 0; e < 3; ++e) {
            const glm::vec3 &x = p[e], &y = p[(e + 1) % 3], &z = p[(e + 2) % 3];
            const std::uint32_t local = std::uint32_t(k);
            if (x[ua] == y[ua])
                lines.push_back({0, x[ua], std::min(x[va], y[va]), std::max(x[va], y[va]), z[ua] > x[ua] ? 1 : -1, local});
            else if (x[va] == y[va])
                lines.push_back({1, x[va], std::min(x[ua], y[ua]), std::max(x[ua], y[ua]), z[va] > x[va] ? 1 : -1, local});
            else {
                glm::vec2 m(x[ua], x[va]), n(y[ua], y[va]);
                if (std::tie(n.x, n.y) < std::tie(m.x, m.y))
                    std::swap(m, n);
                const double o = orient(glm::dvec2(m), glm::dvec2(n), glm::dvec2(z[ua], z[va]));
                others.push_back({m.x, m.y, n.x, n.y, o > 0.0 ? 1 : -1, local});
            }
        }
    }
}

/// Along each axis-aligned line: triangles on opposite sides of a shared stretch are one region,
/// and the stretches covered on one side only are boundary.
void joinAlongLines(std::vector<PlaneLine>& lines, UnionFind& components, BoundaryPieces& boundary)
{
    auto point = [&](int kind, double c, double t) { return kind == 0 ? glm::dvec2(c, t) : glm::dvec2(t, c); };
    std::sort(lines.begin(), lines.end(), [](const PlaneLine& a, const PlaneLine& b) {
        return std::tie(a.kind, a.c, a.lo, a.hi, a.local) < std::tie(b.kind, b.c, b.lo, b.hi, b.local);
    });
    for (std::size_t g0 = 0; g0 < lines.size();) {
        std::size_t g1 = g0 + 1;
        while (g1 < lines.size() && lines[g1].kind == lines[g0].kind && lines[g1].c == lines[g0].c)
            ++g1;
        for (std::size_t i = g0; i < g1; ++i)
            for (std::size_t j = i + 1; j < g1 && lines[j].lo < lines[i].hi; ++j)
                if (lines[j].side != lines[i].side && std::min(lines[i].hi, lines[j].hi) > lines[j].lo)
                    components.join(lines[i].local, lines[j].local);
        std::vector<float> cuts;
        for (std::size_t i = g0; i < g1; ++i)
            cuts.insert(cuts.end(), {lines[i].lo, lines[i].hi});
        std::sort(cuts.begin(), cuts.end());
        cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
        for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
            bool plus = false, minus = false;
            for (std::size_t i = g0; i < g1; ++i)
                if (lines[i].lo <= cuts[k] && lines[i].hi >= cuts[k + 1])
                    (lines[i].side > 0 ? plus : minus) = true;
            if (plus == minus)
                continue;   // inside (both sides) or no edge there at all
            const std::array<glm::dvec2, 2> piece = {point(lines[g0].kind, lines[g0].c, cuts[k]),
                                                     point(lines[g0].kind, lines[g0].c, cuts[k + 1])};
            for (std::size_t i = g0; i < g1; ++i)
                if (lines[i].lo <= cuts[k] && lines[i].hi >= cuts[k + 1])
                    boundary.push_back({lines[i].local, piece});
        }
        g0 = g1;
    }
}

/// The other edges: one shared by exactly two triangles on opposite sides is inner, any other
/// is boundary.
void joinAcrossEdges(std::vector<PlaneOtherEdge>& others, UnionFind& components, BoundaryPieces& boundary)
{
    std::sort(others.begin(), others.end(), [](const PlaneOtherEdge& a, const PlaneOtherEdge& b) {
        return std::tie(a.a0, a.a1, a.b0, a.b1, a.local) < std::tie(b.a0, b.a1, b.b0, b.b1, b.local);
    });
    auto sameEdge = [](const PlaneOtherEdge& a, const PlaneOtherEdge& b) {
        return a.a0 == b.a0 && a.a1 == b.a1 && a.b0 == b.b0 && a.b1 == b.b1;
    };
    for (std::size_t e = 0; e < others.size();) {
        std::size_t f = e + 1;
        while (f < others.size() && sameEdge(others[e], others[f]))
            ++f;
        if (f - e == 2 && others[e].side != others[e + 1].side) {
            components.join(others[e].local, others[e + 1].local);   // an inner edge
        } else {
            const std::array<glm::dvec2, 2> piece = {glm::dvec2(others[e].a0, others[e].a1), glm::dvec2(others[e].b0, others[e].b1)};
            for (std::size_t k = e; k < f; ++k)
                boundary.push_back({others[k].local, piece});
        }
        e = f;
    }
}

} // namespace

double Quad::radius() const { return 0.5 * std::max(glm::length(u + v), glm::length(u - v)); }

double Quad::extent() const { return std::max(glm::length(u), glm::length(v)); }

std::pair<Quad, Quad> Quad::split() const
{
    if (glm::dot(u, u) >= glm::dot(v, v))
        return {Quad{corner, 0.5 * u, v}, Quad{corner + 0.5 * u, 0.5 * u, v}};
    return {Quad{corner, u, 0.5 * v}, Quad{corner + 0.5 * v, u, 0.5 * v}};
}

std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> p)
{
    std::sort(p.begin(), p.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return std::tie(a.x, a.y) < std::tie(b.x, b.y); });
    p.erase(std::unique(p.begin(), p.end()), p.end());
    if (p.size() < 3)
        return p;
    std::vector<glm::dvec2> hull(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && orient(hull[k - 2], hull[k - 1], p[i]) <= 0.0)
            --k;
        hull[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && orient(hull[k - 2], hull[k - 1], p[i]) <= 0.0)
            --k;
        hull[k++] = p[i];
    }
    hull.resize(k - 1);
    return hull;
}

double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0)
        return glm::length(p - a);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3)
        return glm::length(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
        return glm::length(p - (a + (d1 / (d1 - d3)) * ab));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6)
        return glm::length(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
        return glm::length(p - (a + (d2 / (d2 - d6)) * ac));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
        return glm::length(p - (b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)));
    const double sum = va + vb + vc;
    if (!(sum > 0.0))   // degenerate: the nearest of its edges
        return std::min({glm::length(p - a), glm::length(p - b), glm::length(p - c)});
    return glm::length(p - (a + ab * (vb / sum) + ac * (vc / sum)));
}

ShaftProver::ShaftProver(const Scene& scene)
{
    WorldTriangles world = worldTriangles(scene);
    vertices_ = std::move(world.vertices);
    instanceOf_ = std::move(world.instanceOf);
    regionOf_.assign(instanceOf_.size(), -1);
    const std::vector<PlaneKey> keys = axisAlignedTriangles(vertices_);
    for (std::size_t begin = 0; begin < keys.size();) {
        std::size_t end = begin + 1;
        while (end < keys.size() && keys[end].axis == keys[begin].axis && keys[end].facing == keys[begin].facing &&
               keys[end].offset == keys[begin].offset)
            ++end;
        std::vector<std::uint32_t> triangles;
        for (std::size_t k = begin; k < end; ++k)
            triangles.push_back(keys[k].triangle);
        addPlaneRegions(keys[begin].axis, double(keys[begin].offset), triangles);
        begin = end;
    }
    for (Region& r : regions_)
        finishRegion(r);
    addClosedSolids(scene);
}

/// The regions of one plane's triangles (x[axis] = offset): triangles joined across inner edges,
/// each region with its boundary.
void ShaftProver::addPlaneRegions(int axis, double offset, const std::vector<std::uint32_t>& triangles)
{
    const std::size_t count = triangles.size();
    std::vector<PlaneLine> lines;
    std::vector<PlaneOtherEdge> others;
    planeEdges(vertices_, triangles, axis, lines, others);
    UnionFind components(count);
    BoundaryPieces boundary;
    joinAlongLines(lines, components, boundary);
    joinAcrossEdges(others, components, boundary);
    // One region per component.
    std::vector<std::int32_t> regionOfComponent(count, -1);
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t c = components.find(std::uint32_t(k));
        if (regionOfComponent[c] < 0) {
            regionOfComponent[c] = std::int32_t(regions_.size());
            Region r;
            r.axis = axis;
            r.offset = offset;
            regions_.push_back(std::move(r));
        }
        Region& r = regions_[std::size_t(regionOfComponent[c])];
        r.triangles.push_back(triangles[k]);
        r.instances.push_back(instanceOf_[triangles[k]]);
        regionOf_[triangles[k]] = regionOfComponent[c];
    }
    for (const auto& [local, piece] : boundary)
        regions_[std::size_t(regionOfComponent[components.find(local)])].boundary.push_back(piece);
}

/// A region's instances and boundary without repeats, and its grid index.
void ShaftProver::finishRegion(Region& r)
{
    std::sort(r.instances.begin(), r.instances.end());
    r.instances.erase(std::unique(r.instances.begin(), r.instances.end()), r.instances.end());
    auto less = [](const std::array<glm::dvec2, 2>& a, const std::array<glm::dvec2, 2>& b) {
        return std::tie(a[0].x, a[0].y, a[1].x, a[1].y) < std::tie(b[0].x, b[0].y, b[1].x, b[1].y);
    };
    std::sort(r.boundary.begin(), r.boundary.end(), less);
    r.boundary.erase(std::unique(r.boundary.begin(), r.boundary.end()), r.boundary.end());
    indexRegion(r);
}

void ShaftProver::addClosedSolids(const Scene& scene)
{
    // Closed solids: the connected parts (triangles joined by shared edges) of instances of
    // closed, consistently wound meshes (Scene.h closedAndOutward: every edge is shared by two
    // triangles in opposite directions, so each part is closed on its own: a chair's legs, one
    // casing of the trim, one book).
    solidOf_.assign(instanceOf_.size(), -1);
    std::vector<signed char> closedMesh(scene.meshes.size(), -1);
    std::size_t first = 0;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const std::uint32_t meshIndex = scene.instances[i].mesh;
        const std::size_t n = scene.meshes[meshIndex].triangleCount();
        if (n > 0 && n <= kMaxInstanceTriangles) {
            if (closedMesh[meshIndex] < 0)
                closedMesh[meshIndex] = closedAndOutward(scene.meshes[meshIndex]) ? 1 : 0;
            if (closedMesh[meshIndex] == 1)
                addSolids(first, n);
        }
        first += n;
    }
}

void ShaftProver::addSolids(std::size_t first, std::size_t n)
{
    // Weld the instance's world vertices by exact position, then join triangles across edges.
    using Key = std::tuple<float, float, float>;
    std::vector<std::pair<Key, std::uint32_t>> corners;
    for (std::size_t k = 0; k < 3 * n; ++k) {
        const glm::vec3& p = vertices_[3 * first + k];
        corners.push_back({Key{p.x, p.y, p.z}, std::uint32_t(k)});
    }
    std::sort(corners.begin(), corners.end());
    std::vector<std::uint32_t> weld(3 * n);
    std::uint32_t id = 0;
    for (std::size_t k = 0; k < corners.size(); ++k) {
        if (k > 0 && corners[k].first != corners[k - 1].first)
            ++id;
        weld[corners[k].second] = id;
    }
    std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> edges;   // (low, high, triangle)
    for (std::size_t t = 0; t < n; ++t)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t x = weld[3 * t + std::size_t(e)], y = weld[3 * t + std::size_t((e + 1) % 3)];
            edges.push_back({std::min(x, y), std::max(x, y), std::uint32_t(t)});
        }
    std::sort(edges.begin(), edges.end());
    UnionFind parts(n);
    for (std::size_t e = 0; e + 1 < edges.size(); ++e)
        if (std::get<0>(edges[e]) == std::get<0>(edges[e + 1]) && std::get<1>(edges[e]) == std::get<1>(edges[e + 1]))
            parts.join(std::get<2>(edges[e]), std::get<2>(edges[e + 1]));
    std::vector<std::int32_t> solidOfPart(n, -1);
    std::vector<std::size_t> sizes(n, 0);
    for (std::size_t t = 0; t < n; ++t)
        ++sizes[parts.find(std::uint32_t(t))];
    for (std::size_t t = 0; t < n; ++t) {
        const std::uint32_t part = parts.find(std::uint32_t(t));
        if (sizes[part] > kMaxSolidTriangles)
            continue;   // a part too large to test triangle by triangle: planes only
        if (solidOfPart[part] < 0) {
            solidOfPart[part] = std::int32_t(solids_.size());
            solids_.emplace_back();
        }
        Solid& s = solids_[std::size_t(solidOfPart[part])];
        for (int k = 0; k < 3; ++k) {
            s.vertices.emplace_back(vertices_[3 * (first + t) + std::size_t(k)]);
            s.bounds.extend(vertices_[3 * (first + t) + std::size_t(k)]);
        }
        solidOf_[first + t] = solidOfPart[part];
    }
}

std::size_t ShaftProver::solidCount() const { return solids_.size(); }

void ShaftProver::indexRegion(Region& r)
{
    const int a = (r.axis + 1) % 3, b = (r.axis + 2) % 3;
    r.lo = glm::dvec2(INFINITY);
    r.hi = glm::dvec2(-INFINITY);
    double area = 0.0;
    for (std::uint32_t t : r.triangles) {
        glm::dvec2 q[3];
        for (int k = 0; k < 3; ++k) {
            q[k] = glm::dvec2(vertices_[3 * t + std::size_t(k)][a], vertices_[3 * t + std::size_t(k)][b]);
            r.lo = glm::min(r.lo, q[k]);
            r.hi = glm::max(r.hi, q[k]);
        }
        area += std::abs(orient(q[0], q[1], q[2])) * 0.5;
    }
    const glm::dvec2 size = r.hi - r.lo;
    r.size = glm::length(size);
    const double cell = std::max(std::sqrt(std::max(area, 1e-12) / double(r.triangles.size())) * 2.0, 1e-6);
    r.nx = std::clamp(int(std::ceil(size.x / cell)), 1, 128);
    r.ny = std::clamp(int(std::ceil(size.y / cell)), 1, 128);
    auto range = [&](glm::dvec2 lo, glm::dvec2 hi, int& x0, int& x1, int& y0, int& y1) {
        const glm::dvec2 scale(r.nx / std::max(size.x, 1e-300), r.ny / std::max(size.y, 1e-300));
        x0 = std::clamp(int(std::floor((lo.x - r.lo.x) * scale.x)), 0, r.nx - 1);
        x1 = std::clamp(int(std::floor((hi.x - r.lo.x) * scale.x)), 0, r.nx - 1);
        y0 = std::clamp(int(std::floor((lo.y - r.lo.y) * scale.y)), 0, r.ny - 1);
        y1 = std::clamp(int(std::floor((hi.y - r.lo.y) * scale.y)), 0, r.ny - 1);
    };
    auto build = [&](auto boxOf, std::size_t items, std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& out) {
        std::vector<std::uint32_t> counts(std::size_t(r.nx * r.ny) + 1, 0);
        for (int pass = 0; pass < 2; ++pass) {
            if (pass == 1) {
                start.assign(counts.size(), 0);
                for (std::size_t k = 1; k < counts.size(); ++k)
                    start[k] = start[k - 1] + counts[k - 1];
                out.assign(start.back(), 0);
                std::fill(counts.begin(), counts.end(), 0);
            }
            for (std::size_t i = 0; i < items; ++i) {
                glm::dvec2 lo, hi;
                boxOf(i, lo, hi);
                int x0, x1, y0, y1;
                range(lo - kEdgeMargin, hi + kEdgeMargin, x0, x1, y0, y1);
                for (int y = y0; y <= y1; ++y)
                    for (int x = x0; x <= x1; ++x) {
                        const std::size_t c = std::size_t(y * r.nx + x);
                        if (pass == 1)
                            out[start[c] + counts[c]] = std::uint32_t(i);
                        ++counts[c];
                    }
            }
        }
    };
    build(
        [&](std::size_t i, glm::dvec2& lo, glm::dvec2& hi) {
            lo = glm::dvec2(INFINITY);
            hi = glm::dvec2(-INFINITY);
            for (int k = 0; k < 3; ++k) {
                const glm::dvec2 q(vertices_[3 * r.triangles[i] + std::size_t(k)][a], vertices_[3 * r.triangles[i] + std::size_t(k)][b]);
                lo = glm::min(lo, q);
                hi = glm::max(hi, q);
            }
        },
        r.triangles.size(), r.triStart, r.triItems);
    build(
        [&](std::size_t i, glm::dvec2& lo, glm::dvec2& hi) {
            lo = glm::min(r.boundary[i][0], r.boundary[i][1]);
            hi = glm::max(r.boundary[i][0], r.boundary[i][1]);
        },
        r.boundary.size(), r.edgeStart, r.edgeItems);
}

bool ShaftProver::regionContains(const Region& r, const std::vector<glm::dvec2>& hull, const OwnInstances& own) const
{
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    for (const glm::dvec2& p : hull) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    if (lo.x < r.lo.x || lo.y < r.lo.y || hi.x > r.hi.x || hi.y > r.hi.y)
        return false;   // leaves the region's bounds
    const glm::dvec2 size = r.hi - r.lo;
    const glm::dvec2 scale(r.nx / std::max(size.x, 1e-300), r.ny / std::max(size.y, 1e-300));
    auto cellX = [&](double x) { return std::clamp(int(std::floor((x - r.lo.x) * scale.x)), 0, r.nx - 1); };
    auto cellY = [&](double y) { return std::clamp(int(std::floor((y - r.lo.y) * scale.y)), 0, r.ny - 1); };
    const int x0 = cellX(lo.x - kEdgeMargin), x1 = cellX(hi.x + kEdgeMargin);
    const int y0 = cellY(lo.y - kEdgeMargin), y1 = cellY(hi.y + kEdgeMargin);
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            const std::size_t c = std::size_t(y * r.nx + x);
            for (std::uint32_t k = r.edgeStart[c]; k < r.edgeStart[c + 1]; ++k) {
                const auto& e = r.boundary[r.edgeItems[k]];
                if (std::max(e[0].x, e[1].x) < lo.x - kEdgeMargin || std::min(e[0].x, e[1].x) > hi.x + kEdgeMargin ||
                    std::max(e[0].y, e[1].y) < lo.y - kEdgeMargin || std::min(e[0].y, e[1].y) > hi.y + kEdgeMargin)
                    continue;
                if (segmentNear(e[0], e[1], hull, kEdgeMargin))
                    return false;
            }
        }
    const int a = (r.axis + 1) % 3, b = (r.axis + 2) % 3;
    auto corners = [&](std::uint32_t t) {
        const glm::vec3* q = &vertices_[3 * t];
        return std::array<glm::dvec2, 3>{glm::dvec2(q[0][a], q[0][b]), glm::dvec2(q[1][a], q[1][b]), glm::dvec2(q[2][a], q[2][b])};
    };
    // The target's own triangles in the region are holes: their edges must keep off the hull too.
    if (own)
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const std::size_t c = std::size_t(y * r.nx + x);
                for (std::uint32_t k = r.triStart[c]; k < r.triStart[c + 1]; ++k) {
                    const std::uint32_t t = r.triangles[r.triItems[k]];
                    if (!own(instanceOf_[t]))
                        continue;
                    const auto q = corners(t);
                    for (int e = 0; e < 3; ++e)
                        if (segmentNear(q[std::size_t(e)], q[std::size_t((e + 1) % 3)], hull, kEdgeMargin))
                            return false;
                }
            }
    // No boundary edge near the hull: it is all inside R or all outside (and all inside or all
    // outside each hole). One point decides.
    const glm::dvec2 p = hull[0];
    const std::size_t c = std::size_t(cellY(p.y) * r.nx + cellX(p.x));
    for (std::uint32_t k = r.triStart[c]; k < r.triStart[c + 1]; ++k) {
        const std::uint32_t t = r.triangles[r.triItems[k]];
        const auto q = corners(t);
        if (insideTriangle(p, q[0], q[1], q[2]))
            return !own || !own(instanceOf_[t]);
    }
    return false;
}

ShaftProver::RegionPlane ShaftProver::regionPlane(std::size_t region) const
{
    const Region& r = regions_[region];
    return {r.axis, r.offset, r.lo, r.hi};
}

bool ShaftProver::regionCovers(std::size_t region, const glm::dvec2& lo, const glm::dvec2& hi) const
{
    return regionContains(regions_[region], {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}}, {});
}

std::vector<std::array<glm::dvec2, 3>> ShaftProver::regionTriangles(std::size_t region) const
{
    const Region& r = regions_[region];
    std::vector<std::array<glm::dvec2, 3>> out;
    for (std::uint32_t t : r.triangles) {
        const glm::vec3* q = &vertices_[3 * t];
        out.push_back({drop(glm::dvec3(q[0]), r.axis), drop(glm::dvec3(q[1]), r.axis), drop(glm::dvec3(q[2]), r.axis)});
    }
    return out;
}

bool ShaftProver::planeBlocks(std::size_t triangle, const Quad& f, const Quad& g, const OwnInstances& own) const
{
    const glm::vec3* q = &vertices_[3 * triangle];
    const std::int32_t regionIndex = regionOf_[triangle];
    // The plane: x[axis] = offset for a region, n . x = d for a lone triangle.
    glm::dvec3 n(0.0);
    double d = 0.0;
    int axis = 0;
    if (regionIndex >= 0) {
        const Region& r = regions_[std::size_t(regionIndex)];
        axis = r.axis;
        n[axis] = 1.0;
        d = r.offset;
    } else {
        const glm::dvec3 a(q[0]), b(q[1]), c(q[2]);
        n = glm::cross(b - a, c - a);
        const double len = glm::length(n);
        if (!(len > 0.0))
            return false;
        n /= len;
        d = glm::dot(n, a);
        axis = std::abs(n.x) >= std::abs(n.y) && std::abs(n.x) >= std::abs(n.z) ? 0 : std::abs(n.y) >= std::abs(n.z) ? 1 : 2;
    }
    const auto fc = f.corners(), gc = g.corners();
    double sf[4], sg[4];
    for (int k = 0; k < 4; ++k) {
        sf[k] = glm::dot(n, fc[std::size_t(k)]) - d;
        sg[k] = glm::dot(n, gc[std::size_t(k)]) - d;
    }
    const bool fAbove = sf[0] > 0.0;
    for (int k = 0; k < 4; ++k) {
        if (fAbove ? !(sf[k] > kSideMargin && sg[k] < -kSideMargin) : !(sf[k] < -kSideMargin && sg[k] > kSideMargin))
            return false;
    }
    std::vector<glm::dvec2> crossings;
    crossings.reserve(16);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const double s = sf[i] / (sf[i] - sg[j]);
            const glm::dvec3 x = fc[std::size_t(i)] + s * (gc[std::size_t(j)] - fc[std::size_t(i)]);
            crossings.push_back(drop(x, axis));
        }
    const std::vector<glm::dvec2> hull = convexHull(std::move(crossings));
    if (regionIndex >= 0)
        return regionContains(regions_[std::size_t(regionIndex)], hull, own);
    if (own && own(instanceOf_[triangle]))
        return false;
    // A lone triangle (convex): every hull point inside it, kEdgeMargin from its edges.
    const glm::dvec2 a = drop(glm::dvec3(q[0]), axis), b = drop(glm::dvec3(q[1]), axis), c = drop(glm::dvec3(q[2]), axis);
    const double sign = orient(a, b, c) > 0.0 ? 1.0 : -1.0;
    const glm::dvec2 corners[3] = {a, b, c};
    // Dropping an axis never lengthens a distance, so a margin met in the projection is met in
    // the plane.
    for (int e = 0; e < 3; ++e) {
        const glm::dvec2 p0 = corners[e], p1 = corners[(e + 1) % 3];
        const double len = glm::length(p1 - p0);
        if (!(len > 0.0))
            return false;
        for (const glm::dvec2& p : hull)
            if (sign * orient(p0, p1, p) / len < kEdgeMargin)
                return false;
    }
    return true;
}

double ShaftProver::blockerSize(std::size_t triangle) const
{
    double size = 0.0;
    const std::int32_t r = regionOf_[triangle];
    if (r >= 0) {
        size = regions_[std::size_t(r)].size;
    } else {
        const glm::vec3* q = &vertices_[3 * triangle];
        size = std::max({glm::length(q[1] - q[0]), glm::length(q[2] - q[1]), glm::length(q[0] - q[2])});
    }
    if (isSolid(triangle)) {
        const Bounds& b = solidBounds(triangle);
        size = std::max(size, double(glm::length(b.max - b.min)));
    }
    return size;
}

bool ShaftProver::isSolid(std::size_t triangle) const { return solidOf_[triangle] >= 0; }

const Bounds& ShaftProver::solidBounds(std::size_t triangle) const { return solids_[std::size_t(solidOf_[triangle])].bounds; }

bool ShaftProver::ballInsideSolid(std::size_t triangle, const glm::dvec3& m, double r) const
{
    const Solid& s = solids_[std::size_t(solidOf_[triangle])];
    // Quick reject: a ball reaching out of the solid's bounds is not inside it.
    for (int k = 0; k < 3; ++k)
        if (m[k] - r < double(s.bounds.min[k]) || m[k] + r > double(s.bounds.max[k]))
            return false;
    double omega = 0.0;
    for (std::size_t t = 0; t + 2 < s.vertices.size(); t += 3) {
        const glm::dvec3 &a = s.vertices[t], &b = s.vertices[t + 1], &c = s.vertices[t + 2];
        if (pointTriangleDistance(m, a, b, c) <= r)
            return false;
        omega += solidAngle(a - m, b - m, c - m);
    }
    // Winding number omega / 4 pi: 1 inside an outward mesh (-1 inward), 0 outside; far from
    // every triangle (distance > r > 0) it is close to an integer.
    return std::abs(omega) > 2.0 * std::numbers::pi;
}

} // namespace sightline::pvs
