#include "ProvenRayCaster.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <ctime>
#include <cmath>
#include <limits>
#include <mutex>
#include <numeric>
#include <string>
#include <utility>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "HitProof.h"
#include "../bitmask/Strategy.h"
#include "RayPackets.h"
#include "base/Error.h"
#include "visibility/ExactSegment.h"
#include "visibility/ReceiverHeights.h"

namespace sightline::raycast {

namespace {

void onEmbreeError(void* user, RTCError, const char* message)
{
    static_cast<std::string*>(user)->assign(message ? message : "unknown Embree error");
}

/// Triangles whose longest edge rounds up to the same power of two share an Embree geometry, so
/// a hit's geomID gives the proof its edge bound without touching the triangle.
int sizeClass(double longestEdge)
{
    int exponent = 0;
    std::frexp(longestEdge, &exponent);   // longestEdge < 2^exponent
    return exponent;
}

/// The proof for a packet's 16 lanes at once (their hits, SoA): a bit per lane proven. Lanes
/// without a hit must have `edge` 0 and are masked off by the caller.
__attribute__((target_clones("avx512f", "avx2", "default"))) std::uint32_t
provenLanes(const RTCRayHit16& rh, const float* edge, float vertexError)
{
    alignas(64) int proven[16];
    for (int k = 0; k < 16; ++k)
        proven[k] = provenCrossing({rh.ray.org_x[k], rh.ray.org_y[k], rh.ray.org_z[k], rh.ray.dir_x[k], rh.ray.dir_y[k],
                                    rh.ray.dir_z[k], rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k], rh.hit.u[k],
                                    rh.hit.v[k], rh.ray.tfar[k]},
                                   edge[k], vertexError);
    std::uint32_t mask = 0;
    for (int k = 0; k < 16; ++k)
        mask |= std::uint32_t(proven[k] != 0) << k;
    return mask;
}

/// This thread's processor time: the probe between the two traversals compares work, not
/// waits (the machine may be shared).
std::uint64_t threadNanoseconds()
{
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return std::uint64_t(now.tv_sec) * 1000000000u + std::uint64_t(now.tv_nsec);
}

/// One hit counted per task, added to the call's totals once.
struct Tally {
    std::uint64_t rays = 0, proven = 0, exact = 0, contradictions = 0;
};

} // namespace

struct ProvenRayCaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::string error;
    double buildMs = 0.0;
    glm::dvec3 origin{0.0};               ///< the local frame's origin (world)
    float vertexError = 0.0f;             ///< largest |fl(v - origin) - (v - origin)|, metres
    std::vector<glm::vec3> world;         ///< the file's values, 3 per world triangle
    std::vector<float> classEdge;         ///< by geomID: bound on its triangles' edges
    std::vector<std::uint32_t> classFirst;   ///< by geomID: its first entry of `worldOf`
    std::vector<std::uint32_t> worldOf;      ///< float triangle (class-sorted) -> world triangle
    bool empty = true;

    ~Impl()
    {
        if (scene)
            rtcReleaseScene(scene);
        if (device)
            rtcReleaseDevice(device);
    }

    std::uint32_t worldTriangle(unsigned geomID, unsigned primID) const { return worldOf[classFirst[geomID] + primID]; }

    /// The contract's double test, exactly as the reference computes it: the receiver end and
    /// the direction to the source end (RayCastSampler.cpp).
    bool crossesExactly(std::uint32_t t, const glm::dvec3& receiverEnd, const glm::dvec3& toSource) const
    {
        const glm::vec3* v = &world[3 * std::size_t(t)];
        const TriangleSeenFrom triangle(receiverEnd, glm::dvec3(v[0]), glm::dvec3(v[1]), glm::dvec3(v[2]));
        std::int64_t hit = 0;
        crossedLanes(triangle, &toSource.x, &toSource.y, &toSource.z, 1, &hit);
        return hit != 0;
    }

    /// What the occlusion filter needs: the rays' exact ends (by ray id) and the task's counters.
    struct FilterContext {
        RTCIntersectContext base;
        const Impl* self = nullptr;
        const glm::dvec3* receiverEnds = nullptr;   ///< by ray id
        const glm::dvec3* toSources = nullptr;      ///< by ray id
        bool verify = false;
        Tally* tally = nullptr;
        /// Packets: the hit each lane stopped at, by ray id, proven after the call; hits closer
        /// to an end than `endDistance` (by ray id, in t) are passed over.
        RTCRayHit16* deferred = nullptr;
        float* stopDistance = nullptr;   ///< by ray id: t of the hit it stopped at (Embree then sets tfar to -inf)
        const float* endDistance = nullptr;
    };

    /// Keeps a reported hit only where the contract says the segment crosses the triangle: proven
    /// from the hit (HitProof.h), or by the double test.
    static void filter(const RTCFilterFunctionNArguments* args)
    {
        const auto* context = reinterpret_cast<const FilterContext*>(args->context);
        const Impl& self = *context->self;
        if (RTCRayHit16* stop = context->deferred) {
            // Accept the hit and prove it after the call, 16 lanes at once (provenLanes): a
            // filter call is then a few stores. A hit at an end (a patch on a wall) is not a
            // crossing, and would stop the ray; passing over one that is leaves its ray to the
            // confirmation, which is exact.
            for (unsigned k = 0; k < args->N; ++k) {
                if (args->valid[k] != -1)
                    continue;
                const unsigned id = RTCRayN_id(args->ray, args->N, k);
                const float t = RTCRayN_tfar(args->ray, args->N, k), end = context->endDistance[id];
                if (!(t > end && t < 1.0f - end)) {
                    args->valid[k] = 0;
                    continue;
                }
                context->stopDistance[id] = t;
                stop->hit.Ng_x[id] = RTCHitN_Ng_x(args->hit, args->N, k);
                stop->hit.Ng_y[id] = RTCHitN_Ng_y(args->hit, args->N, k);
                stop->hit.Ng_z[id] = RTCHitN_Ng_z(args->hit, args->N, k);
                stop->hit.u[id] = RTCHitN_u(args->hit, args->N, k);
                stop->hit.v[id] = RTCHitN_v(args->hit, args->N, k);
                stop->hit.geomID[id] = RTCHitN_geomID(args->hit, args->N, k);
                stop->hit.primID[id] = RTCHitN_primID(args->hit, args->N, k);
            }
            return;
        }
        for (unsigned k = 0; k < args->N; ++k) {
            if (args->valid[k] != -1)
                continue;
            const unsigned geomID = RTCHitN_geomID(args->hit, args->N, k), primID = RTCHitN_primID(args->hit, args->N, k);
            const ReportedHit hit{RTCRayN_org_x(args->ray, args->N, k), RTCRayN_org_y(args->ray, args->N, k),
                                  RTCRayN_org_z(args->ray, args->N, k), RTCRayN_dir_x(args->ray, args->N, k),
                                  RTCRayN_dir_y(args->ray, args->N, k), RTCRayN_dir_z(args->ray, args->N, k),
                                  RTCHitN_Ng_x(args->hit, args->N, k),  RTCHitN_Ng_y(args->hit, args->N, k),
                                  RTCHitN_Ng_z(args->hit, args->N, k),  RTCHitN_u(args->hit, args->N, k),
                                  RTCHitN_v(args->hit, args->N, k),     RTCRayN_tfar(args->ray, args->N, k)};
            const unsigned id = RTCRayN_id(args->ray, args->N, k);
            if (provenCrossing(hit, self.classEdge[geomID], self.vertexError)) {
                ++context->tally->proven;
                if (context->verify &&
                    !self.crossesExactly(self.worldTriangle(geomID, primID), context->receiverEnds[id], context->toSources[id]))
                    ++context->tally->contradictions;
                continue;
            }
            ++context->tally->exact;
            if (!self.crossesExactly(self.worldTriangle(geomID, primID), context->receiverEnds[id], context->toSources[id]))
                args->valid[k] = 0;
        }
    }
};

ProvenRayCaster::ProvenRayCaster(const WorldTriangles& triangles) : impl_(std::make_unique<Impl>())
{
    const auto start = std::chrono::steady_clock::now();
    Impl& m = *impl_;
    m.world = triangles.vertices;
    const std::size_t T = triangles.size();
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const glm::vec3& v : triangles.vertices)
        lo = glm::min(lo, glm::dvec3(v)), hi = glm::max(hi, glm::dvec3(v));
    if (T > 0)
        m.origin = 0.5 * (lo + hi);

    // Local vertices, their rounding, and each triangle's size class. Triangles of zero area
    // block nothing by the contract (their plane test never has two sides) and stay out.
    std::vector<glm::vec3> local(m.world.size());
    double rounding = 0.0;
    for (std::size_t k = 0; k < m.world.size(); ++k) {
        const glm::dvec3 exact = glm::dvec3(m.world[k]) - m.origin;
        local[k] = glm::vec3(exact);
        const glm::dvec3 off = glm::dvec3(local[k]) - exact;
        rounding = std::max({rounding, std::abs(off.x), std::abs(off.y), std::abs(off.z)});
    }
    // A component-wise bound, as a length, rounded up (and a hair for `exact`'s own rounding).
    m.vertexError = float((std::sqrt(3.0) * rounding + 1e-12 * glm::length(hi - lo)) * (1.0 + 1e-6));
    std::vector<int> classOf(T, 0);
    std::vector<std::uint32_t> kept;
    kept.reserve(T);
    for (std::size_t t = 0; t < T; ++t) {
        const glm::dvec3 a(m.world[3 * t]), b(m.world[3 * t + 1]), c(m.world[3 * t + 2]);
        if (glm::length(glm::cross(b - a, c - a)) == 0.0)
            continue;
        const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        classOf[t] = sizeClass(longest * (1.0 + 1e-6) + 2.0 * double(m.vertexError));
        kept.push_back(std::uint32_t(t));
    }
    std::stable_sort(kept.begin(), kept.end(), [&](std::uint32_t x, std::uint32_t y) { return classOf[x] < classOf[y]; });
    m.worldOf = kept;

    m.device = rtcNewDevice(nullptr);
    if (!m.device)
        throw Error("Embree: cannot create a device (" + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(m.device, onEmbreeError, &m.error);
    m.scene = rtcNewScene(m.device);
    // Flat, not robust; high quality (spatial splits): the build is paid once per scene.
    rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
    for (std::size_t first = 0; first < kept.size();) {
        std::size_t end = first;
        while (end < kept.size() && classOf[kept[end]] == classOf[kept[first]])
            ++end;
        const std::size_t count = end - first;
        RTCGeometry geometry = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree may read 16 bytes past a float3, so the vertex buffer has one element more.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                     3 * sizeof(float), 3 * count + 1));
        auto* indices = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count));
        if (!vertices || !indices)
            throw Error("Embree: out of memory for " + std::to_string(T) + " triangles");
        for (std::size_t k = 0; k < count; ++k)
            for (std::size_t c = 0; c < 3; ++c) {
                const glm::vec3& p = local[3 * std::size_t(kept[first + k]) + c];
                vertices[9 * k + 3 * c] = p.x, vertices[9 * k + 3 * c + 1] = p.y, vertices[9 * k + 3 * c + 2] = p.z;
                indices[3 * k + c] = unsigned(3 * k + c);
            }
        vertices[9 * count] = vertices[9 * count + 1] = vertices[9 * count + 2] = 0.0f;
        rtcSetGeometryOccludedFilterFunction(geometry, &Impl::filter);
        rtcCommitGeometry(geometry);
        const unsigned id = rtcAttachGeometry(m.scene, geometry);
        rtcReleaseGeometry(geometry);
        if (id != m.classEdge.size())
            throw Error("Embree: unexpected geometry id " + std::to_string(id));
        m.classEdge.push_back(std::ldexp(1.0f, classOf[kept[first]]));
        m.classFirst.push_back(std::uint32_t(first));
        first = end;
    }
    rtcCommitScene(m.scene);
    if (!m.error.empty())
        throw Error("Embree: " + m.error);
    m.empty = kept.empty();
    m.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

struct ProvenRayCaster::ModeMemo {
    bitmask::Configuration configuration;
    bool fromSource = false;
    bool packets = true;
    int callsLeft = 0;
};

ProvenRayCaster::~ProvenRayCaster() = default;

double ProvenRayCaster::buildMilliseconds() const { return impl_->buildMs; }

namespace {

/// A group of up to 16 samples of the far patch (receiver samples when rays start at the source,
/// source samples when they start at the receiver), cast together.
constexpr int kLanes = 16;

/// CastMode::Auto times the two traversals against each other only on calls with at least this many items
/// (4x4 blocks, or receiver samples), an eighth of them each.
constexpr std::size_t kModeProbeItems = 32;

/// The extent of a 4x4 block of a patch's samples.
double blockExtent(const Patch& p)
{
    return std::max(glm::length(p.u) * std::min(4.0, double(p.na)) / p.na, glm::length(p.v) * std::min(4.0, double(p.nb)) / p.nb);
}

} // namespace

/// One sampleUnblocked call: its sample ends, the traversals (a packet for the closest hit, or
/// occluded rays through the filter) and their proofs, and Auto's timed choice between them.
class ProvenRayCaster::Call {
public:
    Call(const ProvenRayCaster& caster, const Patch& source, const Patch& receiver, HiddenSampleMap& map,
         const RayCastOptions& options, CastMode mode)
        : caster_(caster), m(*caster.impl_), source_(source), receiver_(receiver), map_(map), options_(options), mode_(mode),
          sampleEnds_(source, receiver, options.heights), S(source.sampleCount()),
          // Rays start where a packet's far ends lie closest together.
          fromSource_(blockExtent(receiver) <= blockExtent(source)), verify(caster.verifyProofs_),
          packets_(mode != CastMode::Occluded)
    {
        // Pass 1 works on items: 4x4 blocks of receiver samples (rays from the source) or single
        // receiver samples (rays from the receiver), each owning its rows of the map.
        if (fromSource_) {
            blocks_ = receiverBlocks(receiver, options.receiverSubset);
        } else if (options.receiverSubset) {
            receivers_ = *options.receiverSubset;
            for (int j : receivers_)
                if (j < 0 || j >= receiver.sampleCount())
                    throw Error("ProvenRayCaster: receiver sample " + std::to_string(j) + " is outside the grid");
        } else {
            receivers_.resize(std::size_t(receiver.sampleCount()));
            std::iota(receivers_.begin(), receivers_.end(), 0);
        }
        items_ = fromSource_ ? blocks_.size() : receivers_.size();
        order_ = packetOrder(source);
    }

    /// Pass 1 over every item, in the mode asked or, for Auto, the one a timed probe (or an
    /// earlier call's) chose.
    void pass();
    bool fromSource() const { return fromSource_; }

private:

    /// One ray by a single traversal, every hit through the filter: true when blocked.
    /// `start`: the ray's first end in the local frame (the source end, or the receiver end).
    bool castSingle(const glm::dvec3& receiverEnd_, const glm::dvec3& toSource, const glm::dvec3& start, bool startAtSource,
                    Tally& tally) const
    {
        Impl::FilterContext context;
        rtcInitIntersectContext(&context.base);
        context.base.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        context.self = &m;
        context.receiverEnds = &receiverEnd_;
        context.toSources = &toSource;
        context.verify = verify;
        context.tally = &tally;
        const glm::vec3 org(start), dir(startAtSource ? -toSource : toSource);
        RTCRay ray{};
        ray.org_x = org.x, ray.org_y = org.y, ray.org_z = org.z;
        ray.dir_x = dir.x, ray.dir_y = dir.y, ray.dir_z = dir.z;
        ray.tnear = 0.0f, ray.tfar = 1.0f, ray.mask = 0xffffffffu, ray.id = 0;
        rtcOccluded1(m.scene, &context.base, &ray);
        return ray.tfar < 0.0f;
    }

    /// The lanes of `stopped` hold in `rh` the hit each ray stopped at (ray and hit, SoA): proven
    /// 16 at once, the rest tested in double, and a ray whose hit that test denies cast again
    /// alone (it may be blocked further on), every hit through the filter. Returns the blocked
    /// lanes as bits.
    std::uint32_t proveStops(const RTCRayHit16& rh, std::uint32_t stopped, const glm::dvec3* ends, const glm::dvec3* dirs,
                             const glm::dvec3* starts, bool startAtSource, Tally& tally) const
    {
        alignas(64) float edge[kLanes];
        for (int k = 0; k < kLanes; ++k)
            edge[k] = (stopped >> k & 1u) != 0 ? m.classEdge[rh.hit.geomID[k]] : 0.0f;
        const std::uint32_t provenMask = provenLanes(rh, edge, m.vertexError) & stopped;
        tally.proven += std::uint64_t(std::popcount(provenMask));
        if (verify)
            for (std::uint32_t p = provenMask; p; p &= p - 1) {
                const int k = std::countr_zero(p);
                if (!m.crossesExactly(m.worldTriangle(rh.hit.geomID[k], rh.hit.primID[k]), ends[k], dirs[k]))
                    ++tally.contradictions;
            }
        std::uint32_t blocked = provenMask;
        for (std::uint32_t rest = stopped & ~provenMask; rest; rest &= rest - 1) {
            const int k = std::countr_zero(rest);
            ++tally.exact;
            if (m.crossesExactly(m.worldTriangle(rh.hit.geomID[k], rh.hit.primID[k]), ends[k], dirs[k]) ||
                castSingle(ends[k], dirs[k], starts[k], startAtSource, tally))
                blocked |= 1u << k;
        }
        return blocked;
    }

    /// 16 rays (lane k: receiver end ends[k], direction to its source end dirs[k]) by one packet
    /// traversal for the closest hit, checked after the call; a lane whose hit neither proof nor
    /// test confirms is cast again alone. Returns the blocked lanes as bits.
    std::uint32_t castPacket(const glm::dvec3* ends, const glm::dvec3* dirs, const glm::dvec3* starts, int lanes,
                             bool startAtSource, Tally& tally) const
    {
        // Only the active lanes are written (Embree skips the others; a whole packet written
        // every time cost 5% of a call on an architectural interior). Zeroed once per thread.
        alignas(64) thread_local RTCRayHit16 rh{};
        alignas(64) int valid[kLanes];
        for (int k = 0; k < kLanes; ++k)
            valid[k] = k < lanes ? -1 : 0;
        for (int k = 0; k < lanes; ++k) {
            const glm::vec3 org(starts[k]), dir(startAtSource ? -dirs[k] : dirs[k]);
            rh.ray.org_x[k] = org.x, rh.ray.org_y[k] = org.y, rh.ray.org_z[k] = org.z;
            rh.ray.dir_x[k] = dir.x, rh.ray.dir_y[k] = dir.y, rh.ray.dir_z[k] = dir.z;
            rh.ray.tnear[k] = 0.0f, rh.ray.tfar[k] = 1.0f, rh.ray.time[k] = 0.0f;
            rh.ray.mask[k] = 0xffffffffu, rh.ray.id[k] = unsigned(k), rh.ray.flags[k] = 0;
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        }
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        rtcIntersect16(valid, m.scene, &context, &rh);
        std::uint32_t hits = 0;
        for (int k = 0; k < lanes; ++k)
            hits |= std::uint32_t(rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID) << k;
        return hits == 0 ? hits : proveStops(rh, hits, ends, dirs, starts, startAtSource, tally);
    }

    /// Up to 16 rays by one rtcOccluded16, every hit through the filter, with Embree's incoherent
    /// traversal (the packet near the root, single rays once it diverges). Returns the blocked
    /// lanes as bits.
    std::uint32_t castOccluded(const glm::dvec3* ends, const glm::dvec3* dirs, const glm::dvec3* starts, int lanes,
                               bool startAtSource, Tally& tally) const
    {
        // The rays, and after the call where each stopped (the hit, and its t put back in tfar).
        alignas(64) thread_local RTCRayHit16 stops{};
        alignas(64) int valid[kLanes];
        alignas(64) float endDistance[kLanes], stopDistance[kLanes];
        for (int k = 0; k < kLanes; ++k)
            valid[k] = k < lanes ? -1 : 0;
        RTCRay16& r = stops.ray;
        for (int k = 0; k < lanes; ++k) {
            const glm::vec3 org(starts[k]), dir(startAtSource ? -dirs[k] : dirs[k]);
            r.org_x[k] = org.x, r.org_y[k] = org.y, r.org_z[k] = org.z;
            r.dir_x[k] = dir.x, r.dir_y[k] = dir.y, r.dir_z[k] = dir.z;
            r.tnear[k] = 0.0f, r.tfar[k] = 1.0f, r.time[k] = 0.0f;
            r.mask[k] = 0xffffffffu, r.id[k] = unsigned(k), r.flags[k] = 0;
            // 0.1 mm: far beyond the float t's error at these lengths, and a crossing that close
            // to an end is left to the confirmation.
            endDistance[k] = float(1e-4 / glm::length(dirs[k]));
        }
        Impl::FilterContext context;
        rtcInitIntersectContext(&context.base);
        context.base.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        context.self = &m;
        context.receiverEnds = ends;
        context.toSources = dirs;
        context.verify = verify;
        context.tally = &tally;
        context.deferred = &stops;
        context.stopDistance = stopDistance;
        context.endDistance = endDistance;
        rtcOccluded16(valid, m.scene, &context.base, &r);
        std::uint32_t stopped = 0;
        for (int k = 0; k < lanes; ++k)
            if (r.tfar[k] < 0.0f) {
                stopped |= 1u << k;
                r.tfar[k] = stopDistance[k];
            }
        return stopped == 0 ? stopped : proveStops(stops, stopped, ends, dirs, starts, startAtSource, tally);
    }

    /// Item `item`'s free rays, `packets` or occluded.
    void castItem(std::size_t item, bool packets, Tally& tally)
    {
        glm::dvec3 ends[kLanes], dirs[kLanes], starts[kLanes];
        int lane[kLanes];
        if (fromSource_) {
            const std::vector<int>& js = blocks_[item];
            glm::dvec3 blockEnds[kLanes], shifts[kLanes];
            const std::uint64_t* rows[kLanes];
            for (std::size_t k = 0; k < js.size(); ++k) {
                blockEnds[k] = receiverEnd(js[k]), shifts[k] = options_.jitter.shift(source_, js[k]);
                rows[k] = std::as_const(map_).row(js[k]).data();
            }
            for (int i = 0; i < S; ++i) {
                const glm::dvec3 sample = sampleEnds_.source[std::size_t(i)];
                const std::size_t word = std::size_t(i >> 6);
                const std::uint64_t bit = std::uint64_t(1) << (i & 63);
                int lanes = 0;
                for (std::size_t k = 0; k < js.size(); ++k) {
                    if (rows[k][word] & bit)
                        continue;
                    ends[lanes] = blockEnds[k];
                    // The reference's expression: (source sample + shift) - receiver end.
                    dirs[lanes] = sample + shifts[k] - blockEnds[k];
                    starts[lanes] = sample + shifts[k] - m.origin;
                    lane[lanes++] = js[k];
                }
                tally.rays += std::uint64_t(lanes);
                if (lanes == 0)
                    continue;
                const std::uint32_t blocked = packets ? castPacket(ends, dirs, starts, lanes, true, tally)
                                                      : castOccluded(ends, dirs, starts, lanes, true, tally);
                for (std::uint32_t hit = blocked; hit; hit &= hit - 1)
                    map_.setBlocked(lane[std::countr_zero(hit)], i);
            }
            return;
        }
        const int j = receivers_[item];
        const glm::dvec3 end = receiverEnd(j), shift = options_.jitter.shift(source_, j), start = end - m.origin;
        for (int first = 0; first < S; first += kLanes) {
            int lanes = 0;
            for (int q = first; q < std::min(S, first + kLanes); ++q) {
                const int i = order_[std::size_t(q)];
                if (map_.blocked(j, i))
                    continue;
                ends[lanes] = end;
                dirs[lanes] = sampleEnds_.source[std::size_t(i)] + shift - end;
                starts[lanes] = start;
                lane[lanes++] = i;
            }
            tally.rays += std::uint64_t(lanes);
            if (lanes == 0)
                continue;
            const std::uint32_t blocked = packets ? castPacket(ends, dirs, starts, lanes, false, tally)
                                                  : castOccluded(ends, dirs, starts, lanes, false, tally);
            for (std::uint32_t hit = blocked; hit; hit &= hit - 1)
                map_.setBlocked(j, lane[std::countr_zero(hit)]);
        }
    }

    /// Casts `list`'s items in parallel; returns the thread time they took (ns) and adds the rays.
    std::uint64_t castAll(const std::vector<std::uint32_t>& list, bool packets, std::uint64_t* raysDone)
    {
        std::atomic<std::uint64_t> cpuNs{0}, listRays{0};
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, list.size(), 1), [&](const auto& range) {
            const std::uint64_t begin = raysDone ? threadNanoseconds() : 0;
            Tally tally;
            for (std::size_t k = range.begin(); k != range.end(); ++k)
                castItem(list[k], packets, tally);
            listRays += tally.rays;
            add(tally);
            if (raysDone)
                cpuNs += threadNanoseconds() - begin;
        });
        if (raysDone)
            *raysDone = listRays.load();
        return cpuNs.load();
    }

    void add(const Tally& t)
    {
        rays += t.rays, proven += t.proven, exactTests += t.exact, contradictions += t.contradictions;
    }
    glm::dvec3 receiverEnd(int j) const { return sampleEnds_.receiverEnd(j); }

    const ProvenRayCaster& caster_;
    const Impl& m;
    const Patch& source_;
    const Patch& receiver_;
    HiddenSampleMap& map_;
    const RayCastOptions& options_;
    const CastMode mode_;
    const SampleEnds sampleEnds_;
    const int S;
    const bool fromSource_;
    const bool verify;
    std::vector<std::vector<int>> blocks_;
    std::vector<int> receivers_;
    std::size_t items_ = 0;
    std::vector<int> order_;

public:
    // What the call counted and chose, for the stats.
    std::atomic<std::uint64_t> rays{0}, proven{0}, exactTests{0}, contradictions{0};
    bool packets_;          ///< the traversal pass 1 used
    bool probed_ = false;   ///< chosen by timing both
};

void ProvenRayCaster::Call::pass()
{
    if (m.empty || items_ == 0)
        return;
    std::vector<std::uint32_t> all(items_);
    std::iota(all.begin(), all.end(), 0u);
    if (mode_ != CastMode::Auto) {
        castAll(all, packets_, nullptr);
        return;
    }
    const bitmask::Configuration configuration{source_, receiver_, options_.jitter.enabled(), sampleEnds_.bumpy};
    {
        std::lock_guard lock(caster_.memoMutex_);
        if (caster_.memo_ && caster_.memo_->callsLeft > 0 && caster_.memo_->fromSource == fromSource_ &&
            bitmask::similarConfiguration(caster_.memo_->configuration, configuration)) {
            --caster_.memo_->callsLeft;
            packets_ = caster_.memo_->packets;
            castAll(all, packets_, nullptr);
            return;
        }
    }
    // Time both ways on a few items (their rows are final either way), by thread time per
    // ray, and cast the rest the cheaper way. A call with few items (Auto's probe casts a few
    // tiles at a time) is too small to tell: packets, and no memo. The items come in pairs of
    // neighbours (receiver samples j and j + 1, or blocks side by side), drawn at random,
    // one of each pair to each traversal: neighbours keep nearly the same rays free, so both
    // are timed on like work (items drawn independently can hand one traversal twice the free
    // rays of the other, and the choice to the slower one); at least eight pairs, so that a
    // 32-sample receiver still gives each traversal several.
    if (items_ < kModeProbeItems) {
        castAll(all, packets_, nullptr);
        return;
    }
    // The pairs as Auto's tile probe draws them, on a grid one item wide.
    const bitmask::ProbeTiles split =
        bitmask::probeTiles(items_, 1, std::max(items_ / 8, std::min<std::size_t>(8, items_ / 4)));
    const std::vector<std::uint32_t>& first = split.bitmask;
    const std::vector<std::uint32_t>& second = split.rays;
    const std::vector<std::uint32_t>& rest = split.rest;
    std::uint64_t packetRays = 0, occludedRays = 0;
    const double packetNs = double(castAll(first, true, &packetRays));
    const double occludedNs = double(castAll(second, false, &occludedRays));
    packets_ = occludedRays == 0 || packetRays == 0 ||
              packetNs / double(packetRays) <= occludedNs / double(occludedRays);
    probed_ = true;
    castAll(rest, packets_, nullptr);
    std::lock_guard lock(caster_.memoMutex_);
    caster_.memo_ = std::make_unique<ModeMemo>(ModeMemo{configuration, fromSource_, packets_, bitmask::kProbeReuse});
}

std::uint64_t ProvenRayCaster::sampleUnblocked(const Patch& source, const Patch& receiver, HiddenSampleMap& map,
                                               const RayCastOptions& options, const RayCastScene& exact, CastMode mode,
                                               ProvenCastStats* stats) const
{
    if (map.sourceCount() != source.sampleCount() || map.receiverNa() != receiver.na || map.receiverNb() != receiver.nb)
        throw Error("ProvenRayCaster::sampleUnblocked: map dimensions do not match the patches");
    std::uint64_t confirm = 0;
    double floatMs = 0.0, confirmMs = 0.0;
    bool fromSource = false;
    std::optional<Call> call;
    auto both = [&] {
        call.emplace(*this, source, receiver, map, options, mode);
        fromSource = call->fromSource();
        const auto start = std::chrono::steady_clock::now();
        call->pass();
        const auto middle = std::chrono::steady_clock::now();
        floatMs = std::chrono::duration<double, std::milli>(middle - start).count();
        // Pass 2: the rays pass 1 left free, by the reference.
        RayCastOptions rest = options;
        rest.threads = 0;   // already in the caller's arena
        rest.packets = true;
        rest.fromSource = fromSource;
        confirm = exact.sampleUnblocked(source, receiver, map, rest);
        confirmMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - middle).count();
    };
    if (options.threads > 0) {
        tbb::task_arena arena(options.threads);
        arena.execute(both);
    } else {
        both();
    }
    if (!impl_->error.empty())
        throw Error("Embree: " + impl_->error);
    contradictions_ += call->contradictions.load();
    if (stats) {
        stats->floatRays = call->rays.load();
        stats->provenHits = call->proven.load();
        stats->exactTests = call->exactTests.load();
        stats->confirmRays = confirm;
        stats->floatMs = floatMs;
        stats->confirmMs = confirmMs;
        stats->fromSource = fromSource;
        stats->packets = call->packets_;
        stats->probedMode = call->probed_;
    }
    return call->rays.load();
}

} // namespace sightline::raycast
