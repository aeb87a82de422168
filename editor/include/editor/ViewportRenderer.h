#pragma once
// Draws the editor's view with OpenGL 4.5 core through gl::Functions, so the same code renders in
// the Qt viewport, in OSMesa for `sightline --screenshot` and in tests:
//   - the scene, shaded (headlight + sky term, two-sided), optional wireframe overlay;
//   - the placed occluders; the selected object highlighted;
//   - the two patches (translucent), their outlines and the shaft between them (red if the pair
//     is invalid);
//   - an overlay on one patch (importance or light, PatchOverlay.h): one texel per sample, drawn
//     opaque just in front of the patch in place of its translucent fill;
//   - the rays of the hidden-samples map (§9 of Eisemann & Décoret: the map is the answer the
//     designer looks at). A cap draws a hashed subset, evenly spread over the receiver samples;
//     the subset's free rays (or, with blocked ones shown, a bit per drawn ray) are listed on the
//     CPU once per answer, and a vertex shader turns each into its (receiver sample, source
//     sample) pair. How dense bundles stay readable and cheap: RayLayer.h;
//   - the section cut's outline (where the cut plane meets the level's box) and its handle;
//   - the PVS debugger's gap markers and the gizmo handles, over everything.

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>

#include "editor/Camera.h"
#include "editor/Gizmo.h"
#include "editor/ObjectEdits.h"
#include "editor/OverlayTexels.h"
#include "editor/SectionCutHandle.h"
#include "editor/LitShading.h"
#include "lighting/Light.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/RayDisagreement.h"

#include "visibility/Patch.h"
#include "visibility/Scene.h"
#include "visibility/gl/GlFunctions.h"

namespace sightline::ui {

/// Placed occluders' colour: violet, apart from the source's green, the receiver's blue, the
/// rays' yellow and the selection's orange.
inline constexpr glm::vec3 kOccluderColour{0.62f, 0.42f, 0.82f};

struct ViewStyle {
    bool wireframe = false;
    bool showRays = true;
    bool showBlocked = false;       ///< blocked rays too, in red
    int rayCap = 4096;              ///< at most this many rays drawn (a hashed subset beyond)
    /// A section cut, so interiors are seen from outside without hiding the roof by hand: scene
    /// file geometry above `cutHeight` (world Y), or nearer to the eye than half the way to the
    /// orbit target, is not drawn, and picking passes through it. Display only; sampling sees
    /// everything. The height is the view's own: orbiting, panning and flying never move it (the
    /// editor sets it when a file opens; NaN, for headless images: 1.5 m above the orbit target).
    bool cutaway = true;
    double cutHeight = std::numeric_limits<double>::quiet_NaN();
    /// The rays' colours. Alpha is the coverage an open shaft reaches on screen, whatever the ray
    /// count and zoom (each ray's opacity follows from how many cross a pixel, RayLayer.h); where
    /// rays are blocked the bundle is fainter in proportion. 1: every ray opaque.
    glm::vec4 freeColour{1.0f, 0.85f, 0.15f, 0.6f};
    glm::vec4 blockedColour{0.9f, 0.15f, 0.1f, 0.45f};
    /// Where a blocked ray is first stopped (when its end is known: setRayEnds), a dot.
    glm::vec4 stopColour{1.0f, 1.0f, 1.0f, 0.9f};
    /// Shade the scene file with its ambient occlusion (setAmbientOcclusion), once there is one.
    bool ambientOcclusion = false;
    /// Shade the level by the lit view's light map (LitPreview.h) alone, no headlight: what the
    /// lights give, tone-mapped; set with the map through setAmbientOcclusion.
    bool litView = false;
    /// Headless renders (OffscreenRender.h): what the lit view shows, the overlap budget, and
    /// whether one bounce of indirect light is added.
    LitShading litShading = LitShading::Light;
    int litBudget = 4;
    bool litIndirect = false;
    /// Tint the scene file's objects the PVS debugger says are culled (setPvsCulled).
    bool pvsDebugger = false;
    /// Tint the scene file's objects by the selected light's O'Rorke sets (setPvsCulled's classes).
    bool lightSets = false;
};

/// Which rays the renderer draws for a map and a cap: every one of `sourcePerReceiver` source
/// samples (hashed per receiver) for every `receiverStride`-th receiver sample (hashed).
struct RaySubset {
    std::uint32_t receivers = 0;          ///< receiver samples drawn
    std::uint32_t receiverStride = 1;
    std::uint32_t sourcePerReceiver = 0;  ///< source samples drawn per receiver sample
    std::uint32_t sourceStride = 1;
    std::uint64_t count() const { return std::uint64_t(receivers) * sourcePerReceiver; }
};
RaySubset raySubset(int sourceCount, int receiverCount, int cap);
/// The (receiver, source) pair of drawn ray k; the shader computes the same.
std::pair<std::uint32_t, std::uint32_t> subsetRay(const RaySubset& subset, std::uint32_t k);
/// The drawn rays k of `subset` that `map` leaves free, increasing: while blocked rays are hidden
/// only these are drawn.
std::vector<std::uint32_t> freeDrawnRays(const HiddenSampleMap& map, const RaySubset& subset);
/// Bit k (of word k / 32) set where drawn ray k of `subset` is blocked in `map`: what the shader
/// reads while blocked rays are shown, in place of the whole map.
std::vector<std::uint32_t> blockedDrawnRays(const HiddenSampleMap& map, const RaySubset& subset);

/// The colour of the rays of an opening the designer picked (setSelectedRays): a light cyan that
/// none of the free, blocked or disagreement colours is.
inline constexpr std::uint8_t kSelectedRayRgb[3] = {80, 235, 255};

/// The colour of the PVS debugger's view-cell outline: a magenta no ray, patch or gap marker has.
inline constexpr std::uint8_t kViewCellRgb[3] = {255, 70, 230};

/// The rays a disagreement view draws (RayDisagreement.h): every false-blocked, false-free and tie
/// ray, or an even spread of `cap` of them, each listed as k | class << 30 with k = i * receivers + j
/// (the whole map as one subset: raySubset with strides 1) and class 1 false-blocked, 2 false-free,
/// 3 a tie.
std::vector<std::uint32_t> disagreementDrawnRays(const RayDisagreement& disagreement, std::uint32_t cap);

/// A framebuffer with an RGBA8 colour and a 24/8 depth-stencil renderbuffer: the background
/// cache and the headless screenshot.
struct RenderTarget {
    GLuint framebuffer = 0, colour = 0, depth = 0;
    int width = 0, height = 0;

    /// (Re)creates it at this size; false if the framebuffer is incomplete.
    bool create(const gl::Functions& gl, int w, int h);
    void destroy(const gl::Functions& gl);
};

struct FrameState {
    Camera camera;
    int width = 1;
    int height = 1;
    unsigned framebuffer = 0;     ///< target FBO (0 = default)
    double sceneRadius = 10.0;
    Patch source;
    Patch receiver;
    bool sourceHidden = false, receiverHidden = false;   ///< not drawn (their rays still are)
    bool pairValid = true;
    ObjectRef selection;
    std::optional<GizmoFrame> gizmo;
    GizmoMode gizmoMode = GizmoMode::Move;   ///< the handles' heads: arrows, rings or boxes
    std::optional<Patch> placementGhost;     ///< where a click would place a patch: drawn faint
    /// A suggested occluder (a convex polygon, world space; empty for none): translucent, its
    /// outline drawn over everything so it shows through walls.
    std::vector<glm::vec3> occluderGhost;
    int hoveredAxis = -1;
    /// The section cut's handle (interactive views only) and the level's box its outline spans.
    std::optional<CutHandle> cutHandle;
    bool cutHandleHovered = false;
    Bounds levelBounds;
    ViewStyle style;
    /// The PVS debugger's gap list: the openings through which the reference saw an object the
    /// bake culls. Drawn over everything: a cross at the opening (`at`), and for the gaps of the
    /// shown cell (`ray`) a witness ray through it, from its point in the cell to the object; the
    /// selected one brighter and larger, with its witness rays (`gapWitnesses`) in the colour of
    /// picked rays.
    struct GapMarker {
        glm::vec3 from{0.0f}, to{0.0f}, at{0.0f};
        bool ray = false;
    };
    std::vector<GapMarker> gapMarkers;
    int gapSelected = -1;
    std::vector<std::pair<glm::vec3, glm::vec3>> gapWitnesses;
    /// The PVS debugger's shown view cell (the camera's, or the frozen one), outlined over
    /// everything in kViewCellRgb.
    std::optional<Bounds> viewCell;
    /// The project's lights, drawn over everything as markers in their colour (orange when
    /// selected): a star at a point light, a star and its outer cone at a spot, an arrow from the
    /// sun's anchor (LightObjects.h), an area light's rectangle and normal.
    std::vector<Light> lights;
    Bounds sunLevel;   ///< the box a sun is drawn above (EditorDocument::levelBounds)
    /// The selected light's scissor rectangle (O'Rorke: the screen bounds of what it lights and
    /// the camera sees), in pixels: min x, min y, max x, max y. Drawn as a dashed frame.
    std::optional<glm::dvec4> scissor;
};

/// The section cut's colour: cyan, apart from the patches, the rays, the selection and the axes.
inline constexpr glm::vec3 kCutColour{0.2f, 0.85f, 0.95f};

/// The cutaway's limits: geometry above `height` or nearer than `depth` along the view direction
/// is hidden (infinite height and zero depth when the cutaway is off).
struct Cutaway {
    double height = 0.0;
    double depth = 0.0;
};
Cutaway cutaway(const FrameState& frame);
/// The same limits from a style and camera (picking uses them to skip what is not drawn).
Cutaway cutaway(const ViewStyle& style, const Camera& camera);
/// Whether a point of the scene file is hidden by the cut.
bool hiddenByCut(const Cutaway& cut, const Camera& camera, const glm::dvec3& point);

struct MeshVertex;

/// The scene file's triangles as the renderer draws them (positions, normals, object ids).
/// Built from the scene alone, so a worker thread can prepare it (on a first open building the
/// demo's would stall the GUI thread, mostly touching new memory) and the GUI thread only
/// uploads it.
struct LevelMesh {
    std::vector<MeshVertex> vertices;
    LevelMesh();
    ~LevelMesh();
    LevelMesh(LevelMesh&&) noexcept;
    LevelMesh& operator=(LevelMesh&&) noexcept;
};
LevelMesh prepareLevelMesh(const Scene& scene);

/// How a frame got the level's image: the cached one as it was, the cached one lit again from a
/// new light map with the same uvs (LevelRelight.h), or drawn (whole, or a chunk of a first draw).
enum class LevelPass { Cached, Relit, Drawn };

class ViewportRenderer {
public:
    /// Compiles the programs; the context must stay current while the renderer is used.
    explicit ViewportRenderer(const gl::Functions& gl);
    ~ViewportRenderer();
    ViewportRenderer(const ViewportRenderer&) = delete;
    ViewportRenderer& operator=(const ViewportRenderer&) = delete;

    /// The scene file's objects (object id = instance index).
    void setSceneFile(const Scene& scene);
    /// The same, prepared by prepareLevelMesh (on any thread); an empty mesh draws no level.
    /// `inChunks`: its first draw is spread over frames (levelIncomplete()), for interactive views.
    void setSceneFile(LevelMesh mesh, bool inChunks = false);
    /// The level's ambient occlusion as a light map (AoPreview.h): `uvs` per world triangle
    /// corner of the whole scene, the scene file's triangles then the placed occluders'
    /// (worldTriangles order; -1 where a triangle has none), a width x height map of the light
    /// reaching each texel (AO in [0, 1] under a uniform sky, an environment's colour otherwise).
    /// Ignored when the uvs are not for the current scene. Drawn while the style asks. A map
    /// whose uvs and size are the last one's lights the cached level again (lastLevelPass()).
    void setAmbientOcclusion(const std::vector<glm::vec2>& uvs, int width, int height, const std::vector<glm::vec3>& map);
    /// Per instance of the scene file, a tint class: 0 none, 1 culled by the PVS debugger
    /// (magenta), and for a light's O'Rorke sets 2 lit and visible (I, yellow), 3 a shadow caster
    /// into I (S, violet), 4 visible but out of the light's reach (V \\ L, darkened). Empty: none.
    void setPvsCulled(const std::vector<std::uint8_t>& culled);
    /// Objects the designer hid (ObjectFlags.h): per scene-file instance and per placed occluder,
    /// 1 where not drawn (shorter or empty: the rest drawn).
    void setHiddenObjects(const std::vector<std::uint8_t>& sceneFile, const std::vector<std::uint8_t>& occluders);
    /// The placed occluders (object id of instance i = occluderOf[i]).
    void setOccluders(const Scene& occluders, const std::vector<std::size_t>& occluderOf);
    /// The map to draw rays from (nullptr: none, e.g. an invalid pair), kept by pointer until the
    /// next call: call again whenever its contents change. Forgets the ray ends.
    void setHiddenSamples(const HiddenSampleMap* map);
    /// Rays where an approximation answers differently from the map (RayDisagreement.h), drawn in
    /// place of the map's rays while set and for the pair's grids: false-blocked red, false-free
    /// blue, ties amber, at most the style's cap (spread evenly). Kept by pointer until the next
    /// call, as setHiddenSamples; nullptr: the map's rays again.
    void setDisagreement(const RayDisagreement* disagreement);
    /// Rays drawn over the map's, opaque in kSelectedRayRgb: those of the opening the designer
    /// picked (OccluderAssistant), each `receiver * sources + source` of a `sources` x `receivers`
    /// pair; drawn only while the pair's grids are those. Empty: none.
    void setSelectedRays(std::vector<std::uint64_t> rays, int sources, int receivers);
    /// Where each drawn ray of a `cap`-ray subset ends (RayEnds.h), after setHiddenSamples: blocked
    /// rays are then drawn up to their first stop, with a dot there, while the style's cap is `cap`.
    /// Empty: blocked rays are drawn whole.
    void setRayEnds(const std::vector<float>& ends, int cap);
    /// Colours to draw on the source or receiver patch (nullptr or ObjectKind::None: none).
    /// Copied: a small buffer upload (4 bytes a sample). Drawn only while the patch's grid is
    /// the texels' grid.
    void setOverlay(ObjectKind patch, const OverlayTexels* texels);

    void render(const FrameState& frame);

    /// Rays drawn by the last render().
    std::uint64_t raysDrawn() const { return raysDrawn_; }
    /// A newly set level is drawn over several frames (its first draw is the slow one): true
    /// until the last frame drew all of it; the caller asks for another frame meanwhile.
    bool levelIncomplete() const;
    /// What the last render() did to the level's image.
    LevelPass lastLevelPass() const;

private:
    struct MeshBuffer;
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::uint64_t raysDrawn_ = 0;
};

} // namespace sightline::ui
