#include "lighting/ao/AoEmbree.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "base/Error.h"

namespace sightline {

struct AoEmbreeScene::Impl {
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

AoEmbreeScene::AoEmbreeScene(const AoOccluders& occluders) : impl_(std::make_unique<Impl>())
{
    impl_->device = rtcNewDevice(nullptr);
    if (!impl_->device)
        throw Error("Embree: cannot create a device");
    impl_->scene = rtcNewScene(impl_->device);
    if (occluders.triangleCount() > 0) {
        RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), occluders.vertices.size()));
        for (std::size_t i = 0; i < occluders.vertices.size(); ++i) {
            v[3 * i] = occluders.vertices[i].x;
            v[3 * i + 1] = occluders.vertices[i].y;
            v[3 * i + 2] = occluders.vertices[i].z;
        }
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), occluders.triangleCount()));
        for (std::size_t i = 0; i < occluders.indices.size(); ++i)
            idx[i] = occluders.indices[i];
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(impl_->scene, geometry);
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(impl_->scene);
}

AoEmbreeScene::~AoEmbreeScene() = default;

bool AoEmbreeScene::unblocked(const glm::vec3& origin, const glm::vec3& direction) const
{
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    ray.org_x = origin.x;
    ray.org_y = origin.y;
    ray.org_z = origin.z;
    ray.dir_x = direction.x;
    ray.dir_y = direction.y;
    ray.dir_z = direction.z;
    ray.tnear = 0.0f;
    ray.tfar = std::numeric_limits<float>::infinity();
    ray.mask = 0xffffffffu;
    rtcOccluded1(impl_->scene, &context, &ray);
    return ray.tfar >= 0.0f;   // Embree sets tfar to -inf on a hit
}

std::uint32_t AoEmbreeScene::unblocked16(const glm::vec3& origin, const glm::vec3& normal, const AoDirectionSet& set,
                                         int first, int last) const
{
    alignas(64) RTCRay16 rays;
    alignas(64) int valid[16];
    for (int k = 0; k < 16; ++k) {
        const int j = first + k;
        const glm::vec3 d = j < last ? set.directions[std::size_t(j)] : glm::vec3(0.0f, 0.0f, 1.0f);
        valid[k] = j < last && glm::dot(normal, d) > 0.0f ? -1 : 0;
        rays.org_x[k] = origin.x, rays.org_y[k] = origin.y, rays.org_z[k] = origin.z;
        rays.dir_x[k] = d.x, rays.dir_y[k] = d.y, rays.dir_z[k] = d.z;
        rays.tnear[k] = 0.0f, rays.tfar[k] = std::numeric_limits<float>::infinity();
        rays.time[k] = 0.0f, rays.mask[k] = 0xffffffffu, rays.id[k] = unsigned(k), rays.flags[k] = 0;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);   // incoherent: the 16 directions fan out over the hemisphere
    rtcOccluded16(valid, impl_->scene, &context, &rays);
    std::uint32_t open = 0;
    for (int k = 0; k < 16; ++k)
        open |= std::uint32_t(valid[k] != 0 && rays.tfar[k] >= 0.0f) << k;
    return open;
}

AoEmbreeCaster::AoEmbreeCaster(const AoOccluders& occluders, int threads, AoEmbreeTraversal traversal)
    : scene_(occluders), threads_(threads), traversal_(traversal)
{
}

bool AoEmbreeCaster::fill(const AoPoints& points, const AoDirectionSet& set, int first, int last, VisibilityMatrix& matrix,
                          const AoFillControl& control)
{
    std::atomic<bool> stopped{false};
    tbb::task_arena arena(threads_ > 0 ? threads_ : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
            if (control.cancelled()) {
                stopped = true;
                return;
            }
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                const glm::vec3 n = points.normals[i];
                if (traversal_ == AoEmbreeTraversal::DirectionPackets) {
                    for (int j0 = first; j0 < last; j0 += 16)
                        for (std::uint32_t open = scene_.unblocked16(points.origins[i], n, set, j0, std::min(last, j0 + 16));
                             open; open &= open - 1)
                            matrix.setVisible(i, j0 + std::countr_zero(open));
                    continue;
                }
                for (int j = first; j < last; ++j) {
                    const glm::vec3 d = set.directions[std::size_t(j)];
                    if (glm::dot(n, d) <= 0.0f)
                        continue;
                    if (scene_.unblocked(points.origins[i], d))
                        matrix.setVisible(i, j);
                }
            }
        });
    });
    if (!stopped)
        for (int j = first; j < last; ++j)
            control.finishedOne();
    return !stopped;
}

std::vector<float> monteCarloAo(const AoEmbreeScene& scene, const AoPoints& points, int rays, std::uint64_t seed, int threads)
{
    const int side = std::max(1, int(std::sqrt(double(rays))));
    std::vector<float> ao(points.size(), std::numeric_limits<float>::quiet_NaN());
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 16), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                if (points.status[i] != AoPointStatus::Ok)
                    continue;
                std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + i);
                std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
                const glm::vec3 n = points.normals[i];
                const glm::vec3 helper = std::abs(n.x) < 0.6f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
                glm::vec3 t = glm::normalize(glm::cross(helper, n));
                glm::vec3 b = glm::cross(n, t);
                const float spin = 6.2831853f * uniform(rng);
                const glm::vec3 t2 = std::cos(spin) * t + std::sin(spin) * b;
                b = glm::cross(n, t2);
                t = t2;
                int seen = 0;
                for (int sy = 0; sy < side; ++sy)
                    for (int sx = 0; sx < side; ++sx) {
                        // Malley: uniform on the disk, lifted to the hemisphere = cosine-weighted.
                        const float u1 = (float(sx) + uniform(rng)) / float(side);
                        const float u2 = (float(sy) + uniform(rng)) / float(side);
                        const float radius = std::sqrt(u1), phi = 6.2831853f * u2;
                        const float x = radius * std::cos(phi), y = radius * std::sin(phi);
                        const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
                        const glm::vec3 d = glm::normalize(x * t + y * b + z * n);
                        seen += scene.unblocked(points.origins[i], d);
                    }
                ao[i] = float(seen) / float(side * side);
            }
        });
    });
    return ao;
}

} // namespace sightline
