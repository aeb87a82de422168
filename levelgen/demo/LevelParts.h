#pragma once
// Building blocks of the generated levels (internal to levelgen/demo): the deterministic random
// generator and angle helper, transforms, a flat-shaded mesh builder, closed primitive solids,
// and architecture (walls with openings, tile grids, door and window casings).
//
// Everything here is arithmetic on floats and doubles with no libm trigonometry and no std
// distributions, so a level built from these parts has bit-identical triangles on every platform.
// Closed parts (box, bevelBox, closed lathes, cylinder, rod, wall) are outward oriented; a mesh
// stays closedAndOutward (visibility/Scene.h) as long as its parts never share an edge.

#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline::demo::parts {

using glm::mat4;
using glm::vec2;
using glm::vec3;

constexpr float kCeiling = 3.2f;   // the demo level's storey height
constexpr float kWall = 0.2f;      // wall thickness

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
    /// Uniform in {lo, ..., hi} (the modulo bias of 64 bits is far below anything a level shows).
    int between(int lo, int hi) { return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1)); }
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

mat4 translate(vec3 t);
mat4 scale(float s);
/// (cos, sin) of an angle given in turns (1 = 360 degrees), by Taylor series in double precision:
/// arithmetic only, so it rounds the same everywhere (libm's sin and cos differ between libraries
/// in the last bit, which would change triangles from one platform to another).
glm::dvec2 cosSin(double turns);
/// Rotation about +Y by `turns` (positive: local +z turns toward world +x); quarter turns exact.
mat4 yaw(float turns);
/// Object -> world for an object standing at `position`, turned by `yawTurns`, scaled by `s`.
mat4 place(vec3 position, float yawTurns = 0.0f, float s = 1.0f);
/// Point at `radius` and angle `turns` on a horizontal circle at height y (angle 0 on +x, a
/// quarter turn on +z).
vec3 onCircle(float radius, float turns, float y);
/// Maps local +Y onto the segment a -> b (length preserved), right-handed.
mat4 along(vec3 a, vec3 b);

// ------------------------------------------------------------------------------ mesh building

/// Accumulates flat-shaded polygons (each polygon gets its own vertices and face normal) under a
/// current affine transform `xf`. Normals are recomputed after transforming, and a mirroring
/// transform has its winding flipped back, so closed parts stay outward oriented.
struct Builder {
    Mesh mesh;
    mat4 xf{1.0f};

    explicit Builder(std::string name, bool watertight = true);

    /// A planar convex polygon given in cyclic order (either winding), turned so that its normal
    /// agrees with `outward`. Repeated points are dropped (a lathe quad on the axis is a triangle).
    void polygon(std::vector<vec3> points, vec3 outward);
    /// A single triangle, wound as given.
    void triangle(vec3 a, vec3 b, vec3 c);
    /// Runs `add` with `m` applied after the current transform.
    void with(const mat4& m, const std::function<void()>& add);

private:
    void emit(std::vector<vec3> p);
};

void box(Builder& b, vec3 lo, vec3 hi);
/// A box with all 12 edges chamfered by `r` (26 faces, 44 triangles): furniture looks made.
void bevelBox(Builder& b, vec3 lo, vec3 hi, float r);
/// Surface of revolution about +Y. `profile` holds (radius, y) points in order around the
/// cross-section, counter-clockwise in the (r, y) half plane (up the outside); when it starts and
/// ends on the axis (r = 0) the solid is closed and outward oriented.
void lathe(Builder& b, std::initializer_list<vec2> profile, int sides);
/// Closed cylinder of radius r about +Y from y0 to y1.
void cylinder(Builder& b, float r, float y0, float y1, int sides);
/// Closed rod of radius r0 at `from` tapering to r1 at `to`.
void rod(Builder& b, vec3 from, vec3 to, float r0, float r1, int sides);

// ------------------------------------------------------------------------------ architecture

struct Opening {
    float s0, s1;   // along the wall, world coordinate on the wall's axis
    float y0, y1;
};

/// A closed wall slab from `a` to `b` (points on the floor, an axis-aligned line running toward
/// +x or +z), `thickness` thick and `height` high, with rectangular openings. The face is cut into
/// the grid spanned by the opening edges; every solid cell gives a front and a back quad, and
/// every cell edge bordering air gives a quad across the thickness, so the slab is closed with no
/// T-junctions.
Mesh wall(const std::string& name, vec2 a, vec2 b, const std::vector<Opening>& openings, float height = kCeiling,
          float thickness = kWall);

/// One-sided grid of `size` m tiles over [lo, hi] (x, z) at height y, facing +Y (facing = 1) or
/// -Y; the last row and column are cut short where the extent is not a multiple of `size`.
Mesh tiles(const std::string& name, vec2 lo, vec2 hi, float y, float facing, float size);

/// Casings (door and window trim) around an opening of the wall from `a` to `wallEnd`, on its local
/// +z face (onlySide = 1), its -z face (-1) or both (0); and window mullions.
void casing(Builder& b, vec2 a, vec2 wallEnd, const Opening& o, bool mullions, float onlySide,
            float wallThickness = kWall);

} // namespace sightline::demo::parts
