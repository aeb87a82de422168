#include "bench/TunedEmbree.h"

#include <bit>
#include <functional>
#include <numeric>
#include <vector>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "visibility/EmbreeTriangles.h"

namespace sightline::bench {

/// Flat, not robust, Embree's default (medium) build quality.
struct TunedEmbree::Impl {
    EmbreeSoupScene soup;
    explicit Impl(const WorldTriangles& triangles) : soup(triangles.vertices, RTC_SCENE_FLAG_NONE, RTC_BUILD_QUALITY_MEDIUM) {}
};

TunedEmbree::TunedEmbree(const WorldTriangles& triangles) : impl_(std::make_unique<Impl>(triangles)) {}

TunedEmbree::~TunedEmbree() = default;

std::string TunedTraversal::name() const
{
    return std::string(fromSource ? "from-source" : "from-receiver") + (coherent ? " coherent" : " incoherent");
}

std::vector<TunedTraversal> tunedTraversals()
{
    return {{false, true}, {false, false}, {true, true}, {true, false}};
}

namespace {

/// Sample indices of an na x nb grid in 4x4 blocks where the grid allows (more coherent packets
/// than 16 along a row on every bench scene), else in grid order.
std::vector<int> fourByFourOrder(int na, int nb)
{
    std::vector<int> order(std::size_t(na) * std::size_t(nb));
    std::iota(order.begin(), order.end(), 0);
    if (na % 4 == 0 && nb % 4 == 0)
        for (int k = 0; k < na * nb; ++k) {
            const int block = k / 16, within = k % 16, across = na / 4;
            order[std::size_t(k)] = ((block / across) * 4 + within / 4) * na + (block % across) * 4 + within % 4;
        }
    return order;
}

} // namespace

HiddenSampleMap TunedEmbree::sample(const Patch& source, const Patch& receiver, int threads, TunedTraversal traversal) const
{
    validatePatchPair(source, receiver);
    HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
    const int S = source.sampleCount();
    std::vector<glm::dvec3> sources(static_cast<std::size_t>(S));
    for (int i = 0; i < S; ++i)
        sources[std::size_t(i)] = source.sample(i);
    RTCScene scene = impl_->soup.scene;
    const RTCIntersectContextFlags flags =
        traversal.coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    // Casts up to 16 segments from `origin` (lane k to origin + dirs[k]); returns the occluded lanes.
    const auto cast16 = [&](const glm::dvec3& origin, const glm::dvec3* dirs, int lanes) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = flags;
        alignas(64) RTCRay16 rays;
        alignas(64) int valid[16];
        const glm::vec3 org(origin);
        for (int k = 0; k < 16; ++k) {
            valid[k] = k < lanes ? -1 : 0;
            const glm::vec3 d(k < lanes ? dirs[k] : glm::dvec3(1.0));
            rays.org_x[k] = org.x, rays.org_y[k] = org.y, rays.org_z[k] = org.z;
            rays.dir_x[k] = d.x, rays.dir_y[k] = d.y, rays.dir_z[k] = d.z;
            rays.tnear[k] = 1e-6f, rays.tfar[k] = 1.0f - 1e-6f;
            rays.time[k] = 0.0f, rays.mask[k] = ~0u, rays.id[k] = unsigned(k), rays.flags[k] = 0;
        }
        rtcOccluded16(valid, scene, &context, &rays);
        std::uint32_t occluded = 0;
        for (int k = 0; k < lanes; ++k)
            occluded |= std::uint32_t(rays.tfar[k] < 0.0f) << k;
        return occluded;
    };
    std::function<void()> run;
    const std::vector<int> order =
        traversal.fromSource ? fourByFourOrder(receiver.na, receiver.nb) : fourByFourOrder(source.na, source.nb);
    if (!traversal.fromSource) {
        // From each receiver sample to 4x4 blocks of source samples.
        run = [&] {
            tbb::parallel_for(tbb::blocked_range<int>(0, receiver.sampleCount(), 16), [&](const auto& range) {
                glm::dvec3 dirs[16];
                for (int j = range.begin(); j != range.end(); ++j) {
                    const glm::dvec3 r = receiver.sample(j);
                    auto bits = map.row(j);
                    for (int first = 0; first < S; first += 16) {
                        const int lanes = std::min(16, S - first);
                        for (int k = 0; k < lanes; ++k)
                            dirs[k] = sources[std::size_t(order[std::size_t(first + k)])] - r;
                        for (std::uint32_t hit = cast16(r, dirs, lanes); hit; hit &= hit - 1) {
                            const int i = order[std::size_t(first + std::countr_zero(hit))];
                            bits[std::size_t(i >> 6)] |= std::uint64_t(1) << (i & 63);
                        }
                    }
                }
            });
        };
    } else {
        // From each source sample to 4x4 blocks of receiver samples.
        run = [&, R = receiver.sampleCount()] {
            const int blocks = (R + 15) / 16;
            tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const auto& range) {
                glm::dvec3 ends[16], dirs[16];
                for (int b = range.begin(); b != range.end(); ++b) {
                    const int first = 16 * b, lanes = std::min(16, R - first);
                    for (int k = 0; k < lanes; ++k)
                        ends[k] = receiver.sample(order[std::size_t(first + k)]);
                    for (int i = 0; i < S; ++i) {
                        for (int k = 0; k < lanes; ++k)
                            dirs[k] = ends[k] - sources[std::size_t(i)];
                        for (std::uint32_t hit = cast16(sources[std::size_t(i)], dirs, lanes); hit; hit &= hit - 1)
                            map.setBlocked(order[std::size_t(first + std::countr_zero(hit))], i);
                    }
                }
            });
        };
    }
    if (threads > 0)
        tbb::task_arena(threads).execute(run);
    else
        run();
    return map;
}

} // namespace sightline::bench
