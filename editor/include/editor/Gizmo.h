#pragma once
// The transform gizmo: three axis handles at the selected object's pivot, drawn at a constant
// size on screen. Move drags along an axis, Rotate turns about one, Scale stretches along the
// object's own axis (a patch's u or v). In world space (the default) move and rotate use the world
// axes; in local space (X, as in Unity) the object's own axes, so a turned crate slides along its
// own length. Scaling always uses the object's own axes: along a world axis it would shear a
// turned object. Pure geometry on a Camera, so it is tested without a window; the viewport only
// draws the handles and forwards the mouse.

#include <array>

#include "editor/Camera.h"
#include "editor/ObjectEdits.h"

namespace sightline::ui {

enum class GizmoMode { Move, Rotate, Scale };
enum class GizmoSpace { World, Local };

struct GizmoFrame {
    glm::dvec3 pivot{0.0};
    std::array<glm::dvec3, 3> axes{};   ///< unit
    double length = 1.0;                ///< handle length in metres (constant on screen)
};

GizmoFrame gizmoFrame(const ObjectState& state, GizmoMode mode, const Camera& camera, GizmoSpace space = GizmoSpace::World);

/// The handle under pixel (x, y): 0, 1, 2, or -1 for none (within `tolerance` pixels).
int pickGizmoAxis(const GizmoFrame& frame, const Camera& camera, double x, double y, int width, int height,
                  double tolerance = 8.0);

/// A drag in progress: the state it started from, so every step is computed from the start
/// (no drift) and the undo command gets one before/after pair.
struct GizmoDrag {
    GizmoMode mode = GizmoMode::Move;
    GizmoSpace space = GizmoSpace::World;
    int axis = 0;
    ObjectState start;
    GizmoFrame frame;
    double startParam = 0.0;   ///< Move, Scale: position along the axis where the drag began
    double startX = 0.0;       ///< Rotate: the cursor's start
};

/// Snapping, 0 = off for each: a move puts the pivot's coordinate along the axis
/// on a multiple of `move` metres (a world grid; in local space, whose axes need not meet the grid,
/// the distance moved is the multiple), a rotation turns by multiples of `angle` radians, a scale
/// changes the size by multiples of `scale` (0.1 = steps of 10%).
struct GizmoSnap {
    double move = 0.0;
    double angle = 0.0;
    double scale = 0.0;
};

GizmoDrag beginGizmoDrag(GizmoMode mode, int axis, const ObjectState& start, const Camera& camera, double x, double y,
                         int width, int height, GizmoSpace space = GizmoSpace::World);
ObjectState dragGizmo(const GizmoDrag& drag, const Camera& camera, double x, double y, int width, int height,
                      const GizmoSnap& snap = {});

} // namespace sightline::ui
