#pragma once
// What the mouse and keyboard do in the viewport, kept out of the GL window so it is tested
// with plain calls: navigation (orbit: left drag on empty space or Alt + left; pan: middle drag or
// Shift + left; dolly: wheel; fly: right drag + WASD/QE, Shift for speed), placing a patch or a
// light on the surface under a click, selecting by click, and dragging the gizmo. A drag is shown live
// (applyState) and becomes one undo command on release.

#include <optional>

#include <QObject>
#include <QPointF>

#include "editor/Camera.h"
#include "EditorDocument.h"
#include "editor/Gizmo.h"
#include "editor/Picking.h"
#include "editor/SectionCutHandle.h"
#include "editor/ViewportRenderer.h"

namespace sightline::ui {

enum class Tool { Select, PlaceSource, PlaceReceiver, PlacePointLight, PlaceSpotLight, PlaceAreaLight, PickSurface };

/// The light a placing tool puts down, if it is one.
std::optional<LightType> placedLightType(Tool tool);

/// The designer's navigation speeds, as multiples of the defaults (Edit > Preferences).
struct NavigationSpeeds {
    double orbit = 1.0;   ///< 1x: kOrbitRadiansPerPixel (also fly mode's mouse look)
    double fly = 1.0;     ///< 1x: 40% of the scene's radius a second (Shift: 3x that)
};

class ViewportController : public QObject {
    Q_OBJECT
public:
    explicit ViewportController(EditorDocument& document, QObject* parent = nullptr);

    Camera& camera() { return camera_; }
    const Camera& camera() const { return camera_; }
    void setCamera(const Camera& camera);
    /// An axis view (7 / 1 / 3): orthographic until the designer orbits away from it, which
    /// returns to perspective (Blender's "auto perspective", Unity's axis clicks).
    void showAxisView(const Camera& camera);
    /// Perspective or orthographic by the designer's choice (numpad 5): kept while orbiting.
    void setOrthographic(bool on);
    void setViewportSize(int width, int height);
    int width() const { return width_; }
    int height() const { return height_; }

    Tool tool() const { return tool_; }
    void setTool(Tool tool);
    GizmoMode gizmoMode() const { return gizmoMode_; }
    void setGizmoMode(GizmoMode mode);
    /// World or local axes for moving and rotating (X).
    GizmoSpace gizmoSpace() const { return gizmoSpace_; }
    void setGizmoSpace(GizmoSpace space);
    const NavigationSpeeds& speeds() const { return speeds_; }
    void setSpeeds(const NavigationSpeeds& speeds) { speeds_ = speeds; }
    /// Snapping for gizmo drags (all zero: free).
    const GizmoSnap& snap() const { return snap_; }
    void setSnap(const GizmoSnap& snap) { snap_ = snap; }

    /// The handles of the selected object, if any.
    std::optional<GizmoFrame> gizmo() const;
    int hoveredAxis() const { return hoveredAxis_; }
    /// The size a placed patch gets (width, height in metres: a preset, PatchPresets.h), or none
    /// to keep the patch's own size.
    void setPlacementSize(std::optional<std::pair<double, double>> size) { placementSize_ = size; }
    const std::optional<std::pair<double, double>>& placementSize() const { return placementSize_; }
    /// While placing a patch: where a click at the cursor would put it.
    const std::optional<Patch>& placementGhost() const { return ghost_; }
    /// Where a click at `position` would place patch `which` (fitted: on a wall, its bottom edge
    /// never goes through the floor below), or nothing when no visible surface is there.
    std::optional<Patch> placementAt(ObjectKind which, QPointF position) const;
    bool isFlying() const { return flying_; }
    bool isDragging() const { return drag_.has_value(); }

    void mousePress(Qt::MouseButton button, Qt::KeyboardModifiers modifiers, QPointF position);
    void mouseMove(Qt::MouseButtons buttons, Qt::KeyboardModifiers modifiers, QPointF position);
    void mouseRelease(Qt::MouseButton button, QPointF position);
    void wheel(double steps);
    /// Fly keys while the right button is held; returns whether the key was used.
    bool key(int key, bool pressed);
    /// Moves a flying camera by the keys held, for `seconds`.
    void advanceFly(double seconds);

    /// Frames the selection (F), or the whole scene when nothing is selected.
    void frameSelection();
    /// The scene's extent, for clip planes and fly speed.
    double sceneRadius() const;
    /// The box around everything that blocks rays (the section cut's outline spans it).
    const Bounds& levelBounds() const;
    /// The lowest the eye may go while navigating: 10 cm above the scene's lowest point.
    double floorLimit() const;

    /// The view's style: the section cut that picking honours and its handle sets (nullptr:
    /// nothing is cut).
    void setStyle(ViewStyle* style) { style_ = style; }
    /// The section cut's handle where it is drawn now (none while the cut is off, or off screen).
    std::optional<CutHandle> cutHandle() const;
    bool cutHandleHovered() const { return cutHovered_; }
    bool isDraggingCut() const { return cutDrag_.has_value(); }

    /// The surface under `ray` that is drawn: the section cut hides scene-file geometry, never
    /// placed occluders; hidden objects (and those isolation hides) are not drawn. Placement puts
    /// patches on it, locked objects included.
    std::optional<SurfaceHit> visibleSurface(const Ray& ray) const;
    /// Whether nothing of the level, drawn or not, lies straight above `point` (open sky).
    bool openSkyAbove(const glm::dvec3& point) const;
    /// What a click at `position` selects (gizmo handles excepted).
    ObjectRef objectAt(QPointF position) const;
    /// Places the source or receiver on the surface under `position`; false when nothing is hit.
    bool placePatchAt(ObjectKind which, QPointF position);
    /// Adds a light of `type` on the surface under `position` (LightObjects.h's lightOnSurfaceJson),
    /// selected, one undo step; false, with a message, when nothing drawn is there.
    bool placeLightAt(LightType type, QPointF position);
    /// The selected object's box (a patch's corners, a light's marker); the patches' when nothing is selected.
    Bounds selectionBounds() const;
    /// Transform > Drop to Floor (End): the selection moved straight down (or up, out of the
    /// floor) until its lowest point rests on the first surface of the level below its middle, a
    /// patch 2 cm over it; undoable. False, with a message, when nothing is below or nothing is selected.
    bool dropSelectionToFloor();
    /// The world triangles of the document's scene, built once per scene change (picking's).
    const WorldTriangles& triangles() const;

signals:
    void viewChanged();   ///< camera, hover or gizmo: repaint
    void toolChanged(sightline::ui::Tool tool);
    void gizmoModeChanged(sightline::ui::GizmoMode mode);
    void gizmoSpaceChanged(sightline::ui::GizmoSpace space);
    void message(const QString& text);
    /// The section cut's handle was dragged to `height` (metres).
    void cutMoved(double height);
    /// Tool::PickSurface: the surface clicked, a point on it and its unit normal (facing the eye).
    void surfacePicked(glm::dvec3 point, glm::dvec3 normal);

private:
    /// The object a triangle of document_.scene() belongs to.
    ObjectRef objectOfTriangle(std::size_t triangle) const;
    /// visibleSurface, passing through locked objects too when `pickableOnly` (a click selects).
    std::optional<SurfaceHit> surfaceHit(const Ray& ray, bool pickableOnly) const;
    Ray rayAt(QPointF position) const;

    EditorDocument& document_;
    Camera camera_;
    int width_ = 1, height_ = 1;
    Tool tool_ = Tool::Select;
    GizmoMode gizmoMode_ = GizmoMode::Move;
    GizmoSpace gizmoSpace_ = GizmoSpace::World;
    GizmoSnap snap_;
    NavigationSpeeds speeds_;
    int hoveredAxis_ = -1;
    std::optional<Patch> ghost_;
    std::optional<std::pair<double, double>> placementSize_;

    enum class Navigation { None, Orbit, Pan, Fly };
    Navigation navigation_ = Navigation::None;
    bool flying_ = false;
    QPointF last_;
    QPointF pressPosition_;
    bool pressedOnEmpty_ = false;
    std::optional<GizmoDrag> drag_;
    std::optional<CutDrag> cutDrag_;
    bool cutHovered_ = false;
    glm::dvec3 flyKeys_{0.0};   ///< x right, y up, z forward: -1, 0, 1
    bool flyFast_ = false;
    bool autoOrthographic_ = false;   ///< orthographic because of an axis view, not by choice

    ViewStyle* style_ = nullptr;
    mutable std::optional<WorldTriangles> triangles_;
    mutable std::optional<Bounds> sceneBounds_;   ///< of document_.scene(); dropped when it changes
};

} // namespace sightline::ui
