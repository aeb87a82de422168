#include "FastRayCaster.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "RayPackets.h"
#include "visibility/Error.h"
#include "visibility/ExactSegment.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/ShaftGeometry.h"

namespace sightline::raycast {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

constexpr double kUnitRoundoff = 1.0 / 16777216.0;   // float: 2^-24

/// E = kErrorUlps * u * (|O| + |C| + 3 size) bounds, times sin(alpha), how far Embree's float
/// answer moves a crossing in the triangle's plane, for a ray with float origin O (local frame)
/// and a grown triangle whose edges are at most `size` long and whose first vertex lies within |C|
/// of O. The terms, each a few u of these lengths, divided by sin(alpha) where they move a point
/// across the plane's normal:
/// - Moeller-Trumbore's edge tests U = (C x D) . e2 and V = (C x D) . e1 (C = v0 - O, D the
///   direction, e1 and e2 stored rounded): about 10 u |C||D||e|, against U = s |D||e| sin(alpha)
///   for a crossing s inside the edge: 10 u |C|; the third edge, absDen - U - V, adds den's error
///   (Ng = e2 x e1 rounded, about 10 u |e1||e2||D|) and both others, relative to its own length,
///   which is the longest one (vertices are ordered so): 20 u (|C| + size);
/// - box tests (near/far distances from fused multiply-adds with rcp(D) after a Newton step,
///   also in Embree's frustum test of coherent packets): about 8 u (|O| + |C|);
/// - rounding the grown vertices, the origin and the direction to float: 6 u (|O| + |C|).
/// About 34 in all; 64 leaves a factor of two. The same bound, divided by the triangle's
/// heights, bounds the error of the barycentrics Embree reports (the filter's proof).
constexpr double kErrorUlps = 64.0;

/// Triangles grow about their centroid by a factor 1 + 2^-j, the largest for which no vertex
/// moves by more than the inradius (a needle grown in proportion would reach far past its tip
/// and cost every ray near it a rejected hit) and no edge by more than kMaxMarginMetres; each
/// (growth, size) class is one Embree geometry, so the filter reads both from the hit's geomID
/// and needs nothing of the triangle's own to prove a hit.
constexpr double kMaxMarginMetres = 1e-3;
constexpr int kGrowthClasses = 48;
/// Triangles whose edges would move by less than this are left to the close pass whenever they
/// are in the shaft (the needles of scanned meshes).
constexpr double kMinMarginMetres = 1e-7;

void onEmbreeError(void* user, RTCError, const char* message)
{
    static_cast<std::string*>(user)->assign(message ? message : "unknown Embree error");
}

} // namespace

struct FastRayCaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::string error;
    double buildMs = 0.0;
    glm::dvec3 origin{0.0};               ///< the local frame's origin (the scene box's centre), world
    std::vector<glm::vec3> world;         ///< 3 per world triangle: the file's values
    std::vector<std::uint32_t> instanceOf;

    /// One Embree geometry: triangles grown by `scale` about their centroids, edges at most `size`.
    struct GeometryClass {
        float scale = 1.0f;
        float size = 0.0f;
        std::uint32_t first = 0;   ///< its first float triangle (primID 0)
        // What the filter's proof reads, precomputed.
        float shift = 0.0f;            ///< (scale - 1) / 3
        float fourSizes = 0.0f;
        float sizeSquared = 0.0f;
        float normalError = 0.0f;      ///< 8 u size^2
        float scaleSize = 0.0f;
    };
    std::vector<GeometryClass> classes;   ///< by geomID

    // Per float triangle (first + primID of its geometry), for the filter's exact test and each
    // call's check.
    std::vector<std::uint32_t> worldOf;        ///< its world triangle
    std::vector<std::array<glm::vec3, 3>> exact;   ///< the file's values, world
    std::vector<glm::dvec3> centre;            ///< centroid, local frame
    std::vector<glm::dvec3> unitNormal;
    std::vector<double> extent;                ///< the grown vertices lie within this of the centroid
    std::vector<double> margin;                ///< every edge moved out by at least this
    /// World triangles never in the float BVH but able to block (slivers): close when in a shaft.
    std::vector<std::uint32_t> slivers;

    ~Impl()
    {
        if (scene)
            rtcReleaseScene(scene);
        if (device)
            rtcReleaseDevice(device);
    }

    glm::dvec3 worldVertex(std::size_t k) const { return glm::dvec3(world[k]); }

    /// What one receiver sample's rays carry to the filter: their exact common start and
    /// directions, by source index (the ray's id). Embree passes this context (its first member)
    /// to every callback of the call.
    struct SegmentContext {
        RTCIntersectContext base;
        const Impl* self = nullptr;
        glm::dvec3 receiverEnd{0.0};
        const glm::dvec3* directions = nullptr;   ///< q - p, world
        float originReach = 0.0f;                 ///< |O| of every float origin of the call, at most
        /// The original segment spans [lead, 1 - lead] of the lengthened one.
        float lead = 0.0f;
        float errorPerMetre = float(kErrorUlps * kUnitRoundoff * 1.001);
    };

    /// Whether Embree's hit of lane i is a crossing of the original triangle by the contract,
    /// decided in float from the hit and the call's bounds alone (no memory of the triangle's):
    /// the hit point's barycentrics on the original triangle put it inside every edge by more
    /// than the error bound (which has its own factor of two), and its distance along the
    /// segment from both ends exceeds the bound on Embree's distance error. Close calls go to the
    /// exact test.
    ///
    /// The bounds (kErrorUlps), with D the lengthened segment, |C| <= t |D| + size,
    /// den = |Ng . D| minus Ng's rounding (Ng is e2 x e1 of the rounded edges: within
    /// 8 u size^2 |D| of the exact den):
    /// - barycentrics on the grown triangle err by E / (sin(alpha) h) <= E |D| size / den (h a
    ///   height, |e| <= size), and the original's are `scale` times as far off;
    /// - along the segment Embree's crossing errs by E / sin(alpha) = E |Ng| |D| / den <=
    ///   E size^2 |D| / den.
    static bool proven(const Impl& self, const SegmentContext& context, const RTCFilterFunctionNArguments* args,
                       unsigned i)
    {
        const GeometryClass& g = self.classes[RTCHitN_geomID(args->hit, args->N, i)];
        const float dx = RTCRayN_dir_x(args->ray, args->N, i), dy = RTCRayN_dir_y(args->ray, args->N, i),
                    dz = RTCRayN_dir_z(args->ray, args->N, i);
        const float nx = RTCHitN_Ng_x(args->hit, args->N, i), ny = RTCHitN_Ng_y(args->hit, args->N, i),
                    nz = RTCHitN_Ng_z(args->hit, args->N, i);
        // |D|, a little over (for the error bound) and under (for distances along it).
        const float length = std::sqrt(dx * dx + dy * dy + dz * dz);
        const float over = length * 1.00001f, under = length * 0.99999f;
        const float den = std::abs(nx * dx + ny * dy + nz * dz) - g.normalError * over;
        const float t = RTCRayN_tfar(args->ray, args->N, i);
        // E |D| / den, times den: (|O| + |C| + 3 size) |D|.
        const float errorTimesDen = context.errorPerMetre * (context.originReach + t * over + g.fourSizes) * over;
        // Along the segment, from both ends: E size^2 |D| / den (+ 1e-6 m) <= (t - lead) |D|.
        const float nearEnd = std::min(t - context.lead, 1.0f - context.lead - t) * under;
        if (!(den > 0.0f && nearEnd * den >= errorTimesDen * g.sizeSquared + 1e-6f * den))
            return false;
        // In the plane: b = scale * g - (scale - 1) / 3 on the original triangle, g Embree's
        // barycentrics on the grown one; 1e-5 more covers this arithmetic and Embree's division.
        const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
        const float inside = std::min({1.0f - u - v, u, v}) * g.scale - g.shift - 1e-5f;
        return inside * den >= g.scaleSize * errorTimesDen;
    }

    /// Keeps a reported hit only where the contract's test says the segment crosses the triangle.
    static void filter(const RTCFilterFunctionNArguments* args)
    {
        const auto* context = reinterpret_cast<const SegmentContext*>(args->context);
        const Impl& self = *context->self;
        constexpr unsigned kMax = 16;   // rtcOccluded16's lanes
        alignas(32) double dx[kMax], dy[kMax], dz[kMax];
        alignas(32) std::int64_t hit[kMax];
        unsigned lane[kMax];
        // A callback's hits are one triangle's in packet traversal and a single hit in single-ray
        // traversal; lanes are grouped by triangle in case of more.
        for (unsigned base = 0; base < args->N; base += kMax) {
            std::uint32_t undecided = 0;
            for (unsigned i = base; i < args->N && i < base + kMax; ++i)
                if (args->valid[i] == -1 && !proven(self, *context, args, i))
                    undecided |= 1u << (i - base);
            while (undecided) {
                const unsigned first = base + unsigned(std::countr_zero(undecided));
                const unsigned geometry = RTCHitN_geomID(args->hit, args->N, first);
                const unsigned prim = RTCHitN_primID(args->hit, args->N, first);
                int count = 0;
                for (std::uint32_t rest = undecided; rest; rest &= rest - 1) {
                    const unsigned i = base + unsigned(std::countr_zero(rest));
                    if (RTCHitN_primID(args->hit, args->N, i) != prim || RTCHitN_geomID(args->hit, args->N, i) != geometry)
                        continue;
                    const glm::dvec3& d = context->directions[RTCRayN_id(args->ray, args->N, i)];
                    dx[count] = d.x, dy[count] = d.y, dz[count] = d.z;
                    lane[count++] = i;
                    undecided &= ~(1u << (i - base));
                }
                const std::array<glm::vec3, 3>& v = self.exact[self.classes[geometry].first + prim];
                const TriangleSeenFrom triangle(context->receiverEnd, glm::dvec3(v[0]), glm::dvec3(v[1]), glm::dvec3(v[2]));
                crossedLanes(triangle, dx, dy, dz, count, hit);
                for (int k = 0; k < count; ++k)
                    if (!hit[k])
                        args->valid[lane[k]] = 0;
            }
        }
    }
};

FastRayCaster::FastRayCaster(const WorldTriangles& triangles) : impl_(std::make_unique<Impl>())
{
    const auto start = Clock::now();
    Impl& m = *impl_;
    m.world = triangles.vertices;
    m.instanceOf = triangles.instanceOf;
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const glm::vec3& v : triangles.vertices)
        lo = glm::min(lo, glm::dvec3(v)), hi = glm::max(hi, glm::dvec3(v));
    if (!triangles.vertices.empty())
        m.origin = 0.5 * (lo + hi);

    struct Grown {
        std::uint32_t world;
        int growth;   // j: scale 1 + 2^-j
        int size;     // edges at most 2^size
        std::array<glm::vec3, 3> vertices;
        glm::dvec3 centroid, unitNormal;
        double extent, margin;
    };
    std::vector<Grown> grown;
    grown.reserve(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::dvec3 wa = m.worldVertex(3 * t), wb = m.worldVertex(3 * t + 1), wc = m.worldVertex(3 * t + 2);
        // The contract's own normal: where it is exactly zero the triangle blocks nothing.
        if (glm::cross(wb - wa, wc - wa) == glm::dvec3(0.0))
            continue;
        const glm::dvec3 a = wa - m.origin, b = wb - m.origin, c = wc - m.origin;
        const double la = glm::length(b - c), lb = glm::length(c - a), lc = glm::length(a - b);
        const glm::dvec3 normal = glm::cross(b - a, c - a);
        const double area2 = glm::length(normal);
        const double inradius = area2 / (la + lb + lc);
        const double lowest = area2 / std::max({la, lb, lc});   // the smallest height
        const glm::dvec3 centroid = (a + b + c) / 3.0;
        const double farthest = std::max({glm::length(a - centroid), glm::length(b - centroid), glm::length(c - centroid)});
        // Scaling by s about the centroid moves edge i out by (s - 1) h_i / 3 and vertex k by
        // (s - 1) |v_k - centroid|.
        int j = 1;
        while (j <= kGrowthClasses && (std::ldexp(1.0, -j) * farthest > inradius || std::ldexp(1.0, -j) * lowest / 3.0 > kMaxMarginMetres))
            ++j;
        const double margin = std::ldexp(1.0, -j) * lowest / 3.0;
        if (j > kGrowthClasses || !(margin >= kMinMarginMetres)) {
            m.slivers.push_back(std::uint32_t(t));
            continue;
        }
        const double scale = 1.0 + std::ldexp(1.0, -j);
        std::array<glm::dvec3, 3> v{centroid + scale * (a - centroid), centroid + scale * (b - centroid),
                                    centroid + scale * (c - centroid)};
        // The longest edge last (v1 -> v2): Moeller-Trumbore's third edge test, absDen - U - V,
        // errs relative to that edge's length (kErrorUlps).
        const int longest = la >= lb && la >= lc ? 0 : lb >= lc ? 1 : 2;   // edge opposite vertex `longest`
        std::rotate(v.begin(), v.begin() + longest, v.end());
        Grown g{std::uint32_t(t), j, 0, {}, centroid, glm::normalize(normal), 0.0, margin};
        double longestGrown = 0.0;
        for (int k = 0; k < 3; ++k) {
            g.vertices[std::size_t(k)] = glm::vec3(v[std::size_t(k)]);
            g.extent = std::max(g.extent, glm::length(glm::dvec3(g.vertices[std::size_t(k)]) - centroid));
        }
        for (int k = 0; k < 3; ++k)
            longestGrown = std::max(longestGrown, glm::length(glm::dvec3(g.vertices[std::size_t(k)]) -
                                                              glm::dvec3(g.vertices[std::size_t((k + 1) % 3)])));
        g.size = std::ilogb(longestGrown * (1.0 + 1e-6)) + 1;   // 2^size > longestGrown
        grown.push_back(g);
    }
    // Float triangles grouped by class, one geometry each.
    std::stable_sort(grown.begin(), grown.end(), [](const Grown& x, const Grown& y) {
        return std::pair(x.growth, x.size) < std::pair(y.growth, y.size);
    });
    for (const Grown& g : grown) {
        m.worldOf.push_back(g.world);
        m.exact.push_back({m.world[3 * std::size_t(g.world)], m.world[3 * std::size_t(g.world) + 1],
                           m.world[3 * std::size_t(g.world) + 2]});
        m.centre.push_back(g.centroid);
        m.unitNormal.push_back(g.unitNormal);
        m.extent.push_back(g.extent);
        m.margin.push_back(g.margin);
    }

    m.device = rtcNewDevice(nullptr);
    if (!m.device)
        throw Error("Embree: cannot create a device (" + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(m.device, onEmbreeError, &m.error);
    m.scene = rtcNewScene(m.device);   // flat, not robust, default (medium) build quality
    for (std::size_t first = 0; first < grown.size();) {
        std::size_t end = first;
        while (end < grown.size() && grown[end].growth == grown[first].growth && grown[end].size == grown[first].size)
            ++end;
        const std::size_t count = end - first;
        RTCGeometry geometry = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree may read 16 bytes past a float3, so the vertex buffer has one element more.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                     3 * sizeof(float), 3 * count + 1));
        auto* indices = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count));
        if (!vertices || !indices)
            throw Error("Embree: out of memory for " + std::to_string(grown.size()) + " triangles");
        for (std::size_t k = 0; k < count; ++k)
            for (std::size_t c = 0; c < 3; ++c) {
                const glm::vec3& p = grown[first + k].vertices[c];
                vertices[9 * k + 3 * c] = p.x, vertices[9 * k + 3 * c + 1] = p.y, vertices[9 * k + 3 * c + 2] = p.z;
                indices[3 * k + c] = unsigned(3 * k + c);
            }
        vertices[9 * count] = vertices[9 * count + 1] = vertices[9 * count + 2] = 0.0f;
        rtcSetGeometryOccludedFilterFunction(geometry, &Impl::filter);
        rtcCommitGeometry(geometry);
        const unsigned id = rtcAttachGeometry(m.scene, geometry);
        rtcReleaseGeometry(geometry);
        if (id != m.classes.size())
            throw Error("Embree: unexpected geometry id " + std::to_string(id));
        Impl::GeometryClass g;
        g.scale = float(1.0 + std::ldexp(1.0, -grown[first].growth));
        g.size = float(std::ldexp(1.0, grown[first].size));
        g.first = std::uint32_t(first);
        g.shift = float(std::ldexp(1.0, -grown[first].growth) / 3.0 * (1.0 - 1e-6));
        g.fourSizes = 4.0f * g.size;
        g.sizeSquared = g.size * g.size;
        g.normalError = float(8.0 * kUnitRoundoff) * g.sizeSquared;
        g.scaleSize = g.scale * g.size;
        m.classes.push_back(g);
        first = end;
    }
    rtcCommitScene(m.scene);
    if (!m.error.empty())
        throw Error("Embree: " + m.error);
    m.buildMs = msSince(start);
}

FastRayCaster::~FastRayCaster() = default;

double FastRayCaster::buildMilliseconds() const { return impl_->buildMs; }
std::size_t FastRayCaster::floatTriangleCount() const { return impl_->worldOf.size(); }

struct FastRayCaster::Shaft::Data {
    Patch source, receiver;
    SourceJitter jitter;
    const ReceiverHeights* heights = nullptr;
    bool bumpy = false;
    glm::dvec3 normal{0.0};                 ///< bumpy: the receiver's normal toward the source
    std::vector<glm::dvec3> sourceExact;
    std::vector<int> order;
    double extension = 0.0;                 ///< every segment is lengthened by at least this, in metres
    double originReach = 0.0;               ///< |O| of every float origin, at most
    std::vector<std::uint32_t> closeList;   ///< world triangles, ascending
    std::unique_ptr<RayCastScene> close;    ///< CastExactly: their BVH (null when there are none)
    double prepareMs = 0.0;

    glm::dvec3 receiverEnd(int j) const
    {
        return bumpy ? receiver.sample(j) + heights->metres[std::size_t(j)] * normal : receiver.sample(j);
    }
};

FastRayCaster::Shaft::Shaft(std::unique_ptr<Data> data) : data_(std::move(data)) {}
FastRayCaster::Shaft::~Shaft() = default;
std::size_t FastRayCaster::Shaft::closeTriangles() const { return data_->closeList.size(); }
const std::vector<std::uint32_t>& FastRayCaster::Shaft::closeTriangleIndices() const { return data_->closeList; }
double FastRayCaster::Shaft::prepareMilliseconds() const { return data_->prepareMs; }

std::unique_ptr<FastRayCaster::Shaft> FastRayCaster::prepare(const Patch& source, const Patch& receiver,
                                                              const RayCastOptions& options, CloseTriangles close) const
{
    validatePatchPair(source, receiver);
    if (options.heights)
        validateReceiverHeights(source, receiver, *options.heights);
    const auto start = Clock::now();
    const Impl& m = *impl_;
    auto d = std::make_unique<Shaft::Data>();
    d->source = source, d->receiver = receiver, d->jitter = options.jitter, d->heights = options.heights;
    d->bumpy = !flatReceiver(options.heights);
    if (d->bumpy)
        d->normal = receiverNormalTowardSource(source, receiver);
    const int S = source.sampleCount();
    d->sourceExact.resize(std::size_t(S));
    for (int i = 0; i < S; ++i)
        d->sourceExact[std::size_t(i)] = source.sample(i);
    d->order = packetOrder(source);

    // The points every ray starts and ends in (local frame): the receiver's corners (a bumpy
    // receiver's prism between its lowest and highest bump) and the source's (jittered samples
    // stay inside it).
    std::vector<glm::dvec3> receiverPoints, sourcePoints;
    double lowest = 0.0, highest = 0.0;
    if (d->bumpy) {
        const auto [lo, hi] = std::minmax_element(options.heights->metres.begin(), options.heights->metres.end());
        lowest = *lo, highest = *hi;
    }
    for (int k = 0; k < 4; ++k) {
        const glm::dvec3 rc = receiver.corner + double(k & 1) * receiver.u + double(k >> 1) * receiver.v;
        receiverPoints.push_back(rc + lowest * d->normal - m.origin);
        if (d->bumpy)
            receiverPoints.push_back(rc + highest * d->normal - m.origin);
        sourcePoints.push_back(source.corner + double(k & 1) * source.u + double(k >> 1) * source.v - m.origin);
    }
    const auto sphere = [](const std::vector<glm::dvec3>& points) {
        glm::dvec3 c(0.0);
        for (const glm::dvec3& p : points)
            c += p;
        c /= double(points.size());
        double r = 0.0;
        for (const glm::dvec3& p : points)
            r = std::max(r, glm::length(p - c));
        return std::pair(c, r);
    };
    const auto [receiverCentre, receiverRadius] = sphere(receiverPoints);
    const auto [sourceCentre, sourceRadius] = sphere(sourcePoints);

    // Segments are lengthened by kMaxMarginMetres at both ends: a crossing that Embree's distance
    // test could misplace past an end lies within E / sin(alpha) <= margin of it.
    d->extension = kMaxMarginMetres;
    for (const glm::dvec3& p : receiverPoints)
        d->originReach = std::max(d->originReach, glm::length(p));
    d->originReach = (d->originReach + d->extension) * (1.0 + 1e-6);

    // Close triangles: those for which the bound on sin(alpha) does not prove the float pass.
    // A ray through the triangle runs from the receiver to the source, so sin(alpha) is at least
    // either patch's distance from the plane over its farthest distance from the triangle, where
    // the patch lies wholly on one side.
    const auto sinBound = [](const std::vector<glm::dvec3>& points, const glm::dvec3& n, const glm::dvec3& c,
                             double farthest) {
        double below = std::numeric_limits<double>::infinity(), above = -below;
        for (const glm::dvec3& p : points) {
            const double h = glm::dot(n, p - c);
            below = std::min(below, h), above = std::max(above, h);
        }
        const double nearest = below > 0.0 ? below : above < 0.0 ? -above : 0.0;   // 0: the patch meets the plane
        return nearest / farthest;
    };
    const ShaftHull hull = d->bumpy ? ShaftHull([&] {
        std::vector<glm::dvec3> points;
        for (const glm::dvec3& p : sourcePoints)
            points.push_back(p + m.origin);
        for (const glm::dvec3& p : receiverPoints)
            points.push_back(p + m.origin);
        return points;
    }())
                                    : ShaftHull(source, receiver);
    const std::size_t F = m.worldOf.size();
    std::vector<char> isClose(F, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, F, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t f = range.begin(); f != range.end(); ++f) {
            const glm::dvec3& c = m.centre[f];
            const double size = m.extent[f];
            const double toReceiver = glm::length(c - receiverCentre) + receiverRadius + size;
            const double toSource = glm::length(c - sourceCentre) + sourceRadius + size;
            const double sinAlpha = std::max(sinBound(receiverPoints, m.unitNormal[f], c, toReceiver),
                                             sinBound(sourcePoints, m.unitNormal[f], c, toSource));
            const double error = kErrorUlps * kUnitRoundoff * (d->originReach + toReceiver + 6.0 * size);
            if (m.margin[f] * sinAlpha >= error)
                continue;
            const std::array<glm::vec3, 3>& v = m.exact[f];
            isClose[f] = !hull.excludes(v[0], v[1], v[2]);
        }
    });
    for (std::size_t f = 0; f < F; ++f)
        if (isClose[f])
            d->closeList.push_back(m.worldOf[f]);
    for (std::uint32_t t : m.slivers)
        if (!hull.excludes(m.world[3 * std::size_t(t)], m.world[3 * std::size_t(t) + 1], m.world[3 * std::size_t(t) + 2]))
            d->closeList.push_back(t);
    std::sort(d->closeList.begin(), d->closeList.end());
    if (!d->closeList.empty() && close == CloseTriangles::CastExactly) {
        WorldTriangles subset;
        subset.vertices.reserve(3 * d->closeList.size());
        for (std::uint32_t t : d->closeList) {
            subset.vertices.insert(subset.vertices.end(), &m.world[3 * std::size_t(t)], &m.world[3 * std::size_t(t)] + 3);
            subset.instanceOf.push_back(m.instanceOf[t]);
        }
        d->close = std::make_unique<RayCastScene>(subset, /*fastBuild=*/true);
    }
    d->prepareMs = msSince(start);
    return std::make_unique<Shaft>(std::move(d));
}

std::uint64_t FastRayCaster::cast(const Shaft& shaft, HiddenSampleMap& map, const std::vector<int>* receiverSubset) const
{
    const Shaft::Data& d = shaft.data();
    const Impl& m = *impl_;
    const Patch& source = d.source;
    const Patch& receiver = d.receiver;
    if (map.sourceCount() != source.sampleCount() || map.receiverNa() != receiver.na || map.receiverNb() != receiver.nb)
        throw Error("FastRayCaster::cast: map dimensions do not match the patches");
    const int S = source.sampleCount();
    const glm::dvec3 sourceNormal = source.normal();
    std::atomic<std::uint64_t> cast{0};

    auto castFrom = [&](int j) {
        const glm::dvec3 end = d.receiverEnd(j);
        const glm::dvec3 shift = d.jitter.shift(source, j);
        auto bits = map.row(j);
        auto alreadyBlocked = [&](int i) { return (bits[std::size_t(i >> 6)] >> (i & 63)) & 1u; };
        Impl::SegmentContext context;
        rtcInitIntersectContext(&context.base);
        context.base.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        context.self = &m;
        context.receiverEnd = end;
        context.originReach = float(d.originReach);
        thread_local std::vector<glm::dvec3> directions;
        directions.resize(std::size_t(S));
        for (int i = 0; i < S; ++i)
            directions[std::size_t(i)] = d.sourceExact[std::size_t(i)] + shift - end;
        context.directions = directions.data();
        // Every segment from this end is at least as long as the end's distance from the
        // source's plane (which the pair's validation keeps positive), so lengthening each by
        // this fraction of itself at both ends adds at least `extension` metres there.
        const double lengthen = d.extension / std::abs(glm::dot(sourceNormal, end - source.corner));
        // Rounded up: the proof then asks a little more distance from the ends than it needs.
        context.lead = float(lengthen / (1.0 + 2.0 * lengthen) * (1.0 + 1e-6));
        const glm::dvec3 local = end - m.origin;
        std::uint64_t rowCast = 0;
        alignas(64) RTCRay16 rays;
        alignas(64) int valid[16];
        for (int first = 0; first < S; first += 16) {
            int lanes = 0;
            for (int k = 0; k < 16; ++k) {
                const int i = first + k < S ? d.order[std::size_t(first + k)] : S;
                valid[k] = i < S && !alreadyBlocked(i) ? -1 : 0;
                lanes += valid[k] != 0;
                const glm::dvec3 dir = i < S ? directions[std::size_t(i)] : glm::dvec3(1.0);
                const glm::vec3 org(local - lengthen * dir), along((1.0 + 2.0 * lengthen) * dir);
                rays.org_x[k] = org.x, rays.org_y[k] = org.y, rays.org_z[k] = org.z;
                rays.dir_x[k] = along.x, rays.dir_y[k] = along.y, rays.dir_z[k] = along.z;
                rays.tnear[k] = 0.0f;
                rays.tfar[k] = 1.0f;
                rays.time[k] = 0.0f;
                rays.mask[k] = 0xffffffffu;
                rays.id[k] = unsigned(i < S ? i : 0);
                rays.flags[k] = 0;
            }
            if (lanes == 0)
                continue;
            rowCast += std::uint64_t(lanes);
            rtcOccluded16(valid, m.scene, &context.base, &rays);
            for (int k = 0; k < 16 && first + k < S; ++k)
                if (valid[k] && rays.tfar[k] < 0.0f) {
                    const int i = d.order[std::size_t(first + k)];
                    bits[std::size_t(i >> 6)] |= std::uint64_t(1) << (i & 63);
                }
        }
        cast += rowCast;
    };

    const int receivers = receiverSubset ? int(receiverSubset->size()) : receiver.sampleCount();
    if (!m.classes.empty())
        tbb::parallel_for(tbb::blocked_range<int>(0, receivers, 16), [&](const tbb::blocked_range<int>& range) {
            for (int k = range.begin(); k != range.end(); ++k) {
                const int j = receiverSubset ? (*receiverSubset)[std::size_t(k)] : k;
                if (j < 0 || j >= receiver.sampleCount())
                    throw Error("FastRayCaster::cast: receiver sample " + std::to_string(j) + " is outside the grid");
                castFrom(j);
            }
        });
    if (!m.error.empty())
        throw Error("Embree: " + m.error);
    if (d.close)
        d.close->sampleUnblocked(source, receiver, map,
                                 {.jitter = d.jitter, .heights = d.heights, .receiverSubset = receiverSubset});
    return cast;
}

std::uint64_t FastRayCaster::sampleUnblocked(const Patch& source, const Patch& receiver, HiddenSampleMap& map,
                                             const RayCastOptions& options) const
{
    std::uint64_t cast = 0;
    auto run = [&] {
        const std::unique_ptr<Shaft> shaft = prepare(source, receiver, options);
        cast = this->cast(*shaft, map, options.receiverSubset);
    };
    if (options.threads > 0) {
        tbb::task_arena arena(options.threads);
        arena.execute(run);
    } else {
        run();
    }
    return cast;
}

} // namespace sightline::raycast
