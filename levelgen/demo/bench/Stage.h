#pragma once
// A bench scene under construction (internal): the scene with its meshes stored once and placed by
// instances, the patch pair and the line between them, and the floor space already taken, so that
// generators can put things along and across the shaft on purpose and keep everything else out of
// it and out of each other.

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "demo/BenchScenes.h"
#include "demo/LevelParts.h"

namespace sightline::demo::bench {

using namespace parts;

/// Axis-aligned floor rectangle, x and z.
struct Rect {
    vec2 lo, hi;

    bool overlaps(const Rect& o) const { return lo.x < o.hi.x && o.lo.x < hi.x && lo.y < o.hi.y && o.lo.y < hi.y; }
    bool contains(const Rect& o) const { return lo.x <= o.lo.x && lo.y <= o.lo.y && o.hi.x <= hi.x && o.hi.y <= hi.y; }
    Rect grown(float m) const { return {lo - vec2(m), hi + vec2(m)}; }
    static Rect around(vec2 centre, vec2 half) { return {centre - half, centre + half}; }
};

/// A vertical patch `width` x `height` whose lower edge is centred on `base`, its normal the
/// horizontal unit `facing` (x, z). u runs along the floor, v straight up.
Patch standingPatch(glm::dvec3 base, glm::dvec2 facing, double width, double height);

/// `d` turned about +Y by `turns` (as parts::yaw turns: +z toward +x).
glm::dvec2 turned(glm::dvec2 d, double turns);

struct PatchSize {
    double width, height, bottom;   ///< metres; bottom is the lower edge's height above y = 0
};

class Stage {
public:
    Stage(std::uint64_t seed, std::uint64_t kindSalt);

    Rng rng;
    Scene scene;

    std::uint32_t add(Mesh mesh) { return scene.addMesh(std::move(mesh)); }
    void put(std::uint32_t mesh, const mat4& transform);
    void putNew(Mesh mesh, const mat4& transform = mat4(1.0f)) { put(add(std::move(mesh)), transform); }

    /// Stands the source at `from` and the receiver at `to` (floor points x, z), each turned from
    /// facing the other by up to `maxYawTurns` either way, and keeps the floor around them clear.
    void setPatches(vec2 from, PatchSize sourceSize, vec2 to, PatchSize receiverSize, float maxYawTurns);
    const Patch& source() const { return source_; }
    const Patch& receiver() const { return receiver_; }

    /// The floor point at fraction t of the way from the source's base to the receiver's, `lateral`
    /// metres to its left (seen from the source; +side()).
    vec2 along(float t, float lateral = 0.0f) const { return from_ + t * (to_ - from_) + lateral * side(); }
    vec2 side() const;
    float length() const;   ///< between the two patch bases
    /// Half the shaft's width across the floor line at t (the patches' half widths interpolated).
    float halfWidth(float t) const;
    /// The shaft's height range at t (interpolated from the patches' lower and upper edges).
    vec2 heightRange(float t) const;

    bool isFree(const Rect& r) const;
    void take(const Rect& r) { taken_.push_back(r); }
    /// Reserves the floor under the shaft, widened by `margin`, for what is put there on purpose.
    void reserveShaft(float margin);

    BenchScene finish(std::string layout) &&;

private:
    Patch source_, receiver_;
    vec2 from_{0.0f}, to_{0.0f};
    PatchSize sourceSize_{}, receiverSize_{};
    std::vector<Rect> taken_;
};

} // namespace sightline::demo::bench
