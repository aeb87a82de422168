#include "demo/LevelParts.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

namespace sightline::demo::parts {
namespace {

vec3 newellNormal(const std::vector<vec3>& p)
{
    vec3 n(0.0f);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const vec3& a = p[i];
        const vec3& b = p[(i + 1) % p.size()];
        n += vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    return n;
}

vec3 centroid(const std::vector<vec3>& p)
{
    vec3 c(0.0f);
    for (const vec3& q : p)
        c += q;
    return c / float(p.size());
}

/// Unit circle table for `sides` segments, starting `phase` segments from +x.
std::vector<vec2> circle(int sides, float phase)
{
    std::vector<vec2> c(static_cast<std::size_t>(sides));
    for (int j = 0; j < sides; ++j) {
        const glm::dvec2 cs = cosSin((j + double(phase)) / sides);
        c[std::size_t(j)] = vec2(float(cs.x), float(cs.y));
    }
    return c;
}

} // namespace

// ------------------------------------------------------------------------------ transforms

mat4 translate(vec3 t)
{
    mat4 m(1.0f);
    m[3] = glm::vec4(t, 1.0f);
    return m;
}

mat4 scale(float s) { return mat4(glm::vec4(s, 0, 0, 0), glm::vec4(0, s, 0, 0), glm::vec4(0, 0, s, 0), glm::vec4(0, 0, 0, 1)); }

glm::dvec2 cosSin(double turns)
{
    turns -= std::floor(turns + 0.5);                  // [-0.5, 0.5]
    const double x = 2.0 * std::numbers::pi * turns;   // [-pi, pi]
    const double x2 = x * x;
    double c = 1.0, s = 1.0, term = 1.0;
    for (int k = 1; k <= 14; ++k) {   // |error| < pi^29 / 29! ~ 1e-16
        term *= -x2 / ((2.0 * k - 1.0) * (2.0 * k));
        c += term;
        s += term / (2.0 * k + 1.0);
    }
    return {c, s * x};
}

mat4 yaw(float turns)
{
    glm::dvec2 cs = cosSin(turns);
    if (std::abs(cs.x) < 1e-12)
        cs = {0.0, cs.y > 0 ? 1.0 : -1.0};
    if (std::abs(cs.y) < 1e-12)
        cs = {cs.x > 0 ? 1.0 : -1.0, 0.0};
    mat4 m(1.0f);
    m[0] = glm::vec4(float(cs.x), 0, float(-cs.y), 0);
    m[2] = glm::vec4(float(cs.y), 0, float(cs.x), 0);
    return m;
}

mat4 place(vec3 position, float yawTurns, float s)
{
    return translate(position) * yaw(yawTurns) * scale(s);
}

vec3 onCircle(float radius, float turns, float y)
{
    const glm::dvec2 cs = cosSin(turns);
    return {radius * float(cs.x), y, radius * float(cs.y)};
}

mat4 along(vec3 a, vec3 b)
{
    const vec3 y = b - a;
    const vec3 d = glm::normalize(y);
    const vec3 helper = std::abs(d.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0);
    const vec3 x = glm::normalize(glm::cross(d, helper));
    const vec3 z = glm::cross(x, d);
    mat4 m(1.0f);
    m[0] = glm::vec4(x, 0);
    m[1] = glm::vec4(y, 0);   // unit lathes are built with y in [0, 1]
    m[2] = glm::vec4(z, 0);
    m[3] = glm::vec4(a, 1);
    return m;
}

// ------------------------------------------------------------------------------ mesh building

Builder::Builder(std::string name, bool watertight)
{
    mesh.name = std::move(name);
    mesh.watertight = watertight;
}

void Builder::polygon(std::vector<vec3> points, vec3 outward)
{
    std::vector<vec3> p;
    for (const vec3& q : points)
        if (p.empty() || q != p.back())
            p.push_back(q);
    while (p.size() > 1 && p.front() == p.back())
        p.pop_back();
    if (p.size() < 3)
        return;
    if (glm::dot(newellNormal(p), outward) < 0.0f)
        std::reverse(p.begin(), p.end());
    emit(p);
}

void Builder::triangle(vec3 a, vec3 b, vec3 c) { emit({a, b, c}); }

void Builder::with(const mat4& m, const std::function<void()>& add)
{
    const mat4 saved = xf;
    xf = saved * m;
    add();
    xf = saved;
}

void Builder::emit(std::vector<vec3> p)
{
    for (vec3& q : p)
        q = vec3(xf * glm::vec4(q, 1.0f));
    if (glm::determinant(glm::mat3(xf)) < 0.0f)
        std::reverse(p.begin(), p.end());
    const vec3 n = glm::normalize(newellNormal(p));
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (const vec3& q : p) {
        mesh.positions.push_back(q);
        mesh.normals.push_back(n);
    }
    for (std::uint32_t i = 1; i + 1 < p.size(); ++i)
        mesh.indices.insert(mesh.indices.end(), {base, base + i, base + i + 1});
}

void box(Builder& b, vec3 lo, vec3 hi)
{
    const vec3 c = 0.5f * (lo + hi);
    const vec3 v[2] = {lo, hi};
    for (int axis = 0; axis < 3; ++axis) {
        const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        for (int side = 0; side < 2; ++side) {
            std::vector<vec3> p;
            for (auto [i, j] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
                vec3 q;
                q[axis] = v[side][axis];
                q[a1] = v[i][a1];
                q[a2] = v[j][a2];
                p.push_back(q);
            }
            b.polygon(p, centroid(p) - c);
        }
    }
}

void bevelBox(Builder& b, vec3 lo, vec3 hi, float r)
{
    const vec3 c = 0.5f * (lo + hi);
    // Per axis the four coordinates lo, lo + r, hi - r, hi; every vertex picks from this table so
    // shared vertices are bit-identical.
    std::array<std::array<float, 4>, 3> t{};
    for (int a = 0; a < 3; ++a)
        t[a] = {lo[a], lo[a] + r, hi[a] - r, hi[a]};
    auto at = [&](std::array<int, 3> i) { return vec3(t[0][i[0]], t[1][i[1]], t[2][i[2]]); };
    auto inner = [](int s) { return s == 0 ? 1 : 2; };
    auto add = [&](std::initializer_list<std::array<int, 3>> idx) {
        std::vector<vec3> p;
        for (const auto& i : idx)
            p.push_back(at(i));
        b.polygon(p, centroid(p) - c);
    };
    auto make = [](int axis, int va, int a1, int v1, int a2, int v2) {
        std::array<int, 3> i{};
        i[axis] = va;
        i[a1] = v1;
        i[a2] = v2;
        return i;
    };
    for (int axis = 0; axis < 3; ++axis) {
        const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        for (int s : {0, 3}) {
            // Main face.
            add({make(axis, s, a1, 1, a2, 1), make(axis, s, a1, 2, a2, 1), make(axis, s, a1, 2, a2, 2),
                 make(axis, s, a1, 1, a2, 2)});
            // Chamfer along axis a2 between the faces normal to `axis` and to `a1`.
            for (int s1 : {0, 3})
                add({make(axis, s, a1, inner(s1), a2, 1), make(axis, s, a1, inner(s1), a2, 2),
                     make(axis, inner(s), a1, s1, a2, 2), make(axis, inner(s), a1, s1, a2, 1)});
        }
    }
    for (int sx : {0, 3})
        for (int sy : {0, 3})
            for (int sz : {0, 3})
                add({{sx, inner(sy), inner(sz)}, {inner(sx), sy, inner(sz)}, {inner(sx), inner(sy), sz}});
}


void lathe(Builder& b, std::initializer_list<vec2> profileList, int sides)
{
    const std::vector<vec2> profile(profileList);
    const std::vector<vec2> ring = circle(sides, 0.5f);
    auto at = [&](std::size_t k, int j) {
        const vec2 p = profile[k];
        if (p.x == 0.0f)
            return vec3(0.0f, p.y, 0.0f);
        const vec2 c = ring[std::size_t(j % sides)];
        return vec3(p.x * c.x, p.y, -p.x * c.y);
    };
    for (std::size_t k = 0; k + 1 < profile.size(); ++k) {
        const vec2 d = profile[k + 1] - profile[k];
        for (int j = 0; j < sides; ++j) {
            const vec2 m = ring[std::size_t(j)] + ring[std::size_t((j + 1) % sides)];
            const vec3 outward(m.x * d.y, -d.x, -m.y * d.y);
            b.polygon({at(k, j), at(k, j + 1), at(k + 1, j + 1), at(k + 1, j)}, outward);
        }
    }
}

void cylinder(Builder& b, float r, float y0, float y1, int sides)
{
    lathe(b, {{0, y0}, {r, y0}, {r, y1}, {0, y1}}, sides);
}

void rod(Builder& b, vec3 from, vec3 to, float r0, float r1, int sides)
{
    b.with(along(from, to), [&] { lathe(b, {{0, 0}, {r0, 0}, {r1, 1}, {0, 1}}, sides); });
}

// ------------------------------------------------------------------------------ architecture

Mesh wall(const std::string& name, vec2 a, vec2 b, const std::vector<Opening>& openings, float height,
          float thickness)
{
    const vec2 d = glm::normalize(b - a);
    const float length = glm::length(b - a);
    const float start = std::abs(d.x) > std::abs(d.y) ? a.x : a.y;   // world coordinate at s = 0
    std::vector<float> xs{0.0f, length}, ys{0.0f, height};
    for (const Opening& o : openings) {
        xs.insert(xs.end(), {o.s0 - start, o.s1 - start});
        ys.insert(ys.end(), {o.y0, o.y1});
    }
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    std::sort(ys.begin(), ys.end());
    ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
    const int nx = int(xs.size()) - 1, ny = int(ys.size()) - 1;
    auto solid = [&](int i, int j) {
        if (i < 0 || j < 0 || i >= nx || j >= ny)
            return false;
        const float x = 0.5f * (xs[std::size_t(i)] + xs[std::size_t(i + 1)]) + start;
        const float y = 0.5f * (ys[std::size_t(j)] + ys[std::size_t(j + 1)]);
        for (const Opening& o : openings)
            if (x > o.s0 && x < o.s1 && y > o.y0 && y < o.y1)
                return false;
        return true;
    };
    Builder w(name);
    // Local frame: x along the wall, y up, z = x cross y; then placed at `a`.
    w.xf = mat4(glm::vec4(d.x, 0, d.y, 0), glm::vec4(0, 1, 0, 0), glm::vec4(-d.y, 0, d.x, 0),
                glm::vec4(a.x, 0, a.y, 1));
    const float h = 0.5f * thickness;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) {
            if (!solid(i, j))
                continue;
            const float x0 = xs[std::size_t(i)], x1 = xs[std::size_t(i + 1)];
            const float y0 = ys[std::size_t(j)], y1 = ys[std::size_t(j + 1)];
            w.polygon({{x0, y0, h}, {x1, y0, h}, {x1, y1, h}, {x0, y1, h}}, {0, 0, 1});
            w.polygon({{x0, y0, -h}, {x1, y0, -h}, {x1, y1, -h}, {x0, y1, -h}}, {0, 0, -1});
            if (!solid(i - 1, j))
                w.polygon({{x0, y0, -h}, {x0, y0, h}, {x0, y1, h}, {x0, y1, -h}}, {-1, 0, 0});
            if (!solid(i + 1, j))
                w.polygon({{x1, y0, -h}, {x1, y0, h}, {x1, y1, h}, {x1, y1, -h}}, {1, 0, 0});
            if (!solid(i, j - 1))
                w.polygon({{x0, y0, -h}, {x1, y0, -h}, {x1, y0, h}, {x0, y0, h}}, {0, -1, 0});
            if (!solid(i, j + 1))
                w.polygon({{x0, y1, -h}, {x1, y1, -h}, {x1, y1, h}, {x0, y1, h}}, {0, 1, 0});
        }
    return std::move(w.mesh);
}

Mesh tiles(const std::string& name, vec2 lo, vec2 hi, float y, float facing, float size)
{
    // Corners are lo + k * size (exact for the demo's whole-metre grids), so neighbouring tiles
    // share their corner values bit for bit.
    Builder t(name, false);
    const int nx = int(std::ceil((hi.x - lo.x) / size - 1e-4f)), nz = int(std::ceil((hi.y - lo.y) / size - 1e-4f));
    auto at = [&](float origin, float end, int k) { return std::min(end, origin + float(k) * size); };
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < nz; ++j) {
            const float x0 = at(lo.x, hi.x, i), x1 = at(lo.x, hi.x, i + 1), z0 = at(lo.y, hi.y, j), z1 = at(lo.y, hi.y, j + 1);
            t.polygon({{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}}, {0, facing, 0});
        }
    return std::move(t.mesh);
}

void casing(Builder& b, vec2 a, vec2 wallEnd, const Opening& o, bool mullions, float onlySide, float wallThickness)
{
    const vec2 d = glm::normalize(wallEnd - a);
    const float start = std::abs(d.x) > std::abs(d.y) ? a.x : a.y;
    b.with(mat4(glm::vec4(d.x, 0, d.y, 0), glm::vec4(0, 1, 0, 0), glm::vec4(-d.y, 0, d.x, 0),
                glm::vec4(a.x, 0, a.y, 1)),
           [&] {
               const float s0 = o.s0 - start, s1 = o.s1 - start, w = 0.07f, h = 0.5f * wallThickness;
               for (float side : {-1.0f, 1.0f}) {
                   if (side * onlySide < 0.0f)
                       continue;
                   const float z0 = side > 0 ? h - 0.01f : -h - 0.02f, z1 = side > 0 ? h + 0.02f : -h + 0.01f;
                   box(b, {s0 - w, o.y0 > 0 ? o.y0 - w : 0.0f, z0}, {s0, o.y1 + 0.01f, z1});
                   box(b, {s1, o.y0 > 0 ? o.y0 - w : 0.0f, z0}, {s1 + w, o.y1 + 0.01f, z1});
                   box(b, {s0 - w - 0.01f, o.y1, z0}, {s1 + w + 0.01f, o.y1 + w, z1});
                   if (o.y0 > 0)   // window sill
                       box(b, {s0 - w - 0.03f, o.y0 - w - 0.02f, z0 - 0.02f * (side < 0)},
                           {s1 + w + 0.03f, o.y0 + 0.005f, z1 + 0.02f * (side > 0)});
               }
               if (mullions) {
                   const float m = 0.5f * (s0 + s1), ym = o.y0 + 0.62f * (o.y1 - o.y0);
                   box(b, {m - 0.025f, o.y0 - 0.01f, -0.03f}, {m + 0.025f, o.y1 + 0.01f, 0.03f});
                   box(b, {s0 - 0.01f, ym - 0.025f, -0.029f}, {s1 + 0.01f, ym + 0.025f, 0.029f});
               }
           });
}

} // namespace sightline::demo::parts
