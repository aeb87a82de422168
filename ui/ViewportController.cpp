#include "ViewportController.h"

#include "editor/LightObjects.h"
#include "editor/PatchPairFix.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace sightline::ui {

namespace {
constexpr double kClickSlop = 4.0;   // pixels a press may move and still count as a click
} // namespace

ViewportController::ViewportController(EditorDocument& document, QObject* parent) : QObject(parent), document_(document)
{
    connect(&document_, &EditorDocument::changed, this, [this](unsigned changes) {
        if (changes & (OccludersChanged | SceneFileChanged | DocumentReset)) {
            triangles_.reset();
            sceneBounds_.reset();
        }
        emit viewChanged();
    });
    connect(&document_, &EditorDocument::selectionChanged, this, [this] {
        hoveredAxis_ = -1;
        emit viewChanged();
    });
}

void ViewportController::setCamera(const Camera& camera)
{
    camera_ = camera;
    autoOrthographic_ = false;
    emit viewChanged();
}

void ViewportController::showAxisView(const Camera& camera)
{
    setCamera(camera);
    autoOrthographic_ = camera.orthographic;
}

void ViewportController::setOrthographic(bool on)
{
    autoOrthographic_ = false;
    if (camera_.orthographic == on)
        return;
    camera_.orthographic = on;
    emit viewChanged();
}

void ViewportController::setViewportSize(int width, int height)
{
    width_ = std::max(width, 1);
    height_ = std::max(height, 1);
}

std::optional<LightType> placedLightType(Tool tool)
{
    switch (tool) {
    case Tool::PlacePointLight: return LightType::Point;
    case Tool::PlaceSpotLight: return LightType::Spot;
    case Tool::PlaceAreaLight: return LightType::Area;
    default: return std::nullopt;
    }
}

namespace {

QString lightKind(LightType type)
{
    switch (type) {
    case LightType::Point: return ViewportController::tr("point light");
    case LightType::Spot: return ViewportController::tr("spot light");
    case LightType::Area: return ViewportController::tr("area light");
    case LightType::Directional: break;
    }
    return ViewportController::tr("sun");
}

} // namespace

void ViewportController::setTool(Tool tool)
{
    if (tool == tool_)
        return;
    if (const ObjectKind patch = tool == Tool::PlaceSource ? ObjectKind::Source : ObjectKind::Receiver;
        (tool == Tool::PlaceSource || tool == Tool::PlaceReceiver) && document_.flags({patch, 0}).locked) {
        emit message(tr("The %1 is locked (Ctrl+L unlocks the selection, or untick Lock in the outline)")
                         .arg(patch == ObjectKind::Source ? tr("source") : tr("receiver")));
        return;
    }
    tool_ = tool;
    // The handles hide while placing: none is under the cursor when they come back.
    hoveredAxis_ = -1;
    cutHovered_ = false;
    if (ghost_) {
        ghost_.reset();
        emit viewChanged();
    }
    emit toolChanged(tool);
    if (tool == Tool::PlaceSource || tool == Tool::PlaceReceiver) {
        const QString size = placementSize_ ? tr(", %1 × %2 m").arg(placementSize_->first, 0, 'g', 3).arg(placementSize_->second, 0, 'g', 3) : QString();
        emit message(tr("Click a surface to place the %1 patch%2 (Esc cancels)").arg(tool == Tool::PlaceSource ? tr("source") : tr("receiver"), size));
    }
    if (const auto type = placedLightType(tool))
        emit message(tr("Click a surface to place the %1 on it (Esc cancels)").arg(lightKind(*type)));
    if (tool == Tool::PickSurface)
        emit message(tr("Click the surface the occluder should lie on, such as a doorway's frame (Esc cancels)"));
}

void ViewportController::setGizmoMode(GizmoMode mode)
{
    gizmoMode_ = mode;
    emit gizmoModeChanged(mode);
    emit viewChanged();
}

void ViewportController::setGizmoSpace(GizmoSpace space)
{
    gizmoSpace_ = space;
    emit gizmoSpaceChanged(space);
    emit viewChanged();
}

std::optional<GizmoFrame> ViewportController::gizmo() const
{
    const ObjectRef selection = document_.selection();
    // A hidden object has nothing to hold a handle; a locked one is not to be moved.
    if (!selection || tool_ != Tool::Select || !document_.isPickable(selection))
        return std::nullopt;
    return gizmoFrame(document_.state(selection), gizmoMode_, camera_, gizmoSpace_);
}

std::optional<CutHandle> ViewportController::cutHandle() const
{
    if (!style_ || !style_->cutaway || tool_ != Tool::Select)
        return std::nullopt;
    const double height = cutaway(*style_, camera_).height;
    if (cutDrag_) {
        // Held where it was grabbed: the spot is not chosen again under the cursor.
        CutHandle held = cutDrag_->handle;
        held.point.y = height;
        return held;
    }
    // Clear of what the designer clicks: the patches in view and the selection's gizmo.
    std::vector<ScreenBox> keepClear;
    for (const ObjectKind kind : {ObjectKind::Source, ObjectKind::Receiver})
        if (document_.isShown({kind, 0})) {
            const Patch& p = kind == ObjectKind::Source ? document_.project().source : document_.project().receiver;
            if (const auto box = screenBox(camera_, {p.corner, p.corner + p.u, p.corner + p.v, p.corner + p.u + p.v}, width_, height_, 8.0))
                keepClear.push_back(*box);
        }
    if (const auto frame = gizmo()) {
        std::vector<glm::dvec3> ends{frame->pivot};
        for (const glm::dvec3& axis : frame->axes) {
            ends.push_back(frame->pivot + 1.2 * frame->length * axis);
            ends.push_back(frame->pivot - 1.2 * frame->length * axis);
        }
        if (const auto box = screenBox(camera_, ends, width_, height_, 8.0))
            keepClear.push_back(*box);
    }
    return sightline::ui::cutHandle(camera_, height, width_, height_, keepClear);
}

bool ViewportController::openSkyAbove(const glm::dvec3& point) const
{
    return !pickSurface(triangles(), Ray{point, {0.0, 1.0, 0.0}});
}

const WorldTriangles& ViewportController::triangles() const
{
    if (!triangles_)
        triangles_ = worldTriangles(document_.scene());
    return *triangles_;
}

Ray ViewportController::rayAt(QPointF position) const { return pixelRay(camera_, position.x(), position.y(), width_, height_); }

double ViewportController::floorLimit() const
{
    const Bounds& bounds = levelBounds();
    return bounds.empty() ? -std::numeric_limits<double>::infinity() : double(bounds.min.y) + 0.1;
}

const Bounds& ViewportController::levelBounds() const
{
    // Called every frame: the scene's bounds (every vertex of every instance) are kept.
    if (!sceneBounds_)
        sceneBounds_ = document_.scene().bounds();
    return *sceneBounds_;
}

double ViewportController::sceneRadius() const
{
    Bounds bounds = levelBounds();
    for (const Patch* p : {&document_.project().source, &document_.project().receiver}) {
        bounds.extend(glm::vec3(p->corner));
        bounds.extend(glm::vec3(p->corner + p->u + p->v));
    }
    return std::max(0.5 * double(glm::length(bounds.max - bounds.min)), 1.0);
}

ObjectRef ViewportController::objectOfTriangle(std::size_t triangle) const
{
    const std::size_t instance = triangles().instanceOf[triangle];
    const std::size_t fileObjects = document_.sceneFile().instances.size();
    return instance < fileObjects ? ObjectRef{ObjectKind::SceneObject, instance}
                                  : ObjectRef{ObjectKind::Occluder, document_.occluderOfInstance().at(instance - fileObjects)};
}

std::optional<SurfaceHit> ViewportController::surfaceHit(const Ray& ray, bool pickableOnly) const
{
    const std::optional<Cutaway> cut = style_ && style_->cutaway ? std::optional(cutaway(*style_, camera_)) : std::nullopt;
    const std::size_t fileObjects = document_.sceneFile().instances.size();
    const WorldTriangles& all = triangles();
    return pickSurface(all, ray, [&](std::size_t triangle, const glm::dvec3& point) {
        const ObjectRef object = objectOfTriangle(triangle);
        if (!(pickableOnly ? document_.isPickable(object) : document_.isShown(object)))
            return false;
        return !cut || all.instanceOf[triangle] >= fileObjects || !hiddenByCut(*cut, camera_, point);
    });
}

std::optional<SurfaceHit> ViewportController::visibleSurface(const Ray& ray) const { return surfaceHit(ray, false); }

ObjectRef ViewportController::objectAt(QPointF position) const
{
    const Ray ray = rayAt(position);
    ObjectRef best;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (const ObjectKind kind : {ObjectKind::Source, ObjectKind::Receiver}) {
        if (!document_.isPickable({kind, 0}))
            continue;
        const Patch& patch = kind == ObjectKind::Source ? document_.project().source : document_.project().receiver;
        if (auto d = pickPatch(patch, ray); d && *d < bestDistance) {
            bestDistance = *d;
            best = {kind, 0};
        }
    }
    // Locked objects let the click through to what is behind them (and hidden ones are not there).
    if (auto hit = surfaceHit(ray, true); hit && hit->distance < bestDistance) {
        best = objectOfTriangle(hit->triangle);
        bestDistance = hit->distance;
    }
    // Lights are drawn over everything, so they are picked through walls too: the nearest marker
    // within a steady on-screen radius wins over any surface.
    std::optional<double> nearestLight;
    for (std::size_t k = 0; k < document_.lights().size(); ++k) {
        const Light& light = document_.lights()[k];
        const double radius = std::max(0.03 * glm::length(lightPivot(light, document_.levelBounds()) - ray.origin), 0.05);
        if (const auto d = pickLight(light, document_.levelBounds(), ray, radius); d && (!nearestLight || *d < *nearestLight)) {
            nearestLight = d;
            best = {ObjectKind::Light, k};
        }
    }
    return best;
}

std::optional<Patch> ViewportController::placementAt(ObjectKind which, QPointF position) const
{
    const auto hit = visibleSurface(rayAt(position));
    if (!hit)
        return std::nullopt;
    const Patch old = std::get<Patch>(document_.state({which, 0}));
    const auto [width, height] = placementSize_.value_or(std::pair(glm::length(old.u), glm::length(old.v)));
    Patch placed = patchOnSurface(*hit, width, height, old.na, old.nb);
    // Fitted to the surface: a patch on a wall stands on the floor below rather than going through
    // it (a click near a doorway's foot put half the patch under the floor).
    const glm::dvec3 n = glm::normalize(hit->normal);
    if (std::abs(n.y) < 0.5) {
        const double lowest = std::min({placed.corner.y, (placed.corner + placed.v).y, (placed.corner + placed.u).y,
                                        (placed.corner + placed.u + placed.v).y});
        const glm::dvec3 start = hit->point + 0.05 * n;
        if (const auto floor = visibleSurface(Ray{start, glm::dvec3(0.0, -1.0, 0.0)}); floor && floor->point.y > lowest)
            placed.corner.y += floor->point.y - lowest + 0.01;
    }
    // With the other patch: a wall patch standing on the floor crosses the plane of a floor patch
    // 2 cm over it (the most natural pair); lifted off that plane, or shrunk to its side, it is valid.
    const bool source = which == ObjectKind::Source;
    const Project& project = document_.project();
    if (const auto fix = fixPatchPair(source ? placed : project.source, source ? project.receiver : placed, source);
        fix && fix->source == source)
        placed = fix->patch;
    return placed;
}

bool ViewportController::placePatchAt(ObjectKind which, QPointF position)
{
    const std::optional<Patch> placed = placementAt(which, position);
    if (!placed) {
        emit message(tr("Nothing under the cursor to place the patch on"));
        return false;
    }
    const ObjectRef object{which, 0};
    document_.setState(object, *placed, which == ObjectKind::Source ? tr("Place source") : tr("Place receiver"));
    document_.select(object);
    emit message(which == ObjectKind::Source ? tr("Source placed (Ctrl+Z undoes)") : tr("Receiver placed (Ctrl+Z undoes)"));
    return true;
}

bool ViewportController::placeLightAt(LightType type, QPointF position)
{
    const auto hit = visibleSurface(rayAt(position));
    if (!hit) {
        emit message(tr("Nothing under the cursor to place the %1 on").arg(lightKind(type)));
        return false;
    }
    QString kind = lightKind(type);
    kind[0] = kind[0].toUpper();
    const std::string name = kind.toStdString() + " " + std::to_string(document_.lights().size() + 1);
    try {
        document_.addLight(lightOnSurfaceJson(type, hit->point, hit->normal, name));
    } catch (const std::exception& e) {
        emit message(QString::fromUtf8(e.what()));
        return false;
    }
    emit message(tr("%1 placed (Ctrl+Z undoes)").arg(QString::fromStdString(name)));
    return true;
}

void ViewportController::mousePress(Qt::MouseButton button, Qt::KeyboardModifiers modifiers, QPointF position)
{
    last_ = pressPosition_ = position;
    pressedOnEmpty_ = false;
    if (button == Qt::RightButton) {
        navigation_ = Navigation::Fly;
        flying_ = true;
        return;
    }
    if (button == Qt::MiddleButton || (button == Qt::LeftButton && (modifiers & Qt::ShiftModifier))) {
        navigation_ = Navigation::Pan;
        return;
    }
    if (button != Qt::LeftButton)
        return;
    if (modifiers & Qt::AltModifier) {
        navigation_ = Navigation::Orbit;
        return;
    }
    if (tool_ == Tool::PlaceSource || tool_ == Tool::PlaceReceiver) {
        if (placePatchAt(tool_ == Tool::PlaceSource ? ObjectKind::Source : ObjectKind::Receiver, position))
            setTool(Tool::Select);
        return;
    }
    if (const auto type = placedLightType(tool_)) {
        if (placeLightAt(*type, position))
            setTool(Tool::Select);
        return;
    }
    if (tool_ == Tool::PickSurface) {
        if (const auto hit = visibleSurface(rayAt(position))) {
            setTool(Tool::Select);
            emit message(tr("Surface picked: the occluder assistant puts its occluder on that plane (its slider puts it "
                            "between the patches again)"));
            emit surfacePicked(hit->point, hit->normal);
        } else {
            emit message(tr("Nothing under the cursor: click a surface the rays cross (Esc cancels)"));
        }
        return;
    }
    if (const auto frame = gizmo()) {
        const int axis = pickGizmoAxis(*frame, camera_, position.x(), position.y(), width_, height_);
        if (axis >= 0) {
            drag_ = beginGizmoDrag(gizmoMode_, axis, document_.state(document_.selection()), camera_, position.x(),
                                   position.y(), width_, height_, gizmoSpace_);
            return;
        }
    }
    if (const auto handle = cutHandle();
        handle && pickCutHandle(*handle, camera_, position.x(), position.y(), width_, height_)) {
        cutDrag_ = beginCutDrag(*handle, camera_, position.x(), position.y(), width_, height_);
        return;
    }
    // Left press elsewhere: a click selects (on release), a drag orbits.
    pressedOnEmpty_ = true;
    navigation_ = Navigation::Orbit;
}

void ViewportController::mouseMove(Qt::MouseButtons buttons, Qt::KeyboardModifiers, QPointF position)
{
    const QPointF delta = position - last_;
    last_ = position;
    if (drag_) {
        document_.applyState(document_.selection(), dragGizmo(*drag_, camera_, position.x(), position.y(), width_, height_, snap_));
        return;
    }
    if (cutDrag_) {
        // A view setting, not an edit: no undo step; picking follows it at once.
        style_->cutHeight = dragCut(*cutDrag_, camera_, position.x(), position.y(), width_, height_, snap_.move);
        emit cutMoved(style_->cutHeight);
        emit viewChanged();
        return;
    }
    if (buttons == Qt::NoButton && (tool_ == Tool::PlaceSource || tool_ == Tool::PlaceReceiver)) {
        ghost_ = placementAt(tool_ == Tool::PlaceSource ? ObjectKind::Source : ObjectKind::Receiver, position);
        emit viewChanged();
        return;
    }
    if (buttons == Qt::NoButton) {
        const auto frame = gizmo();
        const int axis = frame ? pickGizmoAxis(*frame, camera_, position.x(), position.y(), width_, height_) : -1;
        const auto handle = axis < 0 ? cutHandle() : std::nullopt;
        const bool onCut = handle && pickCutHandle(*handle, camera_, position.x(), position.y(), width_, height_);
        if (axis != hoveredAxis_ || onCut != cutHovered_) {
            hoveredAxis_ = axis;
            cutHovered_ = onCut;
            emit viewChanged();
        }
        return;
    }
    if (pressedOnEmpty_ && std::hypot(position.x() - pressPosition_.x(), position.y() - pressPosition_.y()) <= kClickSlop)
        return;   // still a click
    if (navigation_ == Navigation::Orbit && autoOrthographic_) {
        camera_.orthographic = false;   // leaving the axis view
        autoOrthographic_ = false;
    }
    switch (navigation_) {
    case Navigation::Orbit: orbit(camera_, delta.x(), delta.y(), kOrbitRadiansPerPixel * speeds_.orbit); break;
    case Navigation::Pan: pan(camera_, delta.x(), delta.y(), height_); break;
    case Navigation::Fly: look(camera_, delta.x(), delta.y(), kOrbitRadiansPerPixel * speeds_.orbit); break;
    case Navigation::None: return;
    }
    keepAbove(camera_, floorLimit(), navigation_ == Navigation::Orbit);
    pressedOnEmpty_ = false;
    emit viewChanged();
}

void ViewportController::mouseRelease(Qt::MouseButton button, QPointF position)
{
    if (cutDrag_ && button == Qt::LeftButton) {
        cutDrag_.reset();
        return;
    }
    if (drag_ && button == Qt::LeftButton) {
        const ObjectRef object = document_.selection();
        const ObjectState after = document_.state(object);
        const ObjectState before = drag_->start;
        drag_.reset();
        static const char* names[] = {"Move", "Rotate", "Scale"};
        document_.editState(object, before, after, tr("%1 %2").arg(tr(names[int(gizmoMode_)]), document_.objectName(object)));
        return;
    }
    if (button == Qt::LeftButton && pressedOnEmpty_)
        document_.select(objectAt(position));
    if (button == Qt::RightButton) {
        flying_ = false;
        flyKeys_ = glm::dvec3(0.0);
    }
    pressedOnEmpty_ = false;
    navigation_ = Navigation::None;
}

void ViewportController::wheel(double steps)
{
    dolly(camera_, steps);
    keepAbove(camera_, floorLimit(), true);
    emit viewChanged();
}

bool ViewportController::key(int key, bool pressed)
{
    if (key == Qt::Key_Shift) {
        flyFast_ = pressed;
        return flying_;
    }
    if (!flying_)
        return false;
    const double v = pressed ? 1.0 : 0.0;
    switch (key) {
    case Qt::Key_W: flyKeys_.z = v; break;
    case Qt::Key_S: flyKeys_.z = -v; break;
    case Qt::Key_D: flyKeys_.x = v; break;
    case Qt::Key_A: flyKeys_.x = -v; break;
    case Qt::Key_E: flyKeys_.y = v; break;
    case Qt::Key_Q: flyKeys_.y = -v; break;
    default: return false;
    }
    return true;
}

void ViewportController::advanceFly(double seconds)
{
    if (!flying_ || flyKeys_ == glm::dvec3(0.0))
        return;
    const double speed = 0.4 * sceneRadius() * speeds_.fly * (flyFast_ ? 3.0 : 1.0);   // metres per second
    fly(camera_, flyKeys_ * (speed * seconds));
    keepAbove(camera_, floorLimit(), false);
    emit viewChanged();
}

void ViewportController::frameSelection()
{
    frame(camera_, selectionBounds());
    emit viewChanged();
}

bool ViewportController::dropSelectionToFloor()
{
    const ObjectRef selection = document_.selection();
    if (!selection || selection.kind == ObjectKind::Light || document_.flags(selection).locked) {
        emit message(selection.kind == ObjectKind::Light ? tr("Lights hang where they are: move them with the gizmo")
                                                         : tr("Select a patch or an object to drop to the floor"));
        return false;
    }
    const Bounds bounds = selectionBounds();
    const glm::dvec3 middle = 0.5 * (glm::dvec3(bounds.min) + glm::dvec3(bounds.max));
    // From just under the object's middle (its own faces are not in the way), straight down; a
    // floor it already sinks into is found from its top.
    const WorldTriangles& all = triangles();
    const auto notItself = [&](std::size_t triangle, const glm::dvec3&) { return objectOfTriangle(triangle) != selection && document_.isShown(objectOfTriangle(triangle)); };
    std::optional<SurfaceHit> floor = pickSurface(all, Ray{{middle.x, double(bounds.max.y), middle.z}, {0.0, -1.0, 0.0}}, notItself);
    if (!floor) {
        emit message(tr("Nothing below the selection to drop it onto"));
        return false;
    }
    const double lift = selection.isPatch() ? 0.02 : 0.0;
    const double dy = floor->point.y + lift - double(bounds.min.y);
    if (std::abs(dy) < 1e-9)
        return true;
    ObjectState state = document_.state(selection);
    if (auto* patch = std::get_if<Patch>(&state))
        patch->corner.y += dy;
    else
        std::get<glm::mat4>(state) = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, float(dy), 0.0f)) * std::get<glm::mat4>(state);
    document_.setState(selection, state, tr("Drop to floor"));
    emit message(tr("Dropped %1 cm onto the surface below (Ctrl+Z undoes)").arg(std::round(-100.0 * dy), 0, 'f', 0));
    return true;
}

Bounds ViewportController::selectionBounds() const
{
    Bounds bounds;
    const ObjectRef selection = document_.selection();
    if (selection.isPatch()) {
        const Patch p = std::get<Patch>(document_.state(selection));
        for (int k = 0; k < 4; ++k)
            bounds.extend(glm::vec3(p.cornerPoint(k)));
    } else if (selection.kind == ObjectKind::SceneObject) {
        bounds = document_.sceneFile().instanceBounds(document_.sceneFile().instances.at(selection.index));
    } else if (selection.kind == ObjectKind::Occluder) {
        const Scene& occluders = document_.occluderScene();
        for (std::size_t i = 0; i < occluders.instances.size(); ++i)
            if (document_.occluderOfInstance()[i] == selection.index)
                bounds.extend(occluders.instanceBounds(occluders.instances[i]));
    } else if (selection.kind == ObjectKind::Light && selection.index < document_.lights().size()) {
        const glm::dvec3 pivot = lightPivot(document_.lights()[selection.index], document_.levelBounds());
        bounds.extend(glm::vec3(pivot - glm::dvec3(1.0)));
        bounds.extend(glm::vec3(pivot + glm::dvec3(1.0)));
    } else {   // nothing selected: the pair and the way between them
        for (const Patch* p : {&document_.project().source, &document_.project().receiver})
            for (int k = 0; k < 4; ++k)
                bounds.extend(glm::vec3(p->cornerPoint(k)));
    }
    return bounds;
}

} // namespace sightline::ui
