#include "demo/DemoLevel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace sightline::demo {
namespace {

using glm::mat4;
using glm::vec2;
using glm::vec3;

constexpr float kCeiling = 3.2f;
constexpr float kWall = 0.2f;   // wall thickness

// ------------------------------------------------------------------------------ randomness

/// splitmix64 (Steele, Lea & Flood 2014): tiny, fixed, identical on every platform.
class Rng {
public:
    explicit Rng(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next()
    {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1), 24 bits (exact in float).
    float unit() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }
    float range(float lo, float hi) { return lo + (hi - lo) * unit(); }
    /// Uniform in the unit ball, by rejection (arithmetic only: no libm differences).
    vec3 inBall()
    {
        for (;;) {
            const vec3 p(range(-1, 1), range(-1, 1), range(-1, 1));
            if (glm::dot(p, p) <= 1.0f)
                return p;
        }
    }
    vec3 direction()
    {
        for (;;) {
            const vec3 p = inBall();
            const float l2 = glm::dot(p, p);
            if (l2 > 1e-3f)
                return p / std::sqrt(l2);
        }
    }

private:
    std::uint64_t state_;
};

// ------------------------------------------------------------------------------ transforms

mat4 translate(vec3 t)
{
    mat4 m(1.0f);
    m[3] = glm::vec4(t, 1.0f);
    return m;
}

mat4 scale(float s) { return mat4(glm::vec4(s, 0, 0, 0), glm::vec4(0, s, 0, 0), glm::vec4(0, 0, s, 0), glm::vec4(0, 0, 0, 1)); }

/// (cos, sin) of an angle given in turns (1 = 360 degrees), by Taylor series in double precision:
/// arithmetic only, so it rounds the same everywhere (libm's sin and cos differ between libraries
/// in the last bit, which would change triangles from one platform to another).
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

/// Rotation about +Y by `turns` (positive: local +z turns toward world +x); quarter turns exact.
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

/// Object -> world for an object standing at `position`, turned by `yawTurns`, scaled by `s`.
mat4 place(vec3 position, float yawTurns = 0.0f, float s = 1.0f)
{
    return translate(position) * yaw(yawTurns) * scale(s);
}

/// Point at `radius` and angle `turns` on a horizontal circle at height y (angle 0 on +x, a
/// quarter turn on +z).
vec3 onCircle(float radius, float turns, float y)
{
    const glm::dvec2 cs = cosSin(turns);
    return {radius * float(cs.x), y, radius * float(cs.y)};
}

/// Maps local +Y onto the segment a -> b (length preserved), right-handed.
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

/// Accumulates flat-shaded polygons (each polygon gets its own vertices and face normal) under a
/// current affine transform `xf`. Normals are recomputed after transforming, and a mirroring
/// transform has its winding flipped back, so closed parts stay outward oriented.
struct Builder {
    Mesh mesh;
    mat4 xf{1.0f};

    explicit Builder(std::string name, bool watertight = true)
    {
        mesh.name = std::move(name);
        mesh.watertight = watertight;
    }

    /// A planar convex polygon given in cyclic order (either winding), turned so that its normal
    /// agrees with `outward`. Repeated points are dropped (a lathe quad on the axis is a triangle).
    void polygon(std::vector<vec3> points, vec3 outward)
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
    /// A single triangle, wound as given.
    void triangle(vec3 a, vec3 b, vec3 c) { emit({a, b, c}); }

    /// Runs `add` with `m` applied after the current transform.
    void with(const mat4& m, const std::function<void()>& add)
    {
        const mat4 saved = xf;
        xf = saved * m;
        add();
        xf = saved;
    }

private:
    void emit(std::vector<vec3> p)
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
};

vec3 centroid(const std::vector<vec3>& p)
{
    vec3 c(0.0f);
    for (const vec3& q : p)
        c += q;
    return c / float(p.size());
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

/// A box with all 12 edges chamfered by `r` (26 faces, 44 triangles): furniture looks made.
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

/// Unit circle table for `sides` segments, starting `phase` segments from +x.
std::vector<vec2> circle(int sides, float phase = 0.0f)
{
    std::vector<vec2> c(static_cast<std::size_t>(sides));
    for (int j = 0; j < sides; ++j) {
        const glm::dvec2 cs = cosSin((j + double(phase)) / sides);
        c[std::size_t(j)] = vec2(float(cs.x), float(cs.y));
    }
    return c;
}

/// Surface of revolution about +Y. `profile` holds (radius, y) points in order around the
/// cross-section, counter-clockwise in the (r, y) half plane (up the outside); when it starts and
/// ends on the axis (r = 0) the solid is closed and outward oriented.
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

/// Closed cylinder of radius r about +Y from y0 to y1.
void cylinder(Builder& b, float r, float y0, float y1, int sides)
{
    lathe(b, {{0, y0}, {r, y0}, {r, y1}, {0, y1}}, sides);
}

/// Closed rod of radius r0 at `from` tapering to r1 at `to`.
void rod(Builder& b, vec3 from, vec3 to, float r0, float r1, int sides)
{
    b.with(along(from, to), [&] { lathe(b, {{0, 0}, {r0, 0}, {r1, 1}, {0, 1}}, sides); });
}

// ------------------------------------------------------------------------------ architecture

struct Opening {
    float s0, s1;   // along the wall, world coordinate on the wall's axis
    float y0, y1;
};

/// A closed wall slab from `a` to `b` (points on the floor, an axis-aligned line), kWall thick and
/// kCeiling high, with rectangular openings. The face is cut into the grid spanned by the opening
/// edges; every solid cell gives a front and a back quad, and every cell edge bordering air gives
/// a quad across the thickness, so the slab is closed with no T-junctions.
Mesh wall(const std::string& name, vec2 a, vec2 b, const std::vector<Opening>& openings)
{
    const vec2 d = glm::normalize(b - a);
    const float length = glm::length(b - a);
    const float start = std::abs(d.x) > std::abs(d.y) ? a.x : a.y;   // world coordinate at s = 0
    std::vector<float> xs{0.0f, length}, ys{0.0f, kCeiling};
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
    const float h = 0.5f * kWall;
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

/// One-sided grid of `size` m tiles over the footprint at height y, facing +Y (facing = 1) or -Y.
Mesh tiles(const std::string& name, float y, float facing, int size)
{
    Builder t(name, false);
    for (int x = 0; x < 30; x += size)
        for (int z = 0; z < 20; z += size) {
            const float x0 = float(x), x1 = float(x + size), z0 = float(z), z1 = float(z + size);
            t.polygon({{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}}, {0, facing, 0});
        }
    return std::move(t.mesh);
}

/// Casings (door and window trim) around an opening of the wall from `a` to `wallEnd`, on its local
/// +z face (onlySide = 1), its -z face (-1) or both (0); and window mullions.
void casing(Builder& b, vec2 a, vec2 wallEnd, const Opening& o, bool mullions, float onlySide)
{
    const vec2 d = glm::normalize(wallEnd - a);
    const float start = std::abs(d.x) > std::abs(d.y) ? a.x : a.y;
    b.with(mat4(glm::vec4(d.x, 0, d.y, 0), glm::vec4(0, 1, 0, 0), glm::vec4(-d.y, 0, d.x, 0),
                glm::vec4(a.x, 0, a.y, 1)),
           [&] {
               const float s0 = o.s0 - start, s1 = o.s1 - start, w = 0.07f, h = 0.5f * kWall;
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

// ------------------------------------------------------------------------------ objects

struct PlantShape {
    const char* name;
    std::uint64_t seed;
    float stemTop;      // stem from inside the pot up to here
    vec3 crownCentre;   // leaves fill an ellipsoid here
    vec3 crownRadii;
    int leaves;
    bool hanging;       // hung from the ceiling by cords (origin at the ceiling) instead of a stem
};

/// Stem (or cords) plus `leaves` single-triangle leaves 3-8 cm long, random position in the crown
/// ellipsoid and random orientation. Not closed (leaves are open surfaces).
Mesh plant(const PlantShape& s)
{
    Rng rng(s.seed);
    Builder p(s.name, false);
    if (s.hanging) {
        for (int i = 0; i < 3; ++i)   // down into the basket's rim
            rod(p, vec3(0, 0, 0), onCircle(0.16f, float(i) / 3.0f, -0.81f), 0.004f, 0.004f, 4);
    } else {
        rod(p, vec3(0, 0.2f, 0), vec3(0, s.stemTop, 0), 0.025f, 0.012f, 6);
        for (int i = 0; i < 3; ++i) {
            const vec3 from(0, s.stemTop * rng.range(0.55f, 0.9f), 0);
            const vec3 dir = rng.inBall();
            const vec3 to = s.crownCentre + vec3(0.7f * s.crownRadii.x * dir.x, 0.5f * s.crownRadii.y * std::abs(dir.y),
                                                 0.7f * s.crownRadii.z * dir.z);
            rod(p, from, to, 0.01f, 0.005f, 4);
        }
    }
    for (int i = 0; i < s.leaves; ++i) {
        const vec3 c = s.crownCentre + rng.inBall() * s.crownRadii;
        const vec3 n = rng.direction();
        vec3 d = rng.direction();
        d = d - n * glm::dot(d, n);
        if (glm::dot(d, d) < 1e-4f)
            d = std::abs(n.x) < 0.9f ? vec3(1, 0, 0) - n * n.x : vec3(0, 1, 0) - n * n.y;
        d = glm::normalize(d);
        const vec3 e = glm::cross(n, d);
        const float length = rng.range(0.03f, 0.08f), width = length * rng.range(0.3f, 0.5f);
        const vec3 base = c - 0.5f * length * d;
        p.triangle(base - 0.5f * width * e, c + 0.5f * length * d, base + 0.5f * width * e);
    }
    return std::move(p.mesh);
}

Mesh pot()
{
    Builder b("pot");
    lathe(b, {{0, 0}, {0.14f, 0}, {0.19f, 0.29f}, {0.2f, 0.33f}, {0.175f, 0.33f}, {0, 0.3f}}, 12);
    return std::move(b.mesh);
}

Mesh basket()   // hanging basket, origin at the ceiling
{
    Builder b("basket");
    lathe(b, {{0, -0.98f}, {0.12f, -0.97f}, {0.2f, -0.9f}, {0.22f, -0.8f}, {0.2f, -0.8f}, {0, -0.82f}}, 12);
    return std::move(b.mesh);
}

Mesh pillar()
{
    Builder b("pillar");
    bevelBox(b, {-0.32f, 0, -0.32f}, {0.32f, 0.16f, 0.32f}, 0.02f);                       // plinth
    lathe(b, {{0, 0.15f}, {0.27f, 0.15f}, {0.27f, 0.21f}, {0.235f, 0.26f}, {0.21f, 0.34f}, {0.21f, 1.4f},
              {0.19f, 2.8f}, {0.23f, 2.88f}, {0.26f, 2.96f}, {0.26f, 3.0f}, {0, 3.0f}},
          20);
    bevelBox(b, {-0.3f, 2.99f, -0.3f}, {0.3f, kCeiling, 0.3f}, 0.015f);                     // abacus
    return std::move(b.mesh);
}

/// 2 m railing section along local +x: a post at x = 0, top and bottom rails, 19 turned balusters.
Mesh railing()
{
    Builder b("railing");
    bevelBox(b, {0, 0, -0.04f}, {0.08f, 1.06f, 0.04f}, 0.01f);
    bevelBox(b, {0.05f, 0.96f, -0.035f}, {2.03f, 1.03f, 0.035f}, 0.012f);
    bevelBox(b, {0.05f, 0.06f, -0.025f}, {2.03f, 0.11f, 0.025f}, 0.008f);
    for (int k = 0; k < 19; ++k)
        b.with(translate({0.14f + 0.1f * float(k), 0, 0}), [&] {
            lathe(b, {{0, 0.1f},     {0.014f, 0.1f},  {0.014f, 0.2f},  {0.021f, 0.26f}, {0.025f, 0.32f},
                      {0.018f, 0.4f}, {0.012f, 0.5f}, {0.012f, 0.74f}, {0.018f, 0.82f}, {0.014f, 0.9f},
                      {0.014f, 0.97f}, {0, 0.97f}},
                  6);
        });
    return std::move(b.mesh);
}

Mesh railingPost()
{
    Builder b("railing_post");
    bevelBox(b, {0, 0, -0.04f}, {0.08f, 1.06f, 0.04f}, 0.01f);
    return std::move(b.mesh);
}

/// Wooden chair facing +z: seat, four legs (the rear ones run up as back posts), three back slats,
/// stretchers.
Mesh chairWood()
{
    Builder b("chair_wood");
    bevelBox(b, {-0.22f, 0.43f, -0.21f}, {0.22f, 0.47f, 0.22f}, 0.01f);
    for (float x : {-0.18f, 0.18f}) {
        box(b, {x - 0.02f, 0, 0.16f}, {x + 0.02f, 0.44f, 0.2f});
        box(b, {x - 0.021f, 0, -0.2f}, {x + 0.021f, 0.96f, -0.16f});
        box(b, {x - 0.012f, 0.15f, -0.17f}, {x + 0.012f, 0.18f, 0.17f});
    }
    for (float y : {0.6f, 0.72f, 0.84f})
        box(b, {-0.17f, y, -0.195f}, {0.17f, y + 0.06f, -0.17f});
    return std::move(b.mesh);
}

/// Bistro chair facing +z: round seat, four turned legs, a curved back of bars.
Mesh chairBistro()
{
    Builder b("chair_bistro");
    lathe(b, {{0, 0.44f}, {0.2f, 0.44f}, {0.21f, 0.455f}, {0.2f, 0.47f}, {0, 0.47f}}, 16);
    for (int i = 0; i < 4; ++i) {
        const float a = 0.125f + 0.25f * float(i);
        rod(b, onCircle(0.19f, a, 0.0f), onCircle(0.13f, a, 0.45f), 0.012f, 0.016f, 6);
    }
    const vec3 l(-0.15f, 0.45f, -0.13f), r(0.15f, 0.45f, -0.13f);
    rod(b, l, l + vec3(-0.01f, 0.45f, -0.06f), 0.011f, 0.011f, 6);
    rod(b, r, r + vec3(0.01f, 0.45f, -0.06f), 0.011f, 0.011f, 6);
    for (int i = 0; i < 5; ++i) {   // curved top rail: a polyline of rods
        const float a0 = 0.575f + 0.35f * float(i) / 5.0f, a1 = 0.575f + 0.35f * float(i + 1) / 5.0f;
        const vec3 p0 = onCircle(0.19f, a0, 0.86f), p1 = onCircle(0.19f, a1, 0.86f);
        const vec3 overlap = 0.012f * glm::normalize(p1 - p0);   // no two caps meet edge to edge
        rod(b, p0 - overlap, p1 + overlap, 0.02f, 0.02f, 6);
    }
    return std::move(b.mesh);
}

Mesh tableRound()
{
    Builder b("table_round");
    lathe(b, {{0, 0.715f}, {0.54f, 0.715f}, {0.56f, 0.735f}, {0.545f, 0.76f}, {0, 0.76f}}, 32);
    lathe(b, {{0, 0.03f}, {0.06f, 0.03f}, {0.06f, 0.1f}, {0.032f, 0.4f}, {0.045f, 0.52f}, {0.034f, 0.62f},
              {0.065f, 0.69f}, {0, 0.72f}},
          12);
    bevelBox(b, {-0.32f, 0, -0.04f}, {0.32f, 0.05f, 0.04f}, 0.01f);
    bevelBox(b, {-0.041f, 0.001f, -0.32f}, {0.041f, 0.049f, 0.32f}, 0.01f);
    return std::move(b.mesh);
}

Mesh tableLong()
{
    Builder b("table_long");
    bevelBox(b, {-1.2f, 0.72f, -0.45f}, {1.2f, 0.77f, 0.45f}, 0.012f);
    for (float x : {-1.1f, 1.1f})
        for (float z : {-0.36f, 0.36f})
            bevelBox(b, {x - 0.035f, 0, z - 0.035f}, {x + 0.035f, 0.73f, z + 0.035f}, 0.008f);
    bevelBox(b, {-1.08f, 0.62f, -0.345f}, {1.08f, 0.725f, -0.325f}, 0.005f);
    bevelBox(b, {-1.08f, 0.62f, 0.325f}, {1.08f, 0.725f, 0.345f}, 0.005f);
    return std::move(b.mesh);
}

/// Bookcase, back against local -z, 1.2 x 2.0 x 0.35 m; four shelves of books of random size.
Mesh bookcase(const char* name, std::uint64_t seed)
{
    Rng rng(seed);
    Builder b(name);
    bevelBox(b, {-0.6f, 0, -0.175f}, {-0.57f, 2.0f, 0.175f}, 0.006f);      // sides
    bevelBox(b, {0.57f, 0, -0.175f}, {0.6f, 2.0f, 0.175f}, 0.006f);
    box(b, {-0.58f, 0.01f, -0.176f}, {0.58f, 1.99f, -0.16f});                 // back
    box(b, {-0.58f, 0.0f, -0.17f}, {0.58f, 0.08f, 0.16f});                    // plinth
    bevelBox(b, {-0.58f, 1.97f, -0.17f}, {0.58f, 2.0f, 0.17f}, 0.006f);     // top
    for (int s = 0; s < 4; ++s) {
        const float y = 0.08f + 0.42f * float(s);   // shelf surface
        if (s > 0)
            box(b, {-0.58f, y - 0.03f, -0.17f}, {0.58f, y, 0.17f});
        if (s == 2)
            continue;   // an empty shelf
        for (float x = -0.56f; x < 0.5f;) {
            const float w = rng.range(0.025f, 0.06f), h = rng.range(0.22f, 0.36f), depth = rng.range(0.17f, 0.27f);
            if (rng.unit() < 0.1f) {   // a gap
                x += rng.range(0.04f, 0.15f);
                continue;
            }
            box(b, {x, y - 0.003f, -0.15f}, {x + w - 0.002f, y + h, -0.15f + depth});
            x += w;
        }
    }
    box(b, {-0.58f, 1.73f, -0.17f}, {0.58f, 1.76f, 0.17f});                   // upper shelf, empty
    return std::move(b.mesh);
}

Mesh crate(const char* name, float size)
{
    Builder b(name);
    const float h = 0.5f * size;
    bevelBox(b, {-h, 0, -h}, {h, size, h}, 0.02f);
    for (float y : {0.2f * size, 0.8f * size})   // bands
        box(b, {-h - 0.01f, y - 0.03f, -h - 0.01f}, {h + 0.01f, y + 0.03f, h + 0.01f});
    return std::move(b.mesh);
}

/// Shade, bulb and cord; origin at the ceiling, the shade's rim `drop` + 0.86 m below it.
Mesh pendantLamp(const char* name, float drop)
{
    Builder b(name);
    rod(b, vec3(0, -0.67f - drop, 0), vec3(0, 0.001f, 0), 0.006f, 0.006f, 6);
    b.xf = translate({0, -drop, 0});
    lathe(b, {{0, -0.6f}, {0.1f, -0.64f}, {0.19f, -0.73f}, {0.24f, -0.86f}, {0.25f, -0.86f}, {0.2f, -0.71f},
              {0.1f, -0.615f}, {0, -0.575f}},
          16);
    // bulb (a sphere of radius 6 cm)
    std::vector<vec2> bulb;
    for (int k = 0; k <= 6; ++k) {
        const glm::dvec2 cs = cosSin(float(k) / 12.0f);   // half a turn, bottom to top
        bulb.push_back({k == 0 || k == 6 ? 0.0f : 0.06f * float(cs.y), -0.72f - 0.06f * float(cs.x)});
    }
    lathe(b, {bulb[0], bulb[1], bulb[2], bulb[3], bulb[4], bulb[5], bulb[6]}, 8);
    return std::move(b.mesh);
}

Mesh vaseOnPlinth()
{
    Builder b("vase_plinth");
    bevelBox(b, {-0.22f, 0, -0.22f}, {0.22f, 0.9f, 0.22f}, 0.015f);
    lathe(b, {{0, 0.899f}, {0.07f, 0.899f}, {0.12f, 0.95f}, {0.15f, 1.05f}, {0.14f, 1.15f}, {0.1f, 1.24f},
              {0.06f, 1.3f}, {0.055f, 1.36f}, {0.07f, 1.4f}, {0.045f, 1.38f}, {0, 1.37f}},
          16);
    return std::move(b.mesh);
}

Mesh sofa()   // facing +z, 2.0 m wide
{
    Builder b("sofa");
    bevelBox(b, {-0.9f, 0.1f, -0.4f}, {0.9f, 0.42f, 0.45f}, 0.05f);   // seat
    bevelBox(b, {-0.9f, 0.1f, -0.45f}, {0.9f, 0.85f, -0.22f}, 0.06f);   // back
    for (float x : {-1.0f, 0.78f})
        bevelBox(b, {x, 0.05f, -0.45f}, {x + 0.22f, 0.62f, 0.45f}, 0.06f);   // arms
    for (float x : {-0.9f, 0.9f})
        for (float z : {-0.36f, 0.36f})
            b.with(translate({x, 0, z}), [&] { cylinder(b, 0.03f, 0.0f, 0.12f, 6); });
    return std::move(b.mesh);
}

Mesh tableLow()
{
    Builder b("table_low");
    bevelBox(b, {-0.6f, 0.36f, -0.35f}, {0.6f, 0.42f, 0.35f}, 0.015f);
    bevelBox(b, {-0.55f, 0.06f, -0.3f}, {0.55f, 0.09f, 0.3f}, 0.008f);   // magazine shelf
    for (float x : {-0.52f, 0.52f})
        for (float z : {-0.27f, 0.27f})
            b.with(translate({x, 0, z}), [&] {
                lathe(b, {{0, 0}, {0.022f, 0}, {0.03f, 0.08f}, {0.022f, 0.2f}, {0.026f, 0.37f}, {0, 0.37f}}, 6);
            });
    return std::move(b.mesh);
}

// ------------------------------------------------------------------------------ the level

const PlantShape kFicus{"plant_ficus", 0x51C0FFEEull, 1.25f, {0, 1.45f, 0}, {0.42f, 0.42f, 0.42f}, 1000, false};
const PlantShape kFern{"plant_fern", 0xFE4Aull, 0.45f, {0, 0.72f, 0}, {0.55f, 0.3f, 0.55f}, 1000, false};
const PlantShape kPalm{"plant_palm", 0xA1A1ull, 1.5f, {0, 1.68f, 0}, {0.5f, 0.32f, 0.5f}, 1000, false};
const PlantShape kHanging{"plant_hanging", 0x4A46ull, 0.0f, {0, -1.2f, 0}, {0.3f, 0.45f, 0.3f}, 1000, true};

class LevelBuilder {
public:
    Scene scene;

    std::uint32_t add(Mesh mesh) { return scene.addMesh(std::move(mesh)); }
    void put(std::uint32_t mesh, const mat4& transform)
    {
        scene.instances.push_back(Instance{scene.meshes[mesh].name, mesh, transform});
    }
};

struct WallSpec {
    const char* name;
    vec2 a, b;
    std::vector<Opening> doors;     // from the floor
    std::vector<Opening> windows;
    bool outer;                     // outer windows get mullions
};

Opening door(float s0, float s1, float height = 2.1f) { return {s0, s1, 0.0f, height}; }
Opening window(float s0, float s1, float y0 = 0.9f, float y1 = 2.3f) { return {s0, s1, y0, y1}; }

void addArchitecture(LevelBuilder& level)
{
    const std::vector<WallSpec> walls{
        {"wall_south", {-0.1f, 0}, {30.1f, 0}, {},
         {window(3, 4.6f), window(6.5f, 8.1f), window(12, 13.6f), window(15.5f, 17.1f), window(19, 20.6f),
          window(24, 25.6f), window(27, 28.6f)}, true},
        {"wall_north", {-0.1f, 20}, {30.1f, 20}, {},
         {window(2.5f, 4.1f), window(6, 7.6f), window(9.5f, 11.1f), window(16, 17.6f), window(20, 21.6f),
          window(24, 25.6f), window(27.5f, 29.1f)}, true},
        {"wall_west", {0, 0.05f}, {0, 19.95f}, {}, {window(6.5f, 8.1f), window(13, 14.6f), window(16.5f, 18.1f)}, true},
        {"wall_east", {30, 0.05f}, {30, 19.95f}, {}, {window(3, 4.6f), window(6.5f, 8.1f), window(12.5f, 14.1f),
                                                     window(16, 17.6f)}, true},
        {"wall_gallery_conservatory", {10, 0.05f}, {10, 9.95f}, {door(4.55f, 5.45f)},
         {window(1.4f, 2.9f, 1.0f, 2.2f), window(7.1f, 8.6f, 1.0f, 2.2f)}, false},
        {"wall_conservatory_archive", {22, 0.05f}, {22, 9.95f}, {door(7.2f, 8.4f)}, {window(1.5f, 3.0f, 1.0f, 2.2f)}, false},
        {"wall_middle", {0.05f, 10}, {29.95f, 10}, {door(4.2f, 5.2f), door(17, 18.6f, 2.2f), door(25.5f, 26.5f)},
         {window(11.2f, 12.8f, 1.0f, 2.2f)}, false},
        {"wall_dining_lounge", {14, 10.05f}, {14, 19.95f}, {door(14.2f, 15.8f, 2.2f)}, {window(17.4f, 18.8f, 1.0f, 2.2f)}, false},
    };
    Builder trim("trim");
    for (const WallSpec& w : walls) {
        std::vector<Opening> openings = w.doors;
        openings.insert(openings.end(), w.windows.begin(), w.windows.end());
        level.put(level.add(wall(w.name, w.a, w.b, openings)), mat4(1.0f));
        // Outer walls are trimmed on the inside only: the side of the building's centre.
        const vec2 d = glm::normalize(w.b - w.a);
        const float inside = glm::dot(vec2(-d.y, d.x), vec2(15, 10) - w.a) > 0 ? 1.0f : -1.0f;
        for (const Opening& o : w.doors)
            casing(trim, w.a, w.b, o, false, 0.0f);
        for (const Opening& o : w.windows)
            casing(trim, w.a, w.b, o, w.outer, w.outer ? inside : 0.0f);
    }
    level.put(level.add(std::move(trim.mesh)), mat4(1.0f));
    level.put(level.add(tiles("floor", 0.0f, 1.0f, 1)), mat4(1.0f));
    level.put(level.add(tiles("ceiling", kCeiling, -1.0f, 2)), mat4(1.0f));
}

void addFurniture(LevelBuilder& level)
{
    const float quarter = 0.25f, half = 0.5f;   // turns
    // --- pillars: two rows in the conservatory B (outside the demo shaft), four in the lounge E.
    const std::uint32_t pillarMesh = level.add(pillar());
    for (float x : {12.0f, 15.0f, 18.0f, 21.0f})
        for (float z : {2.6f, 7.4f})
            level.put(pillarMesh, place({x, 0, z}));
    for (float x : {18.0f, 26.0f})
        for (float z : {13.0f, 17.0f})
            level.put(pillarMesh, place({x, 0, z}));

    // --- the balustrade across the gallery A (x = 4.5, z in [2.5, 8.5]); sections run along +z.
    const std::uint32_t railMesh = level.add(railing()), postMesh = level.add(railingPost());
    for (int k = 0; k < 3; ++k)
        level.put(railMesh, place({4.5f, 0, 2.5f + 2.0f * float(k)}, -quarter));
    level.put(postMesh, place({4.5f, 0, 8.5f}, -quarter));

    // --- tables and chairs. A chair faces +z locally; turn it to face the table centre.
    const std::uint32_t roundMesh = level.add(tableRound()), bistroMesh = level.add(chairBistro());
    const std::uint32_t longMesh = level.add(tableLong()), woodMesh = level.add(chairWood());
    auto roundTable = [&](vec2 c, float phase, int chairs) {
        level.put(roundMesh, place({c.x, 0, c.y}, phase));
        for (int i = 0; i < chairs; ++i) {
            const float a = phase + float(i) / float(chairs);
            // At angle a around the table; a yaw of -a - 1/4 turns the chair's +z to the centre.
            level.put(bistroMesh, place(vec3(c.x, 0, c.y) + onCircle(0.72f, a, 0.0f), -a - quarter));
        }
    };
    roundTable({7.6f, 2.0f}, 0.3f, 3);     // gallery
    roundTable({14.2f, 4.35f}, 0.1f, 4);   // conservatory, in the shaft
    roundTable({17.4f, 8.4f}, 0.3f, 3);
    roundTable({12.6f, 1.4f}, 0.5f, 2);
    for (float x : {4.0f, 9.8f}) {         // dining hall: two long tables, eight chairs each
        level.put(longMesh, place({x, 0, 15.0f}));
        for (float dx : {-0.75f, 0.0f, 0.75f}) {
            level.put(woodMesh, place({x + dx, 0, 15.0f - 0.62f}, 0.0f));
            level.put(woodMesh, place({x + dx, 0, 15.0f + 0.62f}, half));
        }
        level.put(woodMesh, place({x - 1.5f, 0, 15.0f}, quarter));
        level.put(woodMesh, place({x + 1.5f, 0, 15.0f}, -quarter));
    }

    // --- lounge: sofas around low tables.
    const std::uint32_t sofaMesh = level.add(sofa()), lowMesh = level.add(tableLow());
    level.put(lowMesh, place({22, 0, 15}));
    level.put(sofaMesh, place({22, 0, 13.6f}, 0.0f));
    level.put(sofaMesh, place({22, 0, 16.4f}, half));
    level.put(lowMesh, place({28.2f, 0, 12.2f}, quarter));
    level.put(sofaMesh, place({29.3f, 0, 12.2f}, -quarter));
    level.put(sofaMesh, place({16.0f, 0, 18.9f}, half));

    // --- shelves and crates: archive C, plus a few in the dining hall and the lounge.
    const std::uint32_t caseA = level.add(bookcase("bookcase_a", 0xB00C5ull));
    const std::uint32_t caseB = level.add(bookcase("bookcase_b", 0xB00C6ull));
    for (int i = 0; i < 3; ++i) {          // a back-to-back row in the archive
        const float x = 23.4f + 1.22f * float(i);
        level.put(i % 2 ? caseA : caseB, place({x, 0, 4.6f}, half));
        level.put(i % 2 ? caseB : caseA, place({x, 0, 4.97f}, 0.0f));
    }
    level.put(caseA, place({1.4f, 0, 10.3f}));        // dining hall, against the middle wall
    level.put(caseB, place({18.8f, 0, 19.7f}, half));  // lounge, against the north wall
    const std::uint32_t crateL = level.add(crate("crate_large", 0.8f)), crateS = level.add(crate("crate_small", 0.5f));
    Rng rng(0xC4A7Eull);
    for (vec2 c : {vec2(23.0f, 0.7f), vec2(24.0f, 0.8f), vec2(28.9f, 1.0f), vec2(29.0f, 9.0f), vec2(27.9f, 9.1f)}) {
        level.put(crateL, place({c.x, 0, c.y}, rng.range(-0.03f, 0.03f)));
        level.put(crateS, place({c.x + rng.range(-0.1f, 0.1f), 0.8f, c.y + rng.range(-0.1f, 0.1f)}, rng.range(-0.1f, 0.1f)));
    }
    for (vec2 c : {vec2(25.3f, 8.9f), vec2(23.2f, 9.3f), vec2(26.4f, 0.6f)})
        level.put(crateS, place({c.x, 0, c.y}, rng.range(-0.1f, 0.1f)));

    // --- vases on plinths (gallery, dining), pendant lamps (origin at the ceiling).
    const std::uint32_t vaseMesh = level.add(vaseOnPlinth());
    for (vec2 c : {vec2(0.6f, 0.6f), vec2(0.6f, 9.4f), vec2(9.4f, 0.6f), vec2(13.4f, 19.4f)})
        level.put(vaseMesh, place({c.x, 0, c.y}));
    const std::uint32_t lampMesh = level.add(pendantLamp("lamp_pendant", 0.0f));
    const std::uint32_t lampLong = level.add(pendantLamp("lamp_pendant_long", 0.4f));
    for (vec2 c : {vec2(7.6f, 2.0f), vec2(2.9f, 15.0f), vec2(5.1f, 15.0f), vec2(8.7f, 15.0f), vec2(10.9f, 15.0f),
                   vec2(22.0f, 15.0f), vec2(26.0f, 5.0f), vec2(5.0f, 5.0f)})
        level.put(lampMesh, place({c.x, kCeiling, c.y}));
    for (vec2 c : {vec2(14.2f, 4.35f), vec2(17.4f, 8.4f), vec2(12.6f, 1.4f)})
        level.put(lampLong, place({c.x, kCeiling, c.y}));
}

void addPlants(LevelBuilder& level)
{
    const std::uint32_t potMesh = level.add(pot()), basketMesh = level.add(basket());
    const std::uint32_t variants[3] = {level.add(plant(kFicus)), level.add(plant(kFern)), level.add(plant(kPalm))};
    const std::uint32_t hanging = level.add(plant(kHanging));
    struct Spot {
        float x, z;
        int variant;   // 0 ficus, 1 fern, 2 palm
    };
    const Spot spots[] = {
        // In the demo shaft (z ~ 4-6): two in the gallery by the doorway, seven in the conservatory.
        {7.0f, 4.55f, 0}, {8.8f, 5.65f, 1}, {12.2f, 5.45f, 2}, {13.4f, 5.6f, 0}, {15.7f, 5.5f, 0}, {17.0f, 4.45f, 1},
        {18.7f, 5.5f, 0}, {20.2f, 4.5f, 2}, {21.1f, 5.6f, 1},
        // Elsewhere, mostly in corners and beside doors.
        {0.7f, 2.5f, 0}, {3.0f, 9.4f, 1}, {9.3f, 9.3f, 2}, {9.4f, 3.6f, 1},                        // gallery
        {10.7f, 0.6f, 0}, {10.7f, 9.4f, 2}, {21.4f, 0.6f, 1}, {21.4f, 9.4f, 0}, {15.3f, 9.4f, 1},  // conservatory
        {23.0f, 2.2f, 2}, {29.4f, 5.0f, 0}, {26.8f, 9.3f, 1},                                       // archive
        {0.6f, 10.7f, 2}, {13.4f, 10.7f, 0}, {0.6f, 19.4f, 1}, {7.0f, 19.4f, 0}, {4.8f, 19.4f, 2},  // dining hall
        {14.7f, 19.4f, 0}, {29.4f, 19.4f, 2}, {19.6f, 10.7f, 0}, {23.9f, 19.4f, 1}, {26.0f, 15.0f, 0}, // lounge
    };
    Rng rng(0x9A27ull);
    for (const Spot& s : spots) {
        const float turn = rng.unit(), size = rng.range(0.9f, 1.1f);
        level.put(potMesh, place({s.x, 0, s.z}, turn));
        level.put(variants[s.variant], place({s.x, 0, s.z}, turn, size));
    }
    for (vec2 c : {vec2(7.9f, 5.2f), vec2(11.4f, 4.7f), vec2(16.4f, 5.1f), vec2(19.5f, 5.3f), vec2(25.0f, 15.0f)}) {
        const float turn = rng.unit();
        level.put(basketMesh, place({c.x, kCeiling, c.y}, turn));
        level.put(hanging, place({c.x, kCeiling, c.y}, turn));
    }
}

} // namespace

Scene makeDemoLevel()
{
    LevelBuilder level;
    addArchitecture(level);
    addFurniture(level);
    addPlants(level);
    return std::move(level.scene);
}

namespace {

/// An empty benchmark scene with its patches: the demo view's shapes, 10 m apart along +x.
BenchScene benchScene(std::string name)
{
    BenchScene out;
    out.name = std::move(name);
    const DemoView view = demoView();
    out.source = view.source;
    out.receiver = view.receiver;
    out.source.corner = {0.0, 0.3, 5.5};
    out.receiver.corner = {10.0, 0.2, 4.0};
    return out;
}

} // namespace

BenchScene makeFewOccludersScene()
{
    BenchScene out = benchScene("few-occluders");
    // A wall with a 0.9 m doorway at x = 3, four square pillars, a wall with a window at x = 8.
    out.scene.addMeshInstance(wall("wall_door", {3.0f, 0.0f}, {3.0f, 10.0f}, {{4.55f, 5.45f, 0.0f, 2.1f}}));
    out.scene.addMeshInstance(wall("wall_window", {8.0f, 0.0f}, {8.0f, 10.0f}, {{4.2f, 5.8f, 0.9f, 1.9f}}));
    for (int k = 0; k < 4; ++k) {
        Builder b("pillar_square");
        const float x = 4.0f + 0.9f * float(k), z = k % 2 ? 4.6f : 5.3f;
        box(b, {x - 0.15f, 0.0f, z - 0.15f}, {x + 0.15f, kCeiling, z + 0.15f});
        out.scene.addMeshInstance(std::move(b.mesh));
    }
    return out;
}

BenchScene makeDenseMeshScene()
{
    BenchScene out = benchScene("dense-mesh");
    // A lumpy sphere (a scanned statue stand-in) of 2 x 130 x 266 = 69,160 triangles of about
    // 2 cm, in the middle of the shaft: r = 0.75 (1 + 0.12 sin(5 theta) sin(7 phi)).
    constexpr int kStacks = 131, kSlices = 266;
    const glm::dvec3 centre(5.0, 1.2, 5.0);
    auto point = [&](int i, int j) {
        const glm::dvec2 polar = cosSin(0.5 * i / kStacks), around = cosSin(double(j) / kSlices);
        const double lump = 1.0 + 0.12 * cosSin(2.5 * i / kStacks - 0.25).y * cosSin(7.0 * j / kSlices).y;
        const double r = 0.75 * lump;
        return vec3(centre + r * glm::dvec3(polar.y * around.x, polar.x, polar.y * around.y));
    };
    Builder b("statue", /*watertight=*/false);   // an imported mesh carries no watertight flag
    for (int i = 0; i < kStacks; ++i)
        for (int j = 0; j < kSlices; ++j) {
            const vec3 p00 = point(i, j), p01 = point(i, j + 1), p10 = point(i + 1, j), p11 = point(i + 1, j + 1);
            if (i > 0)
                b.triangle(p00, p01, p11);
            if (i + 1 < kStacks)
                b.triangle(p00, p11, p10);
        }
    out.scene.addMeshInstance(std::move(b.mesh));
    return out;
}

DemoView demoView()
{
    DemoView view;
    view.source.corner = {2.0, 0.3, 5.5};
    view.source.u = {0.0, 0.0, -1.0};
    view.source.v = {0.0, 1.6, 0.0};
    view.receiver.corner = {21.85, 0.2, 4.0};
    view.receiver.u = {0.0, 0.0, 2.0};
    view.receiver.v = {0.0, 2.0, 0.0};
    view.source.na = view.source.nb = 32;
    view.receiver.na = view.receiver.nb = 32;
    return view;
}

} // namespace sightline::demo
