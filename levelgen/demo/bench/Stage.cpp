#include "demo/bench/Stage.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

namespace sightline::demo::bench {

Patch standingPatch(glm::dvec3 base, glm::dvec2 facing, double width, double height)
{
    // u x v = width * height * (-u_z, 0, u_x) / width, so u = width * (f_z, 0, -f_x) makes the
    // normal f.
    Patch p;
    p.u = width * glm::dvec3(facing.y, 0.0, -facing.x);
    p.v = {0.0, height, 0.0};
    p.corner = base - 0.5 * p.u;
    p.na = p.nb = 32;
    return p;
}

glm::dvec2 turned(glm::dvec2 d, double turns)
{
    const glm::dvec2 cs = cosSin(turns);
    return {cs.x * d.x + cs.y * d.y, -cs.y * d.x + cs.x * d.y};
}

Stage::Stage(std::uint64_t seed, std::uint64_t kindSalt) : rng(seed * 0x9E3779B97F4A7C15ull ^ kindSalt) {}

void Stage::put(std::uint32_t mesh, const mat4& transform)
{
    scene.instances.push_back(Instance{scene.meshes[mesh].name, mesh, transform});
}

void Stage::setPatches(vec2 from, PatchSize sourceSize, vec2 to, PatchSize receiverSize, float maxYawTurns)
{
    from_ = from;
    to_ = to;
    sourceSize_ = sourceSize;
    receiverSize_ = receiverSize;
    const glm::dvec2 forward = glm::normalize(glm::dvec2(to - from));
    const glm::dvec2 sourceFacing = turned(forward, rng.range(-maxYawTurns, maxYawTurns));
    const glm::dvec2 receiverFacing = turned(-forward, rng.range(-maxYawTurns, maxYawTurns));
    source_ = standingPatch({from.x, sourceSize.bottom, from.y}, sourceFacing, sourceSize.width, sourceSize.height);
    receiver_ = standingPatch({to.x, receiverSize.bottom, to.y}, receiverFacing, receiverSize.width, receiverSize.height);
    // Nothing stands within half a metre of either patch: a designer's patch is in the open.
    for (const auto& [at, size] : {std::pair{from, sourceSize}, std::pair{to, receiverSize}}) {
        const float h = 0.5f * float(size.width) + 0.5f;
        take(Rect::around(at, vec2(h)));
    }
}

vec2 Stage::side() const
{
    const vec2 d = glm::normalize(to_ - from_);
    return {d.y, -d.x};
}

float Stage::length() const { return glm::length(to_ - from_); }

float Stage::halfWidth(float t) const
{
    return 0.5f * float((1.0 - t) * sourceSize_.width + t * receiverSize_.width);
}

vec2 Stage::heightRange(float t) const
{
    const double lo = (1.0 - t) * sourceSize_.bottom + t * receiverSize_.bottom;
    const double hi = (1.0 - t) * (sourceSize_.bottom + sourceSize_.height) + t * (receiverSize_.bottom + receiverSize_.height);
    return {float(lo), float(hi)};
}

bool Stage::isFree(const Rect& r) const
{
    return std::none_of(taken_.begin(), taken_.end(), [&](const Rect& t) { return t.overlaps(r); });
}

void Stage::reserveShaft(float margin)
{
    const int steps = std::max(2, int(std::ceil(length() / 0.5f)));
    for (int k = 0; k <= steps; ++k) {
        const float t = float(k) / float(steps);
        take(Rect::around(along(t), vec2(halfWidth(t) + margin)));
    }
}

BenchScene Stage::finish(std::string layout) &&
{
    BenchScene out;
    out.scene = std::move(scene);
    out.source = source_;
    out.receiver = receiver_;
    out.layout = std::move(layout);
    return out;
}

} // namespace sightline::demo::bench
