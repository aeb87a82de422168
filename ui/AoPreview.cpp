#include "AoPreview.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <new>

#include <glm/geometric.hpp>

#include "lighting/ao/AoBinnedCaster.h"
#include "lighting/ao/AoComputation.h"
#include "lighting/ao/AoShading.h"
#include "lighting/ao/AoTexels.h"

namespace sightline::ui {

namespace {

constexpr double kMaxTexels = 400'000.0;

AoPreviewLevel failed(std::uint64_t generation, std::string error)
{
    AoPreviewLevel level;
    level.generation = generation;
    level.error = std::move(error);
    return level;
}

/// Each corner's uv in the atlas, from its position in its triangle's tile frame (AoTexels.h),
/// so the mapping does not depend on the corner order of a mirrored instance.
std::vector<glm::vec2> cornerUvs(const Scene& scene, const AoTexelLayout& layout)
{
    const WorldTriangles triangles = worldTriangles(scene);
    std::vector<glm::vec2> uvs(triangles.vertices.size(), glm::vec2(-1.0f));
    for (const AoTexelTile& tile : layout.tiles) {
        const std::size_t t = tile.triangle;   // AoOccluders order: worldTriangles' order, instance by instance
        if (tile.width == 0 || t >= triangles.size())
            continue;
        for (std::size_t c = 0; c < 3; ++c) {
            const glm::vec3 d = triangles.vertices[3 * t + c] - tile.origin;
            const double s = double(tile.x) + double(glm::dot(d, tile.axisU)) * layout.density;
            const double r = double(tile.y) + double(glm::dot(d, tile.axisV)) * layout.density;
            uvs[3 * t + c] = glm::vec2(float(s / layout.width), float(r / layout.height));
        }
    }
    return uvs;
}

} // namespace

double previewTexelDensity(const Scene& scene)
{
    double area = 0.0;
    const WorldTriangles triangles = worldTriangles(scene);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::vec3* p = &triangles.vertices[3 * t];
        area += 0.5 * double(glm::length(glm::cross(p[1] - p[0], p[2] - p[0])));
    }
    // Texels ~ area * density^2 plus a tile's rounding per triangle.
    const double perTriangle = 2.0 * double(triangles.size());
    const double room = std::max(kMaxTexels - perTriangle, 0.25 * kMaxTexels);
    return std::clamp(std::sqrt(room / std::max(area, 1e-6)), 0.25, 4.0);
}

AoPreview::AoPreview(Deliver deliver) : deliver_(std::move(deliver)) {}

AoPreview::~AoPreview() { stop(); }

void AoPreview::stop()
{
    if (cancel_) {
        std::lock_guard lock(mutex_);
        cancel_->store(true);
    }
    wake_.notify_all();
    if (thread_.joinable())
        thread_.join();
    cancel_.reset();
}

void AoPreview::setLighting(AoLighting lighting)
{
    {
        std::lock_guard lock(mutex_);
        lighting_ = std::move(lighting);
        ++lightingVersion_;
    }
    wake_.notify_all();
}

void AoPreview::start(std::uint64_t generation, std::shared_ptr<const Scene> scene, double texelsPerMetre, int targetK,
                      double reach)
{
    stop();
    cancel_ = std::make_shared<std::atomic<bool>>(false);
    thread_ = std::thread([this, generation, scene = std::move(scene), texelsPerMetre, targetK, reach, cancel = cancel_] {
        const auto start = std::chrono::steady_clock::now();
        const auto ms = [&] { return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(); };
        try {
            const AoOccluders occluders = aoOccluders(*scene);
            if (occluders.triangleCount() == 0)
                return;
            AoPoints points;
            const AoTexelLayout layout = aoTexelPoints(occluders, texelsPerMetre, points);
            points.offsetOrigins(kAoOffsetRelative * occluders.diagonal());
            std::vector<glm::vec2> uvs = cornerUvs(*scene, layout);
            // One thread: the other core keeps the live rays and the frames going.
            AoBinnedCaster filler(occluders, AoBinnedOptions{.threads = 1, .maxDistance = reach});
            AoComputation computation(filler, points, targetK);
            const AoFillControl control{.cancel = cancel.get()};
            // One level lit as asked: plain AO for the uniform sky, else the environment's light
            // through the visible directions (AoRelighter: set up once per level, then one
            // multiply-add per visible bit for every change of environment, turn or exposure).
            std::unique_ptr<AoRelighter> relighter;
            const auto lit = [&](int k, const AoLighting& lighting) {
                std::vector<glm::vec3> colour(points.size());
                if (!lighting.environment) {
                    const std::vector<float> ao = ambientOcclusion(computation.matrix(), points, k);
                    for (std::size_t i = 0; i < ao.size(); ++i)
                        colour[i] = glm::vec3(ao[i]);
                    return colour;
                }
                if (!relighter || relighter->k() != k)
                    relighter = std::make_unique<AoRelighter>(computation.matrix(), points, k);
                return relighter->shade(lighting.environment->directionRadiance(aoDirections(k), lighting.rotationDegrees,
                                                                               lighting.exposureEv),
                                        1);
            };
            const auto deliverLevel = [&](int k, const AoLighting& lighting, bool relit) {
                const auto begun = std::chrono::steady_clock::now();
                const std::vector<glm::vec3> colour = lit(k, lighting);
                AoPreviewLevel level;
                level.generation = generation;
                level.k = k;
                level.targetK = targetK;
                level.relit = relit;
                level.width = layout.width;
                level.height = layout.height;
                level.map.assign(std::size_t(layout.width) * std::size_t(layout.height), glm::vec3(1.0f));
                const auto at = [&](int x, int y) -> glm::vec3& { return level.map[std::size_t(y) * std::size_t(layout.width) + std::size_t(x)]; };
                for (const AoTexelTile& tile : layout.tiles)
                    for (int t = 0; t < tile.height; ++t)
                        for (int s = 0; s < tile.width; ++s) {
                            const glm::vec3 v = colour[tile.firstPoint + std::size_t(t) * std::size_t(tile.width) + std::size_t(s)];
                            at(tile.x + s, tile.y + t) = std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) ? v : glm::vec3(1.0f);
                        }
                // The one-texel gutter around each tile takes its nearest texel: filtering at a
                // triangle's edge would otherwise mix in the gutter's 1 (bright lines along edges).
                for (const AoTexelTile& tile : layout.tiles) {
                    if (tile.width == 0)
                        continue;
                    for (int t = -1; t <= tile.height; ++t)
                        for (int s = -1; s <= tile.width; ++s) {
                            if (t >= 0 && t < tile.height && s >= 0 && s < tile.width)
                                continue;
                            const int gx = tile.x + s, gy = tile.y + t;
                            if (gx < 0 || gy < 0 || gx >= layout.width || gy >= layout.height)
                                continue;
                            at(gx, gy) = at(tile.x + std::clamp(s, 0, tile.width - 1), tile.y + std::clamp(t, 0, tile.height - 1));
                        }
                }
                level.uvs = uvs;   // every level carries them: the first one seen may be any
                // A level: time since the start; a relighting: its own time.
                level.ms = relit ? std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begun).count() : ms();
                deliver_(std::move(level));
            };
            const auto currentLighting = [&](std::uint64_t& version) {
                std::lock_guard lock(mutex_);
                version = lightingVersion_;
                return lighting_;
            };
            std::uint64_t version = 0;
            while (!computation.finished()) {
                if (!computation.refineLevel(control) || cancel->load())
                    return;
                deliverLevel(computation.completedK(), currentLighting(version), false);
            }
            // Finished: wait for a new lighting (relit from the matrix) or the end.
            for (;;) {
                {
                    std::unique_lock lock(mutex_);
                    wake_.wait(lock, [&] { return cancel->load() || lightingVersion_ != version; });
                    if (cancel->load())
                        return;
                }
                deliverLevel(computation.completedK(), currentLighting(version), true);
            }
        } catch (const std::bad_alloc&) {
            deliver_(failed(generation, "out of memory computing ambient occlusion"));
        } catch (const std::exception& e) {
            deliver_(failed(generation, e.what()));
        }
    });
}

} // namespace sightline::ui
