// The editor's AO preview (editor/AoPreview.h) without a window: the whole level, placed objects
// included, darkens and is darkened; AO of a chosen object gets texels on that object only, at a
// finer density, the rest of the level still occluding.
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "editor/AoPreview.h"
#include "TestScenes.h"

using namespace sightline;
using namespace sightline::ui;

namespace {

/// A 10 x 10 m floor at y = 0 (instance 0) with a unit box standing on it at the origin (instance 1).
std::shared_ptr<const Scene> boxOnAFloor()
{
    Scene scene = test::sceneOf({test::quad({-5.0f, 0.0f, -5.0f}, {0.0f, 0.0f, 10.0f}, {10.0f, 0.0f, 0.0f}, "floor")});
    scene.addMeshInstance(test::closedBox(), glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.5f, 0.0f)));
    return std::make_shared<const Scene>(std::move(scene));
}

/// The levels a preview delivers (on its worker thread), and a wait for one.
struct Delivered {
    std::mutex mutex;
    std::condition_variable arrived;
    std::vector<AoPreviewLevel> levels;

    AoPreview::Deliver callback()
    {
        return [this](AoPreviewLevel level) {
            std::lock_guard lock(mutex);
            levels.push_back(std::move(level));
            arrived.notify_all();
        };
    }
    /// Until the last level delivered is generation `generation` at k = `k`, or an error (60 s at most).
    bool waitFor(std::uint64_t generation, int k)
    {
        std::unique_lock lock(mutex);
        return arrived.wait_for(lock, std::chrono::seconds(60), [&] {
            return !levels.empty() && (!levels.back().error.empty() || (levels.back().generation == generation && levels.back().k == k));
        });
    }
};

/// Runs the preview to `request.targetK` and returns every level delivered.
std::vector<AoPreviewLevel> run(AoPreviewRequest request)
{
    Delivered delivered;
    AoPreview preview(delivered.callback());
    const int target = request.targetK;
    preview.start(1, std::move(request));
    EXPECT_TRUE(delivered.waitFor(1, target)) << "the preview did not reach k = " << target;
    preview.stop();
    return delivered.levels;
}

/// The map's value at `point` of world triangle `t` (its uv interpolated from the corners').
float aoAt(const AoPreviewLevel& level, const WorldTriangles& triangles, std::size_t t, const glm::vec3& point)
{
    const glm::vec3 a = triangles.vertices[3 * t], b = triangles.vertices[3 * t + 1], c = triangles.vertices[3 * t + 2];
    const glm::vec3 n = glm::cross(b - a, c - a);
    const float area = glm::dot(n, n);
    const float wb = glm::dot(glm::cross(point - a, c - a), n) / area, wc = glm::dot(glm::cross(b - a, point - a), n) / area;
    const glm::vec2 uv = (1.0f - wb - wc) * level.uvs[3 * t] + wb * level.uvs[3 * t + 1] + wc * level.uvs[3 * t + 2];
    const int x = std::clamp(int(uv.x * float(level.width)), 0, level.width - 1);
    const int y = std::clamp(int(uv.y * float(level.height)), 0, level.height - 1);
    return level.map[std::size_t(y) * std::size_t(level.width) + std::size_t(x)].x;
}

/// The world triangle of `instance` that contains `point` (within its plane's tolerance).
std::size_t triangleAt(const WorldTriangles& triangles, std::uint32_t instance, const glm::vec3& point)
{
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        if (triangles.instanceOf[t] != instance)
            continue;
        const glm::vec3 a = triangles.vertices[3 * t], b = triangles.vertices[3 * t + 1], c = triangles.vertices[3 * t + 2];
        const glm::vec3 n = glm::cross(b - a, c - a);
        if (std::abs(glm::dot(glm::normalize(n), point - a)) > 1e-4f)
            continue;
        const float area = glm::dot(n, n);
        const float wb = glm::dot(glm::cross(point - a, c - a), n) / area, wc = glm::dot(glm::cross(b - a, point - a), n) / area;
        if (wb >= -1e-5f && wc >= -1e-5f && wb + wc <= 1.0f + 1e-5f)
            return t;
    }
    ADD_FAILURE() << "no triangle of instance " << instance << " holds the point";
    return 0;
}

} // namespace

TEST(AoPreview, TheWholeLevelIsShadedProgressivelyAndAPlacedObjectDarkensTheFloor)
{
    const auto scene = boxOnAFloor();
    const std::vector<AoPreviewLevel> levels = run({.scene = scene, .instances = {}, .targetK = 66});
    ASSERT_FALSE(levels.empty());
    ASSERT_TRUE(levels.back().error.empty()) << levels.back().error;
    std::vector<int> ks;
    for (const AoPreviewLevel& level : levels)
        ks.push_back(level.k);
    EXPECT_EQ(ks, (std::vector<int>{6, 18, 66}));   // coarse at once, then refined
    const AoPreviewLevel& level = levels.back();
    const WorldTriangles triangles = worldTriangles(*scene);
    ASSERT_EQ(level.uvs.size(), triangles.vertices.size());
    for (const glm::vec2& uv : level.uvs)
        EXPECT_GE(uv.x, 0.0f);   // every surface has texels
    EXPECT_EQ(level.density, 4.0);
    // Beside the box's foot the floor is darker than 4 m away from it (reach 2 m: nothing there).
    const glm::vec3 foot(0.6f, 0.0f, 0.0f), far(4.4f, 0.0f, 4.4f);
    const float nearAo = aoAt(level, triangles, triangleAt(triangles, 0, foot), foot);
    const float farAo = aoAt(level, triangles, triangleAt(triangles, 0, far), far);
    EXPECT_LT(nearAo, 0.85f);
    EXPECT_GT(farAo, 0.97f);
}

TEST(AoPreview, AChosenObjectGetsFinerTexelsAndTheLevelStillOccludesIt)
{
    const auto scene = boxOnAFloor();
    const std::vector<AoPreviewLevel> levels = run({.scene = scene, .instances = {1}, .targetK = 66});
    ASSERT_FALSE(levels.empty());
    ASSERT_TRUE(levels.back().error.empty()) << levels.back().error;
    const AoPreviewLevel& level = levels.back();
    const WorldTriangles triangles = worldTriangles(*scene);
    ASSERT_EQ(level.uvs.size(), triangles.vertices.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (std::size_t c = 0; c < 3; ++c) {
            if (triangles.instanceOf[t] == 0)
                EXPECT_LT(level.uvs[3 * t + c].x, 0.0f) << "the floor was not asked for";
            else
                EXPECT_GE(level.uvs[3 * t + c].x, 0.0f);
        }
    EXPECT_EQ(level.density, 16.0);   // the box's 6 m^2 alone: the finest preview density
    // 12 triangles of 1 m^2 at 16 texels a metre: at least 6 m^2 * 256 texels.
    EXPECT_GE(level.texels, std::size_t(6 * 256));
    // The floor, though not shaded, occludes: a side face is darker at its foot than at its top.
    const glm::vec3 bottom(0.5f, 0.05f, 0.0f), top(0.5f, 0.95f, 0.0f);
    const std::size_t t = triangleAt(triangles, 1, bottom);
    const float bottomAo = aoAt(level, triangles, t, bottom);
    const float topAo = aoAt(level, triangles, triangleAt(triangles, 1, top), top);
    EXPECT_LT(bottomAo, topAo - 0.1f) << "bottom " << bottomAo << ", top " << topAo;
}

TEST(AoPreview, ANewStartCancelsTheRunningOneWithoutWaitingAndOnlyItsAnswersFollow)
{
    const auto scene = boxOnAFloor();
    Delivered delivered;
    AoPreview preview(delivered.callback());
    // Ten restarts in a row, as a drag gives: each cancels the one before.
    for (std::uint64_t generation = 1; generation <= 10; ++generation)
        preview.start(generation, {.scene = scene, .instances = {}, .targetK = generation == 10 ? 66 : 1026});
    ASSERT_TRUE(delivered.waitFor(10, 66));
    preview.cancel();
    preview.stop();   // joins every worker, the cancelled ones too
    for (const AoPreviewLevel& level : delivered.levels) {
        EXPECT_TRUE(level.error.empty()) << level.error;
        // A cancelled run delivers nothing past its cancel: a k = 1026 level never completes.
        EXPECT_LT(level.k, 1026);
    }
}
