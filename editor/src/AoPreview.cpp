#include "editor/AoPreview.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <new>

#include <glm/geometric.hpp>

#include "editor/TexelAtlas.h"
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

} // namespace

double previewTexelDensity(const std::vector<glm::vec3>& corners, double maxDensity)
{
    double area = 0.0;
    const std::size_t triangles = corners.size() / 3;
    for (std::size_t t = 0; t < triangles; ++t) {
        const glm::vec3* p = &corners[3 * t];
        area += 0.5 * double(glm::length(glm::cross(p[1] - p[0], p[2] - p[0])));
    }
    // Texels ~ area * density^2 plus a tile's rounding per triangle.
    const double perTriangle = 2.0 * double(triangles);
    const double room = std::max(kMaxTexels - perTriangle, 0.25 * kMaxTexels);
    return std::clamp(std::sqrt(room / std::max(area, 1e-6)), 0.25, maxDensity);
}

AoPreview::AoPreview(Deliver deliver) : deliver_(std::move(deliver)) {}

AoPreview::~AoPreview() { stop(); }

void AoPreview::cancel() { worker_.cancel(); }

void AoPreview::stop() { worker_.stop(); }

void AoPreview::setLighting(AoLighting lighting)
{
    {
        std::lock_guard lock(mutex_);
        lighting_ = std::move(lighting);
        ++lightingVersion_;
    }
    wake_.notify_all();
}

void AoPreview::start(std::uint64_t generation, AoPreviewRequest request)
{
    worker_.start([this, generation, request = std::move(request)](std::shared_ptr<const std::atomic<bool>> cancel) {
        lowerThisThreadsPriority();
        const auto start = std::chrono::steady_clock::now();
        const auto ms = [&] { return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(); };
        const int targetK = request.targetK;
        try {
            const AoOccluders occluders = aoOccluders(*request.scene);
            if (occluders.triangleCount() == 0)
                return;
            const WorldTriangles triangles = worldTriangles(*request.scene);
            const TexelSurfaces sampled = texelSurfaces(triangles, request.instances);
            if (sampled.worldTriangle.empty() || cancel->load())
                return;
            const double density = previewTexelDensity(sampled.surfaces.vertices, request.instances.empty() ? 4.0 : 16.0);
            AoPoints points;
            const AoTexelLayout layout = aoTexelPoints(sampled.surfaces, density, points);
            points.offsetOrigins(kAoOffsetRelative * occluders.diagonal());
            if (cancel->load())
                return;
            std::vector<glm::vec2> uvs = cornerUvs(triangles, sampled, layout);
            // One thread: the other core keeps the live rays and the frames going.
            AoBinnedCaster filler(occluders, AoBinnedOptions{.threads = 1, .maxDistance = request.reach});
            if (cancel->load())
                return;
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
                level.texels = points.size();
                level.density = density;
                level.map = atlasImage(layout, colour, glm::vec3(1.0f));
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
