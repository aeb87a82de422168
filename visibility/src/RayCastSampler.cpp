#include "visibility/RayCastSampler.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "visibility/Error.h"

namespace sightline {

struct RayCastScene::Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::string error;

    ~Embree()
    {
        if (scene)
            rtcReleaseScene(scene);
        if (device)
            rtcReleaseDevice(device);
    }
};

namespace {

/// A single ray for the segment org -> org + dir with the reference's end-point semantics.
RTCRay segmentRay(const glm::vec3& org, const glm::vec3& dir)
{
    RTCRay ray{};
    ray.org_x = org.x, ray.org_y = org.y, ray.org_z = org.z;
    ray.dir_x = dir.x, ray.dir_y = dir.y, ray.dir_z = dir.z;
    ray.tnear = kSegmentEpsilon;
    ray.tfar = 1.0f - kSegmentEpsilon;
    ray.mask = 0xffffffffu;
    return ray;
}

void onEmbreeError(void* user, RTCError, const char* message)
{
    static_cast<std::string*>(user)->assign(message ? message : "unknown Embree error");
}

} // namespace

RayCastScene::RayCastScene(const Scene& scene) : RayCastScene(worldTriangles(scene)) {}

RayCastScene::RayCastScene(const WorldTriangles& triangles, bool fastBuild)
    : embree_(std::make_unique<Embree>()), triangleCount_(triangles.size())
{
    const auto start = std::chrono::steady_clock::now();
    embree_->device = rtcNewDevice(nullptr);
    if (!embree_->device)
        throw Error("Embree: cannot create a device (" + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(embree_->device, onEmbreeError, &embree_->error);

    embree_->scene = rtcNewScene(embree_->device);
    rtcSetSceneFlags(embree_->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(embree_->scene, fastBuild ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_HIGH);
    if (triangleCount_ > 0) {
        RTCGeometry geometry = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree may read 16 bytes past a float3, so the vertex buffer is padded by one element.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), triangles.vertices.size() + 1));
        auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangleCount_));
        if (!vertices || !indices)
            throw Error("Embree: out of memory for " + std::to_string(triangleCount_) + " triangles");
        for (std::size_t i = 0; i < triangles.vertices.size(); ++i) {
            vertices[3 * i + 0] = triangles.vertices[i].x;
            vertices[3 * i + 1] = triangles.vertices[i].y;
            vertices[3 * i + 2] = triangles.vertices[i].z;
        }
        for (std::size_t i = 0; i < 3 * triangleCount_; ++i)
            indices[i] = static_cast<unsigned>(i);
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(embree_->scene, geometry);
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(embree_->scene);
    if (!embree_->error.empty())
        throw Error("Embree: " + embree_->error);
    buildMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

RayCastScene::~RayCastScene() = default;

HiddenSampleMap RayCastScene::sample(const Patch& source, const Patch& receiver, const RayCastOptions& options) const
{
    validatePatchPair(source, receiver);
    HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
    sampleUnblocked(source, receiver, map, options);
    return map;
}

std::uint64_t RayCastScene::sampleUnblocked(const Patch& source, const Patch& receiver, HiddenSampleMap& map,
                                            const RayCastOptions& options) const
{
    if (map.sourceCount() != source.sampleCount() || map.receiverNa() != receiver.na || map.receiverNb() != receiver.nb)
        throw Error("RayCastScene::sampleUnblocked: map dimensions do not match the patches");
    // A bumpy receiver (§8): each ray starts at its displaced sample. All-zero heights are the
    // flat patch and take the flat path unchanged.
    if (options.heights)
        validateReceiverHeights(source, receiver, *options.heights);
    const bool bumpy = !flatReceiver(options.heights);
    if (triangleCount_ == 0)
        return 0;
    std::atomic<std::uint64_t> cast{0};
    const glm::dvec3 normal = bumpy ? receiverNormalTowardSource(source, receiver) : glm::dvec3(0.0);

    // Positions in double (DESIGN.md §2), rounded to float only as ray input.
    const int S = source.sampleCount();
    std::vector<glm::dvec3> sourceExact(static_cast<std::size_t>(S));
    for (int i = 0; i < S; ++i)
        sourceExact[std::size_t(i)] = source.sample(i);
    RTCScene scene = embree_->scene;

    // Each receiver sample casts its S rays: origin at the receiver sample, direction to the
    // source sample (t = 1 at the source), all sharing one origin, hence coherent.
    auto castFrom = [&](int j) {
        // With jitter, the source grid seen from j is shifted: cast to the shifted samples.
        const glm::dvec3 end =
            bumpy ? receiver.sample(j) + options.heights->metres[std::size_t(j)] * normal : receiver.sample(j);
        const glm::dvec3 r = end - options.jitter.shift(source, j);
        const glm::vec3 org(end);
        auto bits = map.row(j);
        std::uint64_t rowCast = 0;
        auto alreadyBlocked = [&](int i) { return (bits[std::size_t(i >> 6)] >> (i & 63)) & 1u; };
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        if (options.packets) {
            alignas(64) RTCRay16 rays;
            alignas(64) int valid[16];
            for (int first = 0; first < S; first += 16) {
                int lanes = 0;
                for (int k = 0; k < 16; ++k) {
                    const int i = first + k;
                    valid[k] = i < S && !alreadyBlocked(i) ? -1 : 0;
                    lanes += valid[k] != 0;
                    const glm::vec3 dir = i < S ? glm::vec3(sourceExact[std::size_t(i)] - r) : glm::vec3(1.0f);
                    rays.org_x[k] = org.x, rays.org_y[k] = org.y, rays.org_z[k] = org.z;
                    rays.dir_x[k] = dir.x, rays.dir_y[k] = dir.y, rays.dir_z[k] = dir.z;
                    rays.tnear[k] = kSegmentEpsilon;
                    rays.tfar[k] = 1.0f - kSegmentEpsilon;
                    rays.time[k] = 0.0f;
                    rays.mask[k] = 0xffffffffu;
                    rays.id[k] = unsigned(k);
                    rays.flags[k] = 0;
                }
                if (lanes == 0)
                    continue;
                rowCast += std::uint64_t(lanes);
                rtcOccluded16(valid, scene, &context, &rays);
                for (int k = 0; k < 16 && first + k < S; ++k)
                    if (valid[k] && rays.tfar[k] < 0.0f) {
                        const int i = first + k;
                        bits[std::size_t(i >> 6)] |= std::uint64_t(1) << (i & 63);
                    }
            }
        } else {
            for (int i = 0; i < S; ++i) {
                if (alreadyBlocked(i))
                    continue;
                ++rowCast;
                RTCRay ray = segmentRay(org, glm::vec3(sourceExact[std::size_t(i)] - r));
                rtcOccluded1(scene, &context, &ray);
                if (ray.tfar < 0.0f)
                    bits[std::size_t(i >> 6)] |= std::uint64_t(1) << (i & 63);
            }
        }
        cast += rowCast;
    };

    const std::vector<int>* subset = options.receiverSubset;
    const int receivers = subset ? int(subset->size()) : receiver.sampleCount();
    auto run = [&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, receivers, 16), [&](const tbb::blocked_range<int>& range) {
            for (int k = range.begin(); k != range.end(); ++k) {
                const int j = subset ? (*subset)[std::size_t(k)] : k;
                if (j < 0 || j >= receiver.sampleCount())
                    throw Error("RayCastScene::sampleUnblocked: receiver sample " + std::to_string(j) + " is outside the grid");
                castFrom(j);
            }
        });
    };
    if (options.threads > 0) {
        tbb::task_arena arena(options.threads);
        arena.execute(run);
    } else {
        run();
    }
    if (!embree_->error.empty())
        throw Error("Embree: " + embree_->error);
    return cast;
}

} // namespace sightline
