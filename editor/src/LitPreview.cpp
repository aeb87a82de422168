#include "editor/LitPreview.h"

#include "editor/LitIndirect.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <new>
#include <numbers>
#include <optional>
#include <utility>

#include "editor/AoPreview.h"
#include "editor/CameraVisibility.h"
#include "editor/LitReference.h"
#include "editor/TexelAtlas.h"
#include "lighting/DirectLight.h"
#include "lighting/LightEmission.h"
#include "lighting/LightingCache.h"
#include "lighting/LowResolutionPass.h"
#include "lighting/SceneChange.h"
#include "lighting/ao/AoTexels.h"
#include "base/Error.h"

namespace sightline::ui {

namespace {

/// Texels between the low-resolution pass's coarse points (LowResolutionPass.h).
constexpr int kLowResolutionStride = 3;
/// After a dragged light's low-resolution pass, how long its next move may take before its exact
/// refresh starts (a drag moves it every frame the window draws; the exact refresh of an area
/// light over every texel takes several of them, and cannot be cut short).
constexpr std::chrono::milliseconds kDragSettle{60};
/// Error: the reference's lights computed between two frames (at least one).
constexpr double kReferenceMsPerFrame = 250.0;

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

/// Per point, how many computed lights give it light (their kept field > 0).
std::vector<std::size_t> lightsReaching(const LightingCache& cache, std::size_t lights)
{
    std::vector<std::size_t> count(cache.points().size(), 0);
    for (std::size_t l = 0; l < lights; ++l) {
        const std::vector<float>& field = cache.field(l);
        for (std::size_t j = 0; j < field.size(); ++j)
            count[j] += field[j] > 0.0f ? 1 : 0;
    }
    return count;
}

/// Per point, of the lights whose unshadowed terms reach it: which light it wholly, partly or not
/// at all once shadowed (their kept field against the unshadowed sum of their emitters' terms).
/// A light not yet computed counts as shadowed. Unshadowed sums are summed in the same order as
/// the field's, so "wholly" allows float rounding alone.
std::vector<TexelLightCounts> lightCounts(const LightingCache& cache, const std::vector<Light>& lights, const LightingScene& scene)
{
    const std::vector<ShadingPoint>& points = cache.points();
    std::vector<TexelLightCounts> counts(points.size());
    const std::vector<Emitter> emitters = lightEmitters(lights);
    std::size_t first = 0;
    for (std::size_t l = 0; l < lights.size(); ++l) {
        std::size_t last = first;
        while (last < emitters.size() && emitters[last].light == l)
            ++last;
        const std::vector<float>& field = cache.field(l);
        for (std::size_t j = 0; j < points.size(); ++j) {
            double open = 0.0;
            for (std::size_t e = first; e < last; ++e) {
                const glm::dvec3 at = lights[l].type == LightType::Directional ? scene.reach().end(lights[l], points[j].position)
                                                                               : emitters[e].position;
                open += emitterTerm(lights[l], at, points[j].position, points[j].normal);
            }
            if (open <= 0.0)
                continue;
            const double shadowed = field.empty() ? 0.0 : double(field[j]);
            TexelLightCounts& c = counts[j];
            if (shadowed <= 0.0)
                ++c.shadowed;
            else if (shadowed >= open * (1.0 - 1e-5))
                ++c.lit;
            else
                ++c.partial;
        }
        first = last;
    }
    return counts;
}

/// The points' colours for `frame.shading`, and the frame's counts. `reference`: Error's
/// reference irradiance, empty while it is computed.
std::vector<glm::vec3> shadePoints(const LitTexels& texels, const LightingCache& cache, const std::vector<Light>& lights,
                                   const LightingScene& scene, const std::vector<glm::dvec3>& reference,
                                   const LitIndirect* indirect, LitPreviewFrame& frame)
{
    const std::vector<glm::dvec3>& direct = cache.irradiance();
    // The light shown: direct, plus the bounce when asked for (the error is the direct light's).
    std::vector<glm::dvec3> withBounce;
    if (indirect && frame.shading != LitShading::Error) {
        withBounce = direct;
        for (std::size_t j = 0; j < withBounce.size(); ++j)
            withBounce[j] += indirect->irradiance()[j];
    }
    const std::vector<glm::dvec3>& e = withBounce.empty() ? direct : withBounce;
    std::vector<glm::vec3> perPoint(texels.points.size());
    switch (frame.shading) {
    case LitShading::Light:
        for (std::size_t j = 0; j < perPoint.size(); ++j)
            perPoint[j] = toneMapped(e[j], frame.exposure);
        break;
    case LitShading::Staleness: {
        const std::vector<float> stale = cache.staleness();
        for (std::size_t j = 0; j < perPoint.size(); ++j) {
            const glm::vec3 grey(toneMapped(e[j], frame.exposure).g);
            perPoint[j] = glm::mix(0.3f + 0.7f * grey, glm::vec3(0.95f, 0.1f, 0.1f), stale[j]);
        }
        break;
    }
    case LitShading::Overlap: {
        const std::vector<std::size_t> count = lightsReaching(cache, lights.size());
        std::size_t lit = 0, over = 0;
        for (std::size_t j = 0; j < perPoint.size(); ++j) {
            perPoint[j] = overlapColour(count[j], frame.budget);
            lit += count[j] > 0 ? 1 : 0;
            over += count[j] > std::size_t(frame.budget) ? 1 : 0;
            frame.mostLights = std::max(frame.mostLights, count[j]);
        }
        frame.overBudget = lit > 0 ? double(over) / double(lit) : 0.0;
        break;
    }
    case LitShading::Complexity: {
        const std::vector<TexelLightCounts> counts = lightCounts(cache, lights, scene);
        double shadowedSum = 0.0;
        std::size_t reached = 0;
        for (std::size_t j = 0; j < perPoint.size(); ++j) {
            perPoint[j] = complexityColour(counts[j], frame.budget);
            const std::size_t all = std::size_t(counts[j].lit) + counts[j].partial + counts[j].shadowed;
            if (all > 0) {
                ++reached;
                shadowedSum += double(counts[j].partial) + double(counts[j].shadowed);
            }
            frame.mostLights = std::max(frame.mostLights, all);
        }
        frame.meanShadowed = reached > 0 ? shadowedSum / double(reached) : 0.0;
        break;
    }
    case LitShading::Error: {
        if (reference.empty()) {   // still computing: the light in grey
            for (std::size_t j = 0; j < perPoint.size(); ++j)
                perPoint[j] = glm::vec3(0.15f + 0.5f * toneMapped(e[j], frame.exposure).g);
            break;
        }
        const std::vector<float> error = relativeError(e, reference);
        std::size_t lit = 0, over = 0;
        for (std::size_t j = 0; j < perPoint.size(); ++j) {
            perPoint[j] = errorColour(error[j]);
            frame.errorMax = std::max(frame.errorMax, double(error[j]));
            if (reference[j] != glm::dvec3(0.0) || e[j] != glm::dvec3(0.0)) {
                ++lit;
                over += error[j] > 0.01f ? 1 : 0;
            }
        }
        frame.errorOverPercent = lit > 0 ? 100.0 * double(over) / double(lit) : 0.0;
        break;
    }
    }
    return perPoint;
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
    out.uvs = std::make_shared<const std::vector<glm::vec2>>(cornerUvs(triangles, sampled, out.layout));
    out.pointOfPixel = atlasSources(out.layout);
    for (std::uint32_t& source : out.pointOfPixel)
        if (source != kBlankPixel)
            source = out.pointOfTexel[source] == SIZE_MAX ? kBlankPixel : std::uint32_t(out.pointOfTexel[source]);
    return out;
}

glm::vec3 toneMapped(const glm::dvec3& irradiance, double exposure)
{
    // In float: the result is shown in 8 bits, and every texel is mapped every frame.
    const glm::vec3 x(irradiance * (exposure / std::numbers::pi));
    return glm::vec3(1.0f - std::exp(-x.r), 1.0f - std::exp(-x.g), 1.0f - std::exp(-x.b));
}

glm::vec3 overlapColour(std::size_t lights, int budget)
{
    if (lights == 0)
        return glm::vec3(0.08f, 0.08f, 0.1f);
    if (lights > std::size_t(budget))   // over: red, brighter the further over
        return glm::mix(glm::vec3(0.6f, 0.05f, 0.05f), glm::vec3(1.0f, 0.2f, 0.6f),
                        std::min(1.0f, float(lights - std::size_t(budget)) / float(std::max(budget, 1))));
    const float t = budget > 1 ? float(lights - 1) / float(budget - 1) : 1.0f;
    return glm::mix(glm::vec3(0.15f, 0.7f, 0.3f), glm::vec3(1.0f, 0.85f, 0.2f), t);
}

glm::vec3 complexityColour(const TexelLightCounts& counts, int budget)
{
    const float all = float(counts.lit) + float(counts.partial) + float(counts.shadowed);
    if (all == 0.0f)
        return glm::vec3(0.08f, 0.08f, 0.1f);
    const glm::vec3 mix = (float(counts.lit) * glm::vec3(0.2f, 0.85f, 0.3f) + float(counts.partial) * glm::vec3(0.25f, 0.45f, 1.0f) +
                           float(counts.shadowed) * glm::vec3(0.9f, 0.15f, 0.1f)) /
                          all;
    // Brighter with more lights, full at the budget.
    return mix * (0.35f + 0.65f * std::min(1.0f, all / float(std::max(budget, 1))));
}

void LitPreview::requestSets(std::optional<SetsRequest> request)
{
    {
        std::lock_guard lock(mutex_);
        setsRequest_ = std::move(request);
        ++setsVersion_;
    }
    wake_.notify_all();
}

void LitPreview::recycle(std::vector<glm::vec3> map)
{
    std::lock_guard lock(mutex_);
    if (map.capacity() > spareMap_.capacity())
        spareMap_ = std::move(map);
}

void LitPreview::setIndirect(bool on)
{
    {
        std::lock_guard lock(mutex_);
        indirect_ = on;
        ++shadingVersion_;   // shown otherwise: the worker wakes
    }
    wake_.notify_all();
}

void LitPreview::setShading(LitShading shading, int budget)
{
    {
        std::lock_guard lock(mutex_);
        shading_ = shading;
        budget_ = std::max(budget, 1);
        ++shadingVersion_;
    }
    wake_.notify_all();
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

void LitPreview::cancel() { worker_.cancel(); }

void LitPreview::stop() { worker_.stop(); }

std::uint64_t LitPreview::setLights(std::vector<Light> lights)
{
    std::uint64_t version = 0;
    {
        std::lock_guard lock(mutex_);
        lights_ = std::move(lights);
        version = ++lightsVersion_;
    }
    wake_.notify_all();
    return version;
}

/// The worker's state between frames: the texels, the scene as lighting asks about it, the kept
/// lights (LightingCache) and what the overlays keep, and the steps of one frame.
class LitPreview::Session {
public:
    Session(LitPreview& owner, std::uint64_t generation, LitPreviewRequest request, std::shared_ptr<const std::atomic<bool>> cancel)
        : owner_(owner), generation_(generation), request_(std::move(request)), cancel_(std::move(cancel)),
          sceneShared_(request_.scene)
    {
    }

    /// Frames until cancelled; a failure is delivered as the frame's error.
    void run()
    {
        try {
            if (!prepare())
                return;
            for (;;) {
                refreshLights();
                if (cancelled())
                    return;
                LitPreviewFrame frame = nextFrame();
                if (cancelled())
                    return;
                const bool settled = frame.exact;
                deliver(std::move(frame));
                if (!waitForWork(settled))
                    return;
            }
        } catch (const std::bad_alloc&) {
            deliver(failed(generation_, "out of memory lighting the level"));
        } catch (const std::exception& e) {
            deliver(failed(generation_, e.what()));
        }
    }

private:
    bool cancelled() const { return cancel_->load(); }
    void deliver(LitPreviewFrame frame) { owner_.deliver_(std::move(frame)); }

    /// The texels, the lighting scene and the cache of the lights as they are now.
    bool prepare()
    {
        {
            // The version read with what it versions: a scene set since start() is this one's.
            std::lock_guard lock(owner_.mutex_);
            if (cancelled())
                return false;   // a scene set now is the next worker's
            lights_ = owner_.lights_;
            version_ = owner_.lightsVersion_;
            if (owner_.sceneChange_)
                sceneShared_ = std::exchange(owner_.sceneChange_, nullptr);
        }
        texels_ = litTexels(*sceneShared_);
        if (cancelled())
            return false;
        if (texels_.points.empty()) {
            deliver(failed(generation_, "the level has no surfaces to light"));
            return false;
        }
        scene_ = std::make_unique<LightingScene>(*sceneShared_);
        if (cancelled())
            return false;
        cache_ = std::make_unique<LightingCache>(texels_.points, lights_, plan(texels_));
        return true;
    }

    /// Barczak's low-resolution pass for dragged lights: every third texel, edges refined.
    static LowResolutionPlan plan(const LitTexels& texels)
    {
        return lowResolutionPlan(texels.layout, texels.pointOfTexel, kLowResolutionStride, texels.points);
    }

    void refreshLights()
    {
        if (refresh_) {
            // A frame with a dragged light's low-resolution pass is what the designer waits for:
            // every core (the GUI's frame meanwhile only lights its cached level again,
            // LevelRelight.h); the exact refreshes between moves leave a core to the GUI.
            step_ = cache_->update(*scene_, request_.segmentsPerFrame, roughPending_ ? 0 : 1);
            roughPending_ = false;
        } else {   // the same light shown otherwise: nothing refreshed
            const bool exact = step_.exact;
            step_ = {};
            step_.exact = exact;
        }
    }

    /// O'Rorke's sets of the requested light, computed again when asked or when the lights or
    /// the scene changed.
    void updateSets(const std::optional<SetsRequest>& wanted, bool changed)
    {
        if (!changed)
            return;
        setsStale_ = false;
        sets_.reset();
        if (wanted && wanted->light < lights_.size()) {
            const std::vector<std::uint32_t> seen = wanted->visible ? *wanted->visible : visibleInstances(wanted->camera, *scene_);
            LightSetOptions options;
            options.threads = 1;
            if (wanted->reach) {
                options.restricted = {true};
                options.candidates = {*wanted->reach};
            }
            sets_ = lightSets(*scene_, *sceneShared_, {lights_[wanted->light]}, seen, options).front();
            setsLight_ = wanted->light;
            setsServed_ = wanted->visible.has_value();
        }
    }

    /// The bounce: traced when first asked for, refined once the direct light is exact.
    void updateIndirect(bool wanted)
    {
        if (!wanted) {
            indirect_.reset();
            return;
        }
        if (!indirect_) {
            indirect_ = std::make_unique<LitIndirect>(texels_.points);
            indirect_->setLights(*scene_, lights_);
        }
        if (step_.exact)
            indirect_->update(*scene_, request_.segmentsPerFrame);
    }

    LitPreviewFrame nextFrame()
    {
        LitPreviewFrame frame;
        std::optional<SetsRequest> setsWanted;
        bool setsChanged = false;
        bool indirectWanted = false;
        {
            std::lock_guard lock(owner_.mutex_);
            frame.shading = owner_.shading_;
            frame.budget = owner_.budget_;
            indirectWanted = owner_.indirect_;
            shadingSeen_ = owner_.shadingVersion_;
            setsWanted = owner_.setsRequest_;
            setsChanged = owner_.setsVersion_ != setsSeen_ || (setsStale_ && setsWanted);
            setsSeen_ = owner_.setsVersion_;
        }
        updateSets(setsWanted, setsChanged);
        frame.sets = sets_;
        frame.setsLight = setsLight_;
        frame.setsServed = setsServed_;
        updateIndirect(indirectWanted);
        const double shownExposure = exposure_ > 0.0 ? exposure_ : autoExposure(cache_->irradiance());
        if (exposure_ == 0.0 && step_.exact)
            exposure_ = shownExposure;   // fixed once every light has been computed once
        frame.generation = generation_;
        frame.exposure = shownExposure;
        // Error: the reference of the lights as they are now, a few lights a frame.
        std::vector<glm::dvec3> referenceShown;
        referencePending_ = false;
        if (frame.shading == LitShading::Error) {
            referencePending_ = !reference_.update(*scene_, texels_.points, lights_, kReferenceMsPerFrame);
            frame.referenceLights = reference_.current(lights_);
            if (!referencePending_)
                referenceShown = reference_.irradiance(lights_, texels_.points.size());
        }
        const std::vector<glm::vec3> colour = shadePoints(texels_, *cache_, lights_, *scene_, referenceShown, indirect_.get(), frame);
        frame.uvs = texels_.uvs;
        frame.width = texels_.layout.width;
        frame.height = texels_.layout.height;
        {
            std::lock_guard lock(owner_.mutex_);
            frame.map = std::exchange(owner_.spareMap_, {});
        }
        gatherAtlas(texels_.pointOfPixel, colour, glm::vec3(0.0f), frame.map);
        frame.texels = texels_.points.size();
        frame.lights = lights_.size();
        frame.refreshed = step_.refreshed;
        frame.rough = step_.rough;
        frame.costs.reserve(lights_.size());
        for (std::size_t l = 0; l < lights_.size(); ++l)
            frame.costs.push_back(cache_->cost(l));
        frame.stale = cache_->staleCount();
        frame.indirect = indirect_ != nullptr;
        frame.vpls = indirect_ ? indirect_->vpls() : 0;
        frame.exact = step_.exact && (!indirect_ || indirect_->exact());
        frame.lightsVersion = version_;
        frame.frameMs = step_.ms;
        frame.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started_).count();
        return frame;
    }

    /// Exact: waits for new lights or a new scene, another shading or the end; else goes on to
    /// refresh the next stale lights. Takes what changed. False once cancelled.
    bool waitForWork(bool settled)
    {
        std::unique_lock lock(owner_.mutex_);
        if (settled && !referencePending_)
            owner_.wake_.wait(lock, [&] {
                return cancelled() || owner_.lightsVersion_ != version_ || owner_.shadingVersion_ != shadingSeen_ ||
                       owner_.setsVersion_ != setsSeen_;
            });
        else if (step_.rough > 0)   // a light being dragged: its next move, if it comes soon, rather than its exact refresh
            owner_.wake_.wait_for(lock, kDragSettle, [&] { return cancelled() || owner_.lightsVersion_ != version_; });
        if (cancelled())
            return false;
        refresh_ = !step_.exact || owner_.lightsVersion_ != version_;   // (else only the reference goes on)
        if (owner_.lightsVersion_ == version_)
            return true;
        version_ = owner_.lightsVersion_;
        std::vector<Light> next = owner_.lights_;
        std::shared_ptr<const Scene> nextScene = std::exchange(owner_.sceneChange_, nullptr);
        lock.unlock();
        if (nextScene)
            takeScene(std::move(nextScene));
        takeLights(std::move(next));
        return !cancelled();
    }

    /// The lights changed: those whose entry differs get the low-resolution pass, then the exact
    /// one; a changed count starts the fields again.
    void takeLights(std::vector<Light> next)
    {
        if (next.size() != lights_.size()) {
            cache_ = std::make_unique<LightingCache>(texels_.points, next, plan(texels_));
        } else {
            bool changed = false;
            for (std::size_t k = 0; k < next.size(); ++k)
                if (!sameLight(next[k], lights_[k])) {
                    cache_->setLight(k, next[k], /*rough=*/true);
                    changed = roughPending_ = true;
                }
            if (!changed)
                return;
        }
        lights_ = std::move(next);
        setsStale_ = true;
        if (indirect_)
            indirect_->setLights(*scene_, lights_);
    }

    /// The scene changed (an occluder moved, was added or removed): texels that stayed keep
    /// their light, and each light refreshes only the texels whose shadow segments could pass
    /// where the scene changed (LightingCache::sceneChanged).
    void takeScene(std::shared_ptr<const Scene> next)
    {
        LitTexels texels = litTexels(*next);
        if (texels.points.empty())
            throw Error("the level has no surfaces to light");
        auto scene = std::make_unique<LightingScene>(*next);
        const std::vector<Bounds> regions = changedRegions(scene_->triangles(), scene->triangles());
        const std::vector<std::size_t> previous = matchPoints(texels_.points, texels.points);
        cache_->sceneChanged(regions, texels.points, previous, plan(texels));
        texels_ = std::move(texels);
        scene_ = std::move(scene);
        sceneShared_ = std::move(next);
        reference_ = {};
        setsStale_ = true;
        refresh_ = true;
        if (indirect_) {
            indirect_ = std::make_unique<LitIndirect>(texels_.points);
            indirect_->setLights(*scene_, lights_);
        }
    }

    LitPreview& owner_;
    const std::uint64_t generation_;
    const LitPreviewRequest request_;
    const std::shared_ptr<const std::atomic<bool>> cancel_;
    const std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();

    std::shared_ptr<const Scene> sceneShared_;
    LitTexels texels_;
    std::unique_ptr<LightingScene> scene_;
    std::vector<Light> lights_;
    std::uint64_t version_ = 0;
    std::unique_ptr<LightingCache> cache_;
    LightingCache::Frame step_;
    bool refresh_ = true;
    bool roughPending_ = false;   ///< a light was set rough since the last refresh
    double exposure_ = 0.0;
    std::uint64_t shadingSeen_ = 0, setsSeen_ = 0;
    std::optional<LightSets> sets_;
    std::size_t setsLight_ = 0;
    bool setsServed_ = false;
    bool setsStale_ = false;   // the lights or the scene changed since the sets were computed
    LitReference reference_;
    bool referencePending_ = false;
    std::unique_ptr<LitIndirect> indirect_;   // while one bounce is asked for
};

std::uint64_t LitPreview::start(std::uint64_t generation, LitPreviewRequest request)
{
    cancel();
    std::uint64_t started = 0;
    {
        std::lock_guard lock(mutex_);
        lights_ = request.lights;
        started = ++lightsVersion_;
        shading_ = request.shading;
        budget_ = std::max(request.budget, 1);
        indirect_ = request.indirect;
        sceneChange_.reset();
    }
    worker_.start([this, generation, request = std::move(request)](std::shared_ptr<const std::atomic<bool>> cancel) {
        lowerThisThreadsPriority();
        Session(*this, generation, std::move(request), std::move(cancel)).run();
    });
    return started;
}

std::uint64_t LitPreview::setScene(std::shared_ptr<const Scene> scene)
{
    std::uint64_t version = 0;
    {
        std::lock_guard lock(mutex_);
        sceneChange_ = std::move(scene);
        version = ++lightsVersion_;
    }
    wake_.notify_all();
    return version;
}

LitShading parseLitShading(const std::string& name)
{
    if (name == "light")
        return LitShading::Light;
    if (name == "complexity")
        return LitShading::Complexity;
    if (name == "overlap")
        return LitShading::Overlap;
    if (name == "staleness")
        return LitShading::Staleness;
    if (name == "error")
        return LitShading::Error;
    throw Error("the lit view shows light, complexity, overlap, staleness or error, not '" + name + "'");
}

LitPreviewFrame exactLitFrame(std::shared_ptr<const Scene> scene, std::vector<Light> lights, LitShading shading, int budget, bool indirect)
{
    std::mutex mutex;
    std::condition_variable arrived;
    std::optional<LitPreviewFrame> last;
    LitPreview preview([&](LitPreviewFrame frame) {
        std::lock_guard lock(mutex);
        const bool referenced = frame.shading != LitShading::Error || frame.referenceLights == frame.lights;
        if ((frame.exact && referenced) || !frame.error.empty())
            last = std::move(frame);
        arrived.notify_all();
    });
    preview.start(1, {.scene = std::move(scene),
                      .lights = std::move(lights),
                      .segmentsPerFrame = std::uint64_t(1) << 40,
                      .shading = shading,
                      .budget = budget,
                      .indirect = indirect});
    std::unique_lock lock(mutex);
    arrived.wait(lock, [&] { return last.has_value(); });
    LitPreviewFrame out = std::move(*last);
    lock.unlock();
    preview.stop();
    return out;
}

} // namespace sightline::ui
