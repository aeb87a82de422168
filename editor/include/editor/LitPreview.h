#pragma once
// The editor's lit view: the level's light-map texels lit by the project's lights (direct light,
// shadowed exactly: lighting/DirectLight.h), computed on a worker thread and kept live with
// Barczak's amortised updates (lighting/LightingCache.h): every frame refreshes the stale lights,
// brightest and longest stale first, within a budget of shadow segments, and delivers the map; the
// view is the exact answer once no light is stale, and says so. Moving or editing a light stales
// that light alone (setLights); moving an occluder stales, light by light, the texels its shadows
// could reach (setScene); a new level starts again. One bounce of
// indirect light may be added (LitIndirect.h). Plain C++ (no Qt):
// the caller decides how an answer reaches its thread.

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "editor/Camera.h"
#include "editor/LitShading.h"
#include "editor/RestartingWorker.h"
#include "lighting/DirectLight.h"
#include "lighting/Light.h"
#include "lighting/LightSets.h"
#include "lighting/LightingCache.h"
#include "lighting/ao/AoTexels.h"
#include "visibility/Scene.h"

namespace sightline::ui {

/// The overlays' colours and counts for one texel point (tested as a contract).
struct TexelLightCounts {
    std::uint16_t lit = 0, partial = 0, shadowed = 0;   ///< of the lights whose unshadowed term is > 0
};
glm::vec3 overlapColour(std::size_t lights, int budget);
glm::vec3 complexityColour(const TexelLightCounts& counts, int budget);

struct LitPreviewFrame {
    std::uint64_t generation = 0;
    /// As AoPreviewLevel: per world-triangle corner of the scene its place in the map, and a
    /// width x height map (row 0 at the top) of tone-mapped colours in [0, 1]. The uvs are the
    /// texels' own, shared by every frame of them.
    std::shared_ptr<const std::vector<glm::vec2>> uvs;
    int width = 0, height = 0;
    std::vector<glm::vec3> map;
    std::size_t texels = 0;
    std::size_t lights = 0;            ///< lights in the view
    std::size_t refreshed = 0;         ///< lights refreshed for this frame
    std::size_t rough = 0;             ///< of those, by the low-resolution pass (still stale)
    std::size_t stale = 0;             ///< lights still stale: their old light is shown
    bool indirect = false;             ///< one bounce of indirect light added (LitIndirect.h)
    std::size_t vpls = 0;              ///< its virtual point lights
    bool exact = false;                ///< no light stale (nor the bounce): the exact irradiance, tone-mapped
    std::uint64_t lightsVersion = 0;   ///< the lights and scene it shows: start's, setLights' or setScene's answer
    LitShading shading = LitShading::Light;
    int budget = 4;                    ///< Overlap, Complexity: the lights a texel may take
    /// Overlap: the share of lit texels over the budget and the most lights on one texel;
    /// Complexity: the mean lights partly or wholly shadowed per lit texel.
    double overBudget = 0.0;
    std::size_t mostLights = 0;
    double meanShadowed = 0.0;
    /// Error: lights whose reference is computed (all of them before errors are shown), the
    /// largest relative error, and the share of lit texels off by more than 1%.
    std::size_t referenceLights = 0;
    double errorMax = 0.0;
    double errorOverPercent = 0.0;
    /// O'Rorke's sets of light `setsLight` seen from the requested camera (requestSets), once
    /// computed; every frame after carries the latest.
    std::optional<LightSets> sets;
    std::size_t setsLight = 0;
    bool setsServed = false;           ///< V and L came from a PVS (SetsRequest::visible)
    std::vector<LightingCache::LightCost> costs;   ///< per light, what its last refresh cost
    double exposure = 0.0;             ///< colour = 1 - exp(-exposure x E / pi), E in W/m²
    double frameMs = 0.0;              ///< this frame's refresh
    double ms = 0.0;                   ///< since start()
    std::string error;                 ///< non-empty: nothing else is set
};

/// The lit view's texels: the atlas of the level's triangles (previewTexelDensity, as the AO
/// preview), each texel's shading point lifted off its surface as `lights --texel` lifts them,
/// and the corners' uvs.
struct LitTexels {
    AoTexelLayout layout;
    std::shared_ptr<const std::vector<glm::vec2>> uvs;
    std::vector<ShadingPoint> points;
    std::vector<std::size_t> pointOfTexel;   ///< per texel point of the layout; SIZE_MAX: none (degenerate)
    std::vector<std::uint32_t> pointOfPixel; ///< per atlas pixel the point shown there (atlasSources); kBlankPixel: none
};
LitTexels litTexels(const Scene& scene);

/// The lit view's tone map: 1 - exp(-exposure x E / pi) per channel.
glm::vec3 toneMapped(const glm::dvec3& irradiance, double exposure);

struct LitPreviewRequest {
    std::shared_ptr<const Scene> scene;
    std::vector<Light> lights;              ///< validated (validateLights)
    std::uint64_t segmentsPerFrame = 4'000'000;   ///< a frame's budget (LightingCache::update)
    LitShading shading = LitShading::Light;
    int budget = 4;
    bool indirect = false;                  ///< add one bounce of indirect light (LitIndirect.h)
};

class LitPreview {
public:
    using Deliver = std::function<void(LitPreviewFrame frame)>;   ///< called on the worker thread
    explicit LitPreview(Deliver deliver);
    ~LitPreview();
    LitPreview(const LitPreview&) = delete;
    LitPreview& operator=(const LitPreview&) = delete;

    /// Cancels the running computation (without waiting) and starts `request`. Returns the
    /// lights' version: frames for these lights carry it.
    std::uint64_t start(std::uint64_t generation, LitPreviewRequest request);
    /// The lights changed (same scene): lights whose entry differs get the low-resolution pass
    /// (LowResolutionPass.h), then go on stale and are refreshed exactly by priority; a changed
    /// count starts the lights' fields again over the same texels. Returns the lights' version.
    std::uint64_t setLights(std::vector<Light> lights);
    /// The scene changed (an occluder moved, was added or removed; the same level otherwise):
    /// texels that stayed keep their light, and each light refreshes only the texels whose shadow
    /// segments could pass where the scene changed. Returns the version frames of it carry (as
    /// setLights'). A new level takes start().
    std::uint64_t setScene(std::shared_ptr<const Scene> scene);
    /// Shows the same light otherwise (no shadow ray cast again): a frame is delivered anew.
    void setShading(LitShading shading, int budget);
    /// Adds (or drops) one bounce of indirect light: its VPLs are refreshed once the direct light
    /// is exact, and the view is exact once they are too.
    void setIndirect(bool on);
    /// Computes O'Rorke's sets (V from `camera`, lighting/LightSets.h) of light `light` between
    /// frames, and again when the lights change; nullopt stops. A baked PVS may serve them:
    /// `visible` is then V (the camera cell's row) and `reach` bounds L (pvsReach).
    struct SetsRequest {
        std::size_t light = 0;
        Camera camera;
        std::optional<std::vector<std::uint32_t>> visible;
        std::optional<std::vector<std::uint32_t>> reach;
    };
    void requestSets(std::optional<SetsRequest> request);
    /// A delivered frame's map, shown and no longer needed, for a later frame to fill: a map
    /// freed on the GUI thread and allocated anew on the worker could cost the worker fresh pages
    /// each frame (several milliseconds on a level's megapixel atlas). Optional.
    void recycle(std::vector<glm::vec3> map);
    void cancel();
    void stop();

private:
    class Session;   ///< the worker's state and its frames

    Deliver deliver_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::vector<Light> lights_;
    std::shared_ptr<const Scene> sceneChange_;   ///< setScene's, until the worker takes it
    std::uint64_t lightsVersion_ = 0;            ///< of the lights and the scene
    LitShading shading_ = LitShading::Light;
    int budget_ = 4;
    std::uint64_t shadingVersion_ = 0;
    bool indirect_ = false;
    std::optional<SetsRequest> setsRequest_;
    std::uint64_t setsVersion_ = 0;
    std::vector<glm::vec3> spareMap_;   ///< recycle()'s
    RestartingWorker worker_{mutex_, wake_};   // last: its jobs use the above
};

/// Runs a LitPreview to its exact frame and returns it (or the failed frame): the headless
/// screenshot's lit view, and tests; with `indirect`, one bounce of indirect light included.
LitPreviewFrame exactLitFrame(std::shared_ptr<const Scene> scene, std::vector<Light> lights,
                              LitShading shading = LitShading::Light, int budget = 4, bool indirect = false);

/// "light", "complexity", "overlap", "staleness" or "error"; throws sightline::Error for anything else.
LitShading parseLitShading(const std::string& name);

/// Whether two lights give the same light (every field the formulas read).
bool sameLight(const Light& a, const Light& b);

} // namespace sightline::ui
