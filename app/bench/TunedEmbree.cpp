#include "bench/TunedEmbree.h"

#include <numeric>
#include <vector>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "visibility/Error.h"

namespace sightline::bench {

struct TunedEmbree::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~Impl()
    {
        if (scene)
            rtcReleaseScene(scene);
        if (device)
            rtcReleaseDevice(device);
    }
};

TunedEmbree::TunedEmbree(const WorldTriangles& triangles) : impl_(std::make_unique<Impl>())
{
    impl_->device = rtcNewDevice(nullptr);
    if (!impl_->device)
        throw Error("Embree: cannot create a device");
    impl_->scene = rtcNewScene(impl_->device);   // flat, not robust, default (medium) quality
    if (triangles.size() > 0) {
        RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree may read 16 bytes past a float3, so the vertex buffer is padded by one element.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), triangles.vertices.size() + 1));
        auto* indices = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles.size()));
        if (!vertices || !indices)
            throw Error("Embree: out of memory for " + std::to_string(triangles.size()) + " triangles");
        for (std::size_t i = 0; i < triangles.vertices.size(); ++i) {
            vertices[3 * i] = triangles.vertices[i].x;
            vertices[3 * i + 1] = triangles.vertices[i].y;
            vertices[3 * i + 2] = triangles.vertices[i].z;
        }
        for (std::size_t i = 0; i < 3 * triangles.size(); ++i)
            indices[i] = unsigned(i);
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(impl_->scene, geometry);
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(impl_->scene);
}

TunedEmbree::~TunedEmbree() = default;

HiddenSampleMap TunedEmbree::sample(const Patch& source, const Patch& receiver, int threads) const
{
    validatePatchPair(source, receiver);
    HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
    const int S = source.sampleCount();
    std::vector<glm::dvec3> sources(static_cast<std::size_t>(S));
    for (int i = 0; i < S; ++i)
        sources[std::size_t(i)] = source.sample(i);
    std::vector<int> order(static_cast<std::size_t>(S));
    std::iota(order.begin(), order.end(), 0);
    if (source.na % 4 == 0 && source.nb % 4 == 0)
        for (int k = 0; k < S; ++k) {
            const int block = k / 16, within = k % 16, across = source.na / 4;
            order[std::size_t(k)] = ((block / across) * 4 + within / 4) * source.na + (block % across) * 4 + within % 4;
        }
    RTCScene scene = impl_->scene;
    auto run = [&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, receiver.sampleCount(), 16), [&](const auto& range) {
            for (int j = range.begin(); j != range.end(); ++j) {
                const glm::dvec3 r = receiver.sample(j);
                const glm::vec3 origin(r);
                RTCIntersectContext context;
                rtcInitIntersectContext(&context);
                context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
                auto bits = map.row(j);
                alignas(64) RTCRay16 rays;
                alignas(64) int valid[16];
                for (int first = 0; first < S; first += 16) {
                    for (int k = 0; k < 16; ++k) {
                        const bool inside = first + k < S;
                        const int i = inside ? order[std::size_t(first + k)] : 0;
                        valid[k] = inside ? -1 : 0;
                        const glm::vec3 d(sources[std::size_t(i)] - r);
                        rays.org_x[k] = origin.x, rays.org_y[k] = origin.y, rays.org_z[k] = origin.z;
                        rays.dir_x[k] = d.x, rays.dir_y[k] = d.y, rays.dir_z[k] = d.z;
                        rays.tnear[k] = 1e-6f, rays.tfar[k] = 1.0f - 1e-6f;
                        rays.time[k] = 0.0f, rays.mask[k] = ~0u, rays.id[k] = unsigned(k), rays.flags[k] = 0;
                    }
                    rtcOccluded16(valid, scene, &context, &rays);
                    for (int k = 0; k < 16 && first + k < S; ++k)
                        if (rays.tfar[k] < 0.0f) {
                            const int i = order[std::size_t(first + k)];
                            bits[std::size_t(i >> 6)] |= std::uint64_t(1) << (i & 63);
                        }
                }
            }
        });
    };
    if (threads > 0)
        tbb::task_arena(threads).execute(run);
    else
        run();
    return map;
}

} // namespace sightline::bench
