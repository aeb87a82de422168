#include "LitPreview.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <new>
#include <numbers>
#include <optional>

#include "AoPreview.h"
#include "TexelAtlas.h"
#include "lighting/DirectLight.h"
#include "lighting/LightingCache.h"
#include "lighting/ao/AoTexels.h"

namespace sightline::ui {

namespace {

LitPreviewFrame failed(std::uint64_t generation, std::string error)
{
    LitPreviewFrame frame;
    frame.generation = generation;
    frame.error = std::move(error);
    return frame;
}

/// The exposure that puts the 95th percentile of the lit texels' E / pi at 1 - e^-2 (0.86):
/// bright spots keep their shape, and the rest of the room is not lost in the dark.
double autoExposure(const std::vector<glm::dvec3>& irradiance)
{
    std::vector<double> lit;
    for (const glm::dvec3& e : irradiance)
        if (const double y = (0.2126 * e.r + 0.7152 * e.g + 0.0722 * e.b) / std::numbers::pi; y > 0.0)
            lit.push_back(y);
    if (lit.empty())
        return 1.0;
    const std::size_t at = std::min(lit.size() - 1, std::size_t(0.95 * double(lit.size())));
    std::nth_element(lit.begin(), lit.begin() + std::ptrdiff_t(at), lit.end());
    return 2.0 / lit[at];
}

} // namespace

LitTexels litTexels(const Scene& scene)
{
    LitTexels out;
    const WorldTriangles triangles = worldTriangles(scene);
    const TexelSurfaces sampled = texelSurfaces(triangles, {});
    if (sampled.worldTriangle.empty())
        return out;
    AoPoints texels;
    out.layout = aoTexelPoints(sampled.surfaces, previewTexelDensity(sampled.surfaces.vertices, 4.0), texels);
    // Lifted off their surface as `lights --texel` lifts them (the contract's ties).
    const double lift = kAoOffsetRelative * sampled.surfaces.diagonal();
    out.pointOfTexel.assign(texels.size(), SIZE_MAX);
    for (std::size_t k = 0; k < texels.size(); ++k)
        if (texels.status[k] == AoPointStatus::Ok) {
            out.pointOfTexel[k] = out.points.size();
            const glm::dvec3 n(texels.normals[k]);
            out.points.push_back({glm::dvec3(texels.positions[k]) + lift * n, n});
        }
    out.uvs = cornerUvs(triangles, sampled, out.layout);
    return out;
}

glm::vec3 toneMapped(const glm::dvec3& irradiance, double exposure)
{
    const glm::dvec3 x = irradiance * (exposure / std::numbers::pi);
    return glm::vec3(1.0 - std::exp(-x.r), 1.0 - std::exp(-x.g), 1.0 - std::exp(-x.b));
}

bool sameLight(const Light& a, const Light& b)
{
    const Patch &p = a.area, &q = b.area;
    return a.type == b.type && a.colour == b.colour && a.position == b.position && a.intensity == b.intensity &&
           a.range == b.range && a.direction == b.direction && a.innerAngle == b.innerAngle && a.outerAngle == b.outerAngle &&
           p.corner == q.corner && p.u == q.u && p.v == q.v && p.na == q.na && p.nb == q.nb && a.radiance == b.radiance &&
           a.twoSided == b.twoSided && a.clampMetres == b.clampMetres;
}

LitPreview::LitPreview(Deliver deliver) : deliver_(std::move(deliver)) {}

LitPreview::~LitPreview() { stop(); }

void LitPreview::cancel()
{
    if (current_.cancel) {
        current_.cancel->store(true);
        wake_.notify_all();
        retired_.push_back(std::move(current_));
        current_ = {};
    }
    reap(false);
}

void LitPreview::reap(bool wait)
{
    for (auto it = retired_.begin(); it != retired_.end();) {
        if (wait || it->done->load()) {
            if (it->thread.joinable())
                it->thread.join();
            it = retired_.erase(it);
            continue;
        }
        ++it;
    }
}

void LitPreview::stop()
{
    cancel();
    reap(true);
}

void LitPreview::setLights(std::vector<Light> lights)
{
    {
        std::lock_guard lock(mutex_);
        lights_ = std::move(lights);
        ++lightsVersion_;
    }
    wake_.notify_all();
}

void LitPreview::start(std::uint64_t generation, LitPreviewRequest request)
{
    cancel();
    {
        std::lock_guard lock(mutex_);
        lights_ = request.lights;
        ++lightsVersion_;
    }
    current_.cancel = std::make_shared<std::atomic<bool>>(false);
    current_.done = std::make_shared<std::atomic<bool>>(false);
    current_.thread = std::thread([this, generation, request = std::move(request), cancel = current_.cancel, done = current_.done] {
        struct Ended {
            std::atomic<bool>& done;
            ~Ended() { done.store(true); }
        } ended{*done};
        lowerThisThreadsPriority();
        const auto start = std::chrono::steady_clock::now();
        const auto since = [](std::chrono::steady_clock::time_point t) {
            return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
        };
        try {
            const LitTexels texels = litTexels(*request.scene);
            if (cancel->load())
                return;
            if (texels.points.empty()) {
                deliver_(failed(generation, "the level has no surfaces to light"));
                return;
            }
            const LightingScene scene(*request.scene);
            if (cancel->load())
                return;
            std::uint64_t version = 0;
            std::vector<Light> lights;
            {
                std::lock_guard lock(mutex_);
                lights = lights_;
                version = lightsVersion_;
            }
            auto cache = std::make_unique<LightingCache>(texels.points, lights);
            double exposure = 0.0;   // fixed once every light has been computed once
            for (;;) {
                const LightingCache::Frame step = cache->update(scene, request.segmentsPerFrame, 1);
                if (cancel->load())
                    return;
                const std::vector<glm::dvec3>& e = cache->irradiance();
                const double shownExposure = exposure > 0.0 ? exposure : autoExposure(e);
                if (exposure == 0.0 && step.exact)
                    exposure = shownExposure;
                std::vector<glm::vec3> colour(texels.pointOfTexel.size(), glm::vec3(0.0f));
                for (std::size_t k = 0; k < colour.size(); ++k)
                    if (texels.pointOfTexel[k] != SIZE_MAX)
                        colour[k] = toneMapped(e[texels.pointOfTexel[k]], shownExposure);
                LitPreviewFrame frame;
                frame.generation = generation;
                frame.uvs = texels.uvs;
                frame.width = texels.layout.width;
                frame.height = texels.layout.height;
                frame.map = atlasImage(texels.layout, colour, glm::vec3(0.0f));
                frame.texels = texels.points.size();
                frame.lights = lights.size();
                frame.refreshed = step.refreshed;
                frame.stale = step.stale;
                frame.exact = step.exact;
                frame.exposure = shownExposure;
                frame.frameMs = step.ms;
                frame.ms = since(start);
                deliver_(std::move(frame));
                // Exact: wait for new lights (or the end); else refresh the next stale ones.
                std::unique_lock lock(mutex_);
                if (step.exact)
                    wake_.wait(lock, [&] { return cancel->load() || lightsVersion_ != version; });
                if (cancel->load())
                    return;
                if (lightsVersion_ != version) {
                    version = lightsVersion_;
                    std::vector<Light> next = lights_;
                    lock.unlock();
                    if (next.size() != lights.size()) {
                        cache = std::make_unique<LightingCache>(texels.points, next);
                    } else {
                        for (std::size_t k = 0; k < next.size(); ++k)
                            if (!sameLight(next[k], lights[k]))
                                cache->setLight(k, next[k]);
                    }
                    lights = std::move(next);
                }
            }
        } catch (const std::bad_alloc&) {
            deliver_(failed(generation, "out of memory lighting the level"));
        } catch (const std::exception& e) {
            deliver_(failed(generation, e.what()));
        }
    });
}

LitPreviewFrame exactLitFrame(std::shared_ptr<const Scene> scene, std::vector<Light> lights)
{
    std::mutex mutex;
    std::condition_variable arrived;
    std::optional<LitPreviewFrame> last;
    LitPreview preview([&](LitPreviewFrame frame) {
        std::lock_guard lock(mutex);
        if (frame.exact || !frame.error.empty())
            last = std::move(frame);
        arrived.notify_all();
    });
    preview.start(1, {.scene = std::move(scene), .lights = std::move(lights), .segmentsPerFrame = std::uint64_t(1) << 40});
    std::unique_lock lock(mutex);
    arrived.wait(lock, [&] { return last.has_value(); });
    LitPreviewFrame out = std::move(*last);
    lock.unlock();
    preview.stop();
    return out;
}

} // namespace sightline::ui
