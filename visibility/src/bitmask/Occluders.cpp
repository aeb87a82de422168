#include "Occluders.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>

#include <glm/geometric.hpp>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "SampleRange.h"

namespace sightline::bitmask {

bool prepareOccluder(const Shaft& shaft, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, Occluder& out)
{
    const ClippedPolygon polygon = shaft.clip(a, b, c);
    if (polygon.count < 3)
        return false;
    assert(polygon.count <= Occluder::kMaxVertices);   // a triangle and two planes
    out.count = polygon.count;
    double sMin = 1e300, sMax = -1e300, tMin = 1e300, tMax = -1e300, maxD = -1e300;
    bool whole = false;
    for (int i = 0; i < polygon.count; ++i) {
        const glm::dvec3& x = polygon.vertices[std::size_t(i)];
        const glm::dvec3 inSource = shaft.frames.source.coordinates(x);
        out.vertices[std::size_t(i)] = inSource;
        maxD = std::max(maxD, inSource.z);
        const glm::dvec3 inReceiver = shaft.frames.receiver.coordinates(x);
        for (const glm::dvec3& corner : shaft.sourceCornersInReceiver) {
            const double denominator = corner.z - inReceiver.z;
            if (denominator <= 1e-12 * corner.z) {
                whole = true;
                continue;
            }
            for (int level = 0; level < shaft.levelCount; ++level) {
                // Flat: levels[0] == 0 and the factor is corner.z / denominator, bit for bit.
                const double k = (corner.z - shaft.levels[std::size_t(level)]) / denominator;
                const double s = corner.x + (inReceiver.x - corner.x) * k;
                const double t = corner.y + (inReceiver.y - corner.y) * k;
                sMin = std::min(sMin, s), sMax = std::max(sMax, s);
                tMin = std::min(tMin, t), tMax = std::max(tMax, t);
            }
        }
    }
    if (whole) {
        out.a0 = 0, out.a1 = shaft.rna - 1, out.b0 = 0, out.b1 = shaft.rnb - 1;
    } else {
        // Widen so that rounding never drops a sample on the region's boundary: relative to the
        // projections, which reach 1e12 for a vertex just off the source plane.
        const double pad = 1e-9 * (1.0 + std::max({std::abs(sMin), std::abs(sMax), std::abs(tMin), std::abs(tMax)}));
        sampleRange(sMin - pad, sMax + pad, shaft.rna, out.a0, out.a1);
        sampleRange(tMin - pad, tMax + pad, shaft.rnb, out.b0, out.b1);
    }
    out.maxD = maxD;
    // Only the samples of the influence region are ever backprojected from, so on a flat
    // receiver the path is chosen for the region's nearest sample, not the receiver's.
    const bool regional = !shaft.bumpy && !whole && out.a0 <= out.a1 && out.b0 <= out.b1;
    out.path = shaft.pathFor(maxD, regional ? shaft.nearestSample(out.a0, out.a1, out.b0, out.b1) : shaft.minReceiverDistance);
    if (shaft.parallel)
        for (int i = 0; i < out.count; ++i)
            out.factor[std::size_t(i)] = shaft.receiverDistance / (shaft.receiverDistance - out.vertices[std::size_t(i)].z);
    // Sized from the region's farthest corner sample, beyond every vertex unless the occluder
    // crosses the whole region (such occluders go first, as the largest).
    out.cells = 1e300;
    if (regional) {
        glm::dvec3 farthest(0.0, 0.0, -1e300);
        for (const int rb : {out.b0, out.b1})
            for (const int ra : {out.a0, out.a1})
                if (const glm::dvec3& r = shaft.receiverInSource[std::size_t(rb * shaft.rna + ra)]; r.z > farthest.z)
                    farthest = r;
        if (shaft.pathFor(maxD, farthest.z) != Path::Clip)
            out.cells = backprojectedCells(shaft, out, farthest);
    } else if (!whole && out.path != Path::Clip) {
        out.cells = backprojectedCells(shaft, out, shaft.receiverCentre);
    }
    return out.a0 <= out.a1 && out.b0 <= out.b1;
}

double backprojectedCells(const Shaft& shaft, const Occluder& o, const glm::dvec3& r)
{
    double area = 0.0, ps = 0.0, pt = 0.0;
    for (int i = 0; i <= o.count; ++i) {
        const glm::dvec3& x = o.vertices[std::size_t(i % o.count)];
        const double k = r.z / (r.z - x.z);
        const double s = r.x + (x.x - r.x) * k, t = r.y + (x.y - r.y) * k;
        if (i > 0)
            area += ps * t - s * pt;
        ps = s, pt = t;
    }
    return 0.5 * std::abs(area) * shaft.na * shaft.nb;
}

detail::FloatPolygon floatPolygon(const Shaft& shaft, const Occluder& o, bool closed)
{
    detail::FloatPolygon single;
    single.count = o.count;
    single.sharedFactor = shaft.parallel;
    single.closed = closed;
    for (int i = 0; i < o.count; ++i) {
        const glm::dvec3& x = o.vertices[std::size_t(i)];
        single.s[i] = float(x.x), single.sLo[i] = float(x.x - double(single.s[i]));
        single.t[i] = float(x.y), single.tLo[i] = float(x.y - double(single.t[i]));
        single.d[i] = float(x.z), single.dLo[i] = float(x.z - double(single.d[i]));
        single.k[i] = shaft.parallel ? float(o.factor[std::size_t(i)]) : 0.0f;
        single.sReach = std::max(single.sReach, std::abs(single.s[i]));
        single.tReach = std::max(single.tReach, std::abs(single.t[i]));
    }
    return single;
}

bool TriangleFilter::outsideShaft(std::size_t t) const
{
    if (!instanceOutside.empty() && instanceOutside[triangles->instanceOf[t]])
        return true;
    return hull->excludes(triangle(t)[0], triangle(t)[1], triangle(t)[2]);
}

bool TriangleFilter::culled(std::size_t t) const
{
    if (cullable.empty() || !cullable[triangles->instanceOf[t]])
        return false;
    const glm::dvec3 a(triangle(t)[0]), b(triangle(t)[1]), c(triangle(t)[2]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    for (const glm::dvec3& corner : sourceCorners)
        if (glm::dot(n, corner - a) <= 0.0)
            return false;
    return true;
}

PairEstimate estimatePairs(const Shaft& shaft, const TriangleFilter& filter)
{
    constexpr std::size_t kStride = 32;
    const std::size_t count = filter.triangles->size();
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, (count + kStride - 1) / kStride, 64), PairEstimate{},
        [&](const auto& range, PairEstimate sum) {
            Occluder o;
            for (std::size_t k = range.begin(); k != range.end(); ++k) {
                const std::size_t t = k * kStride;
                const glm::vec3* v = filter.triangle(t);
                if (!filter.outsideShaft(t) && !filter.culled(t) && prepareOccluder(shaft, v[0], v[1], v[2], o)) {
                    sum.triangles += kStride;
                    sum.pairs += kStride * std::uint64_t(o.a1 - o.a0 + 1) * std::uint64_t(o.b1 - o.b0 + 1);
                }
            }
            return sum;
        },
        [](PairEstimate a, const PairEstimate& b) {
            a.triangles += b.triangles, a.pairs += b.pairs;
            return a;
        });
}

void OccluderSet::prepare(const Shaft& shaft, const TriangleFilter& filter)
{
    const WorldTriangles& triangles = *filter.triangles;
    constexpr std::size_t kChunk = 2048;
    const std::size_t chunks = (triangles.size() + kChunk - 1) / kChunk;
    if (found_.size() < chunks) {
        found_.resize(chunks);
        foundTriangle_.resize(chunks);
    }
    std::atomic<std::size_t> culledCount{0};
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t chunk) {
        std::size_t chunkCulled = 0;
        found_[chunk].clear();
        foundTriangle_[chunk].clear();
        // Once, at the chunk's full size: growing by doubling copied every occluder about twice
        // on a sampler's first call.
        found_[chunk].reserve(kChunk);
        foundTriangle_[chunk].reserve(kChunk);
        for (std::size_t t = chunk * kChunk; t < std::min(triangles.size(), (chunk + 1) * kChunk); ++t) {
            if (filter.outsideShaft(t))
                continue;
            if (filter.culled(t)) {
                ++chunkCulled;
                continue;
            }
            // Prepared in place: an Occluder is a few hundred bytes, and copies of it showed in
            // profiles.
            Occluder& o = found_[chunk].emplace_back();
            const glm::vec3* v = filter.triangle(t);
            if (prepareOccluder(shaft, v[0], v[1], v[2], o))
                foundTriangle_[chunk].push_back(std::uint32_t(t));
            else
                found_[chunk].pop_back();
        }
        culledCount += chunkCulled;
    });
    occluders.clear();
    triangleOf.clear();
    for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
        for (const Occluder& o : found_[chunk])
            occluders.push_back(&o);
        triangleOf.insert(triangleOf.end(), foundTriangle_[chunk].begin(), foundTriangle_[chunk].end());
    }
    culledFrontFaces = culledCount;
}

} // namespace sightline::bitmask
