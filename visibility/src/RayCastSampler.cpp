#include "visibility/RayCastSampler.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <limits>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <utility>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "base/Error.h"
#include "visibility/ExactSegment.h"
#include "raycast/RayPackets.h"

namespace sightline {

namespace {

/// The float ray Embree traverses, org + t dir with org = fl(R) and dir = fl(S - R), strays from
/// the exact segment by at most (|R| + |S - R|) float epsilons per coordinate; boxes are widened
/// by four times that (the float unit roundoff is 2^-24).
constexpr double kStrayPerMetre = 4.0 / 16777216.0;

void onEmbreeError(void* user, RTCError, const char* message)
{
    static_cast<std::string*>(user)->assign(message ? message : "unknown Embree error");
}

double maxAbs(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

} // namespace

struct RayCastScene::Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::string error;
    std::vector<glm::vec3> vertices;   ///< 3 per triangle: the exact float world values
    std::size_t triangles = 0;
    bool fastBuild = false;
    double pad = 0.0;                  ///< every box is widened by this much (metres)
    double buildMs = 0.0;
    mutable std::shared_mutex lock;    ///< sampling shares it; a wider rebuild takes it alone

    ~Embree() { release(); }

    void release()
    {
        if (scene)
            rtcReleaseScene(scene);
        if (device)
            rtcReleaseDevice(device);
        scene = nullptr, device = nullptr;
    }

    glm::dvec3 vertex(std::size_t k) const { return glm::dvec3(vertices[k]); }

    /// Builds the BVH with boxes widened by `widening`.
    void build(double widening)
    {
        release();
        const auto start = std::chrono::steady_clock::now();
        pad = widening;
        device = rtcNewDevice(nullptr);
        if (!device)
            throw Error("Embree: cannot create a device (" + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
        rtcSetDeviceErrorFunction(device, onEmbreeError, &error);
        scene = rtcNewScene(device);
        rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);   // conservative box tests
        rtcSetSceneBuildQuality(scene, fastBuild ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_HIGH);
        if (triangles > 0) {
            RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(geometry, unsigned(triangles));
            rtcSetGeometryUserData(geometry, this);
            rtcSetGeometryBoundsFunction(geometry, &Embree::bounds, nullptr);
            rtcSetGeometryIntersectFunction(geometry, &Embree::intersect);
            rtcSetGeometryOccludedFunction(geometry, &Embree::occluded);
            rtcCommitGeometry(geometry);
            rtcAttachGeometry(scene, geometry);
            rtcReleaseGeometry(geometry);
        }
        rtcCommitScene(scene);
        if (!error.empty())
            throw Error("Embree: " + error);
        buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }

    /// Widens the boxes (rebuilds) when a call's float rays may stray `needed` metres from its
    /// exact segments, more than the build allowed for.
    void cover(double needed)
    {
        {
            std::shared_lock check(lock);
            if (needed <= pad)
                return;
        }
        std::unique_lock rebuild(lock);
        if (needed > pad)
            build(2.0 * needed);
    }

    static void bounds(const RTCBoundsFunctionArguments* args)
    {
        const Embree& self = *static_cast<const Embree*>(args->geometryUserPtr);
        const glm::vec3* v = &self.vertices[3 * std::size_t(args->primID)];
        const glm::vec3 lo = glm::min(v[0], glm::min(v[1], v[2])), hi = glm::max(v[0], glm::max(v[1], v[2]));
        // Widened in double, then rounded outwards to float.
        const auto down = [](double x) { return std::nextafter(float(x), -std::numeric_limits<float>::infinity()); };
        const auto up = [](double x) { return std::nextafter(float(x), std::numeric_limits<float>::infinity()); };
        RTCBounds* b = args->bounds_o;
        b->lower_x = down(double(lo.x) - self.pad), b->lower_y = down(double(lo.y) - self.pad);
        b->lower_z = down(double(lo.z) - self.pad);
        b->upper_x = up(double(hi.x) + self.pad), b->upper_y = up(double(hi.y) + self.pad);
        b->upper_z = up(double(hi.z) + self.pad);
    }

    /// What one receiver sample's rays carry to the primitive test: their exact common start and
    /// directions, by source index (the ray's id). Embree passes this context (its first member)
    /// to every callback of the call.
    struct SegmentContext {
        RTCIntersectContext base;
        const Embree* self = nullptr;
        glm::dvec3 receiverEnd{0.0};
        const glm::dvec3* directions = nullptr;   ///< q - p
        /// Packets from the source: each ray's own receiver end, by id (receiverEnd unused).
        const glm::dvec3* ends = nullptr;
    };

    static void occluded(const RTCOccludedFunctionNArguments* args)
    {
        const auto* context = reinterpret_cast<const SegmentContext*>(args->context);
        const Embree& self = *context->self;
        const std::size_t t = 3 * std::size_t(args->primID);
        if (context->ends) {
            // Rays from the source: each lane seen from its own receiver end, as above.
            for (unsigned i = 0; i < args->N; ++i) {
                if (args->valid[i] != -1)
                    continue;
                const unsigned id = RTCRayN_id(args->ray, args->N, i);
                const TriangleSeenFrom triangle(context->ends[id], self.vertex(t), self.vertex(t + 1), self.vertex(t + 2));
                const glm::dvec3& d = context->directions[id];
                std::int64_t hit = 0;
                raycast::crossedLanes(triangle, &d.x, &d.y, &d.z, 1, &hit);
                if (hit)
                    RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
            }
            return;
        }
        // The rays of a call share their receiver end: what depends on it and the triangle once.
        const TriangleSeenFrom triangle(context->receiverEnd, self.vertex(t), self.vertex(t + 1), self.vertex(t + 2));
        constexpr unsigned kMax = 16;
        alignas(32) double dx[kMax], dy[kMax], dz[kMax];
        alignas(32) std::int64_t hit[kMax];
        unsigned lane[kMax];
        for (unsigned first = 0; first < args->N; first += kMax) {
            int count = 0;
            for (unsigned i = first; i < std::min(args->N, first + kMax); ++i) {
                if (args->valid[i] != -1)
                    continue;
                const glm::dvec3& d = context->directions[RTCRayN_id(args->ray, args->N, i)];
                dx[count] = d.x, dy[count] = d.y, dz[count] = d.z;
                lane[count++] = i;
            }
            raycast::crossedLanes(triangle, dx, dy, dz, count, hit);
            for (int k = 0; k < count; ++k)
                if (hit[k])
                    RTCRayN_tfar(args->ray, args->N, lane[k]) = -std::numeric_limits<float>::infinity();
        }
    }

    /// Never called (only occlusion is queried); Embree requires one.
    static void intersect(const RTCIntersectFunctionNArguments*) {}
};

RayCastScene::RayCastScene(const Scene& scene) : RayCastScene(worldTriangles(scene)) {}

RayCastScene::RayCastScene(const WorldTriangles& triangles, bool fastBuild) : embree_(std::make_unique<Embree>())
{
    validateCoordinates(triangles, "scene");
    embree_->vertices = triangles.vertices;
    embree_->triangles = triangles.size();
    embree_->fastBuild = fastBuild;
    // Wide enough for rays between any points of the scene's box and as far again beyond it.
    double extent = 0.0;
    for (const glm::vec3& v : triangles.vertices)
        extent = std::max(extent, maxAbs(glm::dvec3(v)));
    embree_->build(kStrayPerMetre * 3.0 * extent);
}

RayCastScene::~RayCastScene() = default;

std::size_t RayCastScene::triangleCount() const { return embree_->triangles; }
double RayCastScene::buildMilliseconds() const { return embree_->buildMs; }

HiddenSampleMap RayCastScene::sample(const Patch& source, const Patch& receiver, const RayCastOptions& options) const
{
    validatePatchPair(source, receiver);
    HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
    sampleUnblocked(source, receiver, map, options);
    return map;
}

namespace {

/// Lane k of a packet: the float ray org + t dir, 0 <= t <= 1, with `id` (by which the call's
/// context finds its exact segment).
void setLane(RTCRay16& rays, int k, const glm::vec3& org, const glm::vec3& dir, unsigned id)
{
    rays.org_x[k] = org.x, rays.org_y[k] = org.y, rays.org_z[k] = org.z;
    rays.dir_x[k] = dir.x, rays.dir_y[k] = dir.y, rays.dir_z[k] = dir.z;
    rays.tnear[k] = 0.0f;
    rays.tfar[k] = 1.0f;
    rays.time[k] = 0.0f;
    rays.mask[k] = 0xffffffffu;
    rays.id[k] = id;
    rays.flags[k] = 0;
}

} // namespace

/// One sampleUnblocked call: the pair's exact sample ends and the map it fills, with one method
/// per traversal (from each receiver sample to its source samples, or from each source sample to
/// a block of 4x4 receiver samples).
struct RayCastScene::UnblockedCall {
    const Embree& embree;
    RTCScene scene;
    const Patch& source;
    const RayCastOptions& options;
    const raycast::SampleEnds& sampleEnds;
    HiddenSampleMap& map;
    const int S;
    const std::vector<int> order;   ///< source samples in packet order
    std::atomic<std::uint64_t> cast{0};

    UnblockedCall(const Embree& e, const Patch& pairSource, const RayCastOptions& callOptions, const raycast::SampleEnds& ends,
                  HiddenSampleMap& hidden)
        : embree(e), scene(e.scene), source(pairSource), options(callOptions), sampleEnds(ends), map(hidden),
          S(pairSource.sampleCount()), order(raycast::packetOrder(pairSource))
    {
    }

    /// Receiver sample j casts its S rays: origin at the receiver sample, direction to the
    /// source sample (t = 1 at the source), all sharing one origin, hence coherent.
    void castFrom(int j)
    {
        const glm::dvec3 end = sampleEnds.receiverEnd(j);
        const glm::dvec3 shift = options.jitter.shift(source, j);
        Embree::SegmentContext context;
        rtcInitIntersectContext(&context.base);
        context.base.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        context.self = &embree;
        context.receiverEnd = end;
        thread_local std::vector<glm::dvec3> directions;
        directions.resize(std::size_t(S));
        for (int i = 0; i < S; ++i)
            directions[std::size_t(i)] = sampleEnds.source[std::size_t(i)] + shift - end;
        context.directions = directions.data();
        auto bits = map.row(j);
        cast += options.packets ? castPacketsFrom(glm::vec3(end), directions, bits, context)
                                : castSinglesFrom(glm::vec3(end), directions, bits, context);
    }

    std::uint64_t castPacketsFrom(const glm::vec3& org, const std::vector<glm::dvec3>& directions, std::span<std::uint64_t> bits,
                                  Embree::SegmentContext& context) const
    {
        std::uint64_t rowCast = 0;
        alignas(64) RTCRay16 rays;
        alignas(64) int valid[16];
        for (int first = 0; first < S; first += 16) {
            int lanes = 0;
            for (int k = 0; k < 16; ++k) {
                const int i = first + k < S ? order[std::size_t(first + k)] : S;
                valid[k] = i < S && !blockedIn(bits, i) ? -1 : 0;
                lanes += valid[k] != 0;
                const glm::vec3 dir = i < S ? glm::vec3(directions[std::size_t(i)]) : glm::vec3(1.0f);
                setLane(rays, k, org, dir, unsigned(i < S ? i : 0));
            }
            if (lanes == 0)
                continue;
            rowCast += std::uint64_t(lanes);
            rtcOccluded16(valid, scene, &context.base, &rays);
            for (int k = 0; k < 16 && first + k < S; ++k)
                if (valid[k] && rays.tfar[k] < 0.0f) {
                    const int i = order[std::size_t(first + k)];
                    bits[std::size_t(i >> 6)] |= std::uint64_t(1) << (i & 63);
                }
        }
        return rowCast;
    }

    std::uint64_t castSinglesFrom(const glm::vec3& org, const std::vector<glm::dvec3>& directions, std::span<std::uint64_t> bits,
                                  Embree::SegmentContext& context) const
    {
        std::uint64_t rowCast = 0;
        for (int i = 0; i < S; ++i) {
            if (blockedIn(bits, i))
                continue;
            ++rowCast;
            const glm::vec3 dir(directions[std::size_t(i)]);
            RTCRay ray{};
            ray.org_x = org.x, ray.org_y = org.y, ray.org_z = org.z;
            ray.dir_x = dir.x, ray.dir_y = dir.y, ray.dir_z = dir.z;
            ray.tnear = 0.0f, ray.tfar = 1.0f, ray.mask = 0xffffffffu, ray.id = unsigned(i);
            rtcOccluded1(scene, &context.base, &ray);
            if (ray.tfar < 0.0f)
                bits[std::size_t(i >> 6)] |= std::uint64_t(1) << (i & 63);
        }
        return rowCast;
    }

    static bool blockedIn(std::span<const std::uint64_t> bits, int i) { return (bits[std::size_t(i >> 6)] >> (i & 63)) & 1u; }

    /// Packets from each source sample to a block of 4x4 receiver samples `js`.
    void castFromSource(const std::vector<int>& js)
    {
        glm::dvec3 ends[16], shifts[16], toSource[16];
        for (std::size_t k = 0; k < js.size(); ++k)
            ends[k] = sampleEnds.receiverEnd(js[k]), shifts[k] = options.jitter.shift(source, js[k]);
        Embree::SegmentContext context;
        rtcInitIntersectContext(&context.base);
        context.base.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        context.self = &embree;
        context.directions = toSource;
        context.ends = ends;
        std::uint64_t blockCast = 0;
        alignas(64) RTCRay16 rays{};   // inactive lanes keep whatever they held: Embree skips them
        alignas(64) int valid[16];
        const std::uint64_t* rows[16];
        for (std::size_t k = 0; k < js.size(); ++k)
            rows[k] = map.row(js[k]).data();
        for (int i = 0; i < S; ++i) {
            // The block's lanes still open for this source sample; a packet only where some are
            // (after the float pass most are closed, and building a packet cost more than
            // skipping it).
            const std::size_t word = std::size_t(i >> 6);
            const std::uint64_t bit = std::uint64_t(1) << (i & 63);
            int lanes = 0;
            for (std::size_t k = 0; k < 16; ++k) {
                valid[k] = k < js.size() && !(rows[k][word] & bit) ? -1 : 0;
                lanes += valid[k] != 0;
            }
            if (lanes == 0)
                continue;
            for (std::size_t k = 0; k < js.size(); ++k) {
                if (!valid[k])
                    continue;
                // The reference's direction, (source sample + shift) - receiver end, and the ray
                // back from that source end: within the widening's bound of the exact segment.
                const glm::dvec3 start = sampleEnds.source[std::size_t(i)] + shifts[k];
                toSource[k] = start - ends[k];
                setLane(rays, int(k), glm::vec3(start), glm::vec3(-toSource[k]), unsigned(k));
            }
            blockCast += std::uint64_t(lanes);
            rtcOccluded16(valid, scene, &context.base, &rays);
            for (std::size_t k = 0; k < js.size(); ++k)
                if (valid[k] && rays.tfar[k] < 0.0f)
                    map.setBlocked(js[k], i);
        }
        cast += blockCast;
    }

    /// Every receiver sample (or the options' subset), over the threads.
    void run(const Patch& receiver)
    {
        const std::vector<int>* subset = options.receiverSubset;
        if (options.fromSource && options.packets) {
            const std::vector<std::vector<int>> blocks = raycast::receiverBlocks(receiver, subset);
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 1), [&](const auto& range) {
                for (std::size_t b = range.begin(); b != range.end(); ++b)
                    castFromSource(blocks[b]);
            });
            return;
        }
        const int receivers = subset ? int(subset->size()) : receiver.sampleCount();
        tbb::parallel_for(tbb::blocked_range<int>(0, receivers, 16), [&](const tbb::blocked_range<int>& range) {
            for (int k = range.begin(); k != range.end(); ++k) {
                const int j = subset ? (*subset)[std::size_t(k)] : k;
                if (j < 0 || j >= receiver.sampleCount())
                    throw Error("RayCastScene::sampleUnblocked: receiver sample " + std::to_string(j) + " is outside the grid");
                castFrom(j);
            }
        });
    }
};

std::uint64_t RayCastScene::sampleUnblocked(const Patch& source, const Patch& receiver, HiddenSampleMap& map,
                                            const RayCastOptions& options) const
{
    if (map.sourceCount() != source.sampleCount() || map.receiverNa() != receiver.na || map.receiverNb() != receiver.nb)
        throw Error("RayCastScene::sampleUnblocked: map dimensions do not match the patches");
    // A bumpy receiver (§8): each ray starts at its displaced sample. All-zero heights are the
    // flat patch and take the flat path unchanged. Checked even when nothing can block.
    const raycast::SampleEnds sampleEnds(source, receiver, options.heights);   // positions in double (docs/design.md §2)
    if (embree_->triangles == 0)
        return 0;
    // The boxes must cover this call's float rays: widen (rebuild) first if its patches lie
    // beyond what the build allowed for.
    double farthest = 0.0, longest = 0.0;
    for (int k = 0; k < 4; ++k) {
        const glm::dvec3 sc = source.cornerPoint(k);
        const glm::dvec3 rc = receiver.cornerPoint(k);
        farthest = std::max({farthest, maxAbs(sc), maxAbs(rc)});
        for (int l = 0; l < 4; ++l)
            longest = std::max(longest, maxAbs(rc - (source.corner + double(l & 1) * source.u + double(l >> 1) * source.v)));
    }
    if (sampleEnds.bumpy)
        for (int j = 0; j < receiver.sampleCount(); ++j)
            farthest = std::max(farthest, maxAbs(sampleEnds.receiverEnd(j)));
    // Jitter moves a source sample by under a cell.
    embree_->cover(kStrayPerMetre * (farthest + 2.0 * longest + maxAbs(source.u) + maxAbs(source.v)));
    std::shared_lock lock(embree_->lock);
    UnblockedCall call(*embree_, source, options, sampleEnds, map);
    if (options.threads > 0) {
        tbb::task_arena arena(options.threads);
        arena.execute([&] { call.run(receiver); });
    } else {
        call.run(receiver);
    }
    if (!embree_->error.empty())
        throw Error("Embree: " + embree_->error);
    return call.cast.load();
}

namespace {

/// `count` segments in packets of 16: `fill(k, i)` puts segment i's exact ends in the context's
/// arrays at lane k and returns its float ray (i == count for an idle lane, which it fills
/// harmlessly); blocked[i] gets the packet's answer.
template <typename Fill>
void castPackets(RTCScene scene, RTCIntersectContext* context, std::size_t count, Fill&& fill, std::uint8_t* blocked)
{
    alignas(64) RTCRay16 rays;
    alignas(64) int valid[16];
    for (std::size_t first = 0; first < count; first += 16) {
        for (int k = 0; k < 16; ++k) {
            const std::size_t i = std::min(first + std::size_t(k), count);
            valid[k] = i < count ? -1 : 0;
            const auto [org, dir] = fill(k, i);
            setLane(rays, k, org, dir, unsigned(k));
        }
        rtcOccluded16(valid, scene, context, &rays);
        for (int k = 0; k < 16 && first + std::size_t(k) < count; ++k)
            blocked[first + std::size_t(k)] = rays.tfar[k] < 0.0f ? 1 : 0;
    }
}

} // namespace

void RayCastScene::segmentsBlocked(const glm::dvec3& start, std::span<const glm::dvec3> ends, std::uint8_t* blocked) const
{
    std::fill(blocked, blocked + ends.size(), std::uint8_t(0));
    if (embree_->triangles == 0 || ends.empty())
        return;
    double farthest = maxAbs(start), longest = 0.0;
    for (const glm::dvec3& end : ends)
        farthest = std::max(farthest, maxAbs(end)), longest = std::max(longest, maxAbs(end - start));
    embree_->cover(kStrayPerMetre * (farthest + 2.0 * longest));
    std::shared_lock lock(embree_->lock);
    Embree::SegmentContext context;
    rtcInitIntersectContext(&context.base);
    context.base.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    context.self = embree_.get();
    context.receiverEnd = start;   // every lane is tested from the shared start
    glm::dvec3 directions[16];
    context.directions = directions;
    const glm::vec3 org(start);
    castPackets(embree_->scene, &context.base, ends.size(), [&](int k, std::size_t i) {
        directions[k] = i < ends.size() ? ends[i] - start : glm::dvec3(1.0, 0.0, 0.0);
        return std::pair{org, glm::vec3(directions[k])};
    }, blocked);
    if (!embree_->error.empty())
        throw Error("Embree: " + embree_->error);
}

void RayCastScene::segmentsBlocked(std::span<const glm::dvec3> starts, std::span<const glm::dvec3> ends,
                                   std::uint8_t* blocked) const
{
    if (starts.size() != ends.size())
        throw Error("RayCastScene::segmentsBlocked: as many starts as ends are needed");
    std::fill(blocked, blocked + ends.size(), std::uint8_t(0));
    if (embree_->triangles == 0 || ends.empty())
        return;
    double farthest = 0.0, longest = 0.0;
    for (std::size_t i = 0; i < ends.size(); ++i)
        farthest = std::max({farthest, maxAbs(starts[i]), maxAbs(ends[i])}),
        longest = std::max(longest, maxAbs(ends[i] - starts[i]));
    embree_->cover(kStrayPerMetre * (farthest + 2.0 * longest));
    std::shared_lock lock(embree_->lock);
    Embree::SegmentContext context;
    rtcInitIntersectContext(&context.base);
    context.self = embree_.get();
    glm::dvec3 from[16], directions[16];
    context.ends = from;   // each lane tested from its own start
    context.directions = directions;
    castPackets(embree_->scene, &context.base, ends.size(), [&](int k, std::size_t i) {
        from[k] = i < ends.size() ? starts[i] : glm::dvec3(0.0);
        directions[k] = i < ends.size() ? ends[i] - starts[i] : glm::dvec3(1.0, 0.0, 0.0);
        return std::pair{glm::vec3(from[k]), glm::vec3(directions[k])};
    }, blocked);
    if (!embree_->error.empty())
        throw Error("Embree: " + embree_->error);
}

} // namespace sightline
