#include "editor/Camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

namespace sightline::ui {

namespace {
constexpr double kMaxPitch = 1.55;   // just short of straight up/down, where yaw loses meaning
constexpr double kDollyPerStep = 0.85;
} // namespace

glm::dvec3 Camera::forward() const
{
    return {-std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
}

glm::dvec3 Camera::right() const { return {std::cos(yaw), 0.0, -std::sin(yaw)}; }

glm::dvec3 Camera::up() const { return glm::cross(right(), forward()); }

glm::mat4 Camera::view() const { return glm::mat4(glm::lookAt(eye(), target, up())); }

double Camera::halfHeight() const { return distance * std::tan(fovY / 2.0); }

double Camera::screenDepth(const glm::dvec3& point) const
{
    return orthographic ? distance : glm::length(eye() - point);
}

glm::mat4 Camera::projection(double aspect, double sceneRadius) const
{
    const double radius = std::max(sceneRadius, 1.0);
    const double nearPlane = std::clamp(distance * 0.01, 0.005, radius * 0.01);
    const double farPlane = distance + 4.0 * radius;
    if (orthographic) {
        const double h = halfHeight(), w = h * std::max(aspect, 1e-3);
        return glm::mat4(glm::ortho(-w, w, -h, h, nearPlane, farPlane));
    }
    return glm::mat4(glm::perspective(fovY, std::max(aspect, 1e-3), nearPlane, farPlane));
}

void orbit(Camera& camera, double dxPixels, double dyPixels, double radiansPerPixel)
{
    camera.yaw -= dxPixels * radiansPerPixel;
    camera.pitch = std::clamp(camera.pitch - dyPixels * radiansPerPixel, -kMaxPitch, kMaxPitch);
}

void pan(Camera& camera, double dxPixels, double dyPixels, int viewportHeight)
{
    // Metres per pixel at the target's depth.
    const double scale = 2.0 * camera.distance * std::tan(camera.fovY / 2.0) / std::max(viewportHeight, 1);
    camera.target += (-dxPixels * camera.right() + dyPixels * camera.up()) * scale;
}

void dolly(Camera& camera, double steps)
{
    camera.distance = std::clamp(camera.distance * std::pow(kDollyPerStep, steps), 0.05, 1e5);
}

void look(Camera& camera, double dxPixels, double dyPixels, double radiansPerPixel)
{
    const glm::dvec3 eye = camera.eye();
    orbit(camera, -dxPixels, -dyPixels, radiansPerPixel);
    camera.target = eye + camera.distance * camera.forward();
}

void fly(Camera& camera, const glm::dvec3& move)
{
    camera.target += move.x * camera.right() + move.y * camera.up() + move.z * camera.forward();
}

void frame(Camera& camera, const Bounds& bounds)
{
    if (bounds.empty())
        return;
    const glm::dvec3 lo(bounds.min), hi(bounds.max);
    camera.target = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * glm::length(hi - lo), 0.1);
    camera.distance = radius / std::sin(camera.fovY / 2.0) * 1.05;
}

Ray pixelRay(const Camera& camera, double x, double y, int width, int height)
{
    const double aspect = double(width) / std::max(height, 1);
    const double tanHalf = std::tan(camera.fovY / 2.0);
    const double ndcX = 2.0 * x / std::max(width, 1) - 1.0;
    const double ndcY = 1.0 - 2.0 * y / std::max(height, 1);
    if (camera.orthographic) {
        const double h = camera.halfHeight();
        return {camera.eye() + ndcX * h * aspect * camera.right() + ndcY * h * camera.up(), camera.forward()};
    }
    const glm::dvec3 direction = camera.forward() + ndcX * tanHalf * aspect * camera.right() + ndcY * tanHalf * camera.up();
    return {camera.eye(), glm::normalize(direction)};
}

glm::dvec3 toPixels(const Camera& camera, const glm::dvec3& point, int width, int height)
{
    const glm::dvec3 d = point - camera.eye();
    const double depth = glm::dot(d, camera.forward());
    const double tanHalf = std::tan(camera.fovY / 2.0);
    const double aspect = double(width) / std::max(height, 1);
    // Orthographic: every depth is drawn at the target's scale.
    const double scaleDepth = camera.orthographic ? camera.distance : depth;
    const double safeDepth = std::abs(scaleDepth) < 1e-12 ? 1e-12 : scaleDepth;
    const double ndcX = glm::dot(d, camera.right()) / (safeDepth * tanHalf * aspect);
    const double ndcY = glm::dot(d, camera.up()) / (safeDepth * tanHalf);
    return {(ndcX + 1.0) * 0.5 * width, (1.0 - ndcY) * 0.5 * height, depth};
}

void keepAbove(Camera& camera, double floorY, bool orbiting)
{
    const double below = floorY - camera.eye().y;
    if (!(below > 0.0))
        return;
    // eye.y = target.y - distance * sin(pitch): the largest pitch that keeps the eye up.
    const double maxSin = (camera.target.y - floorY) / camera.distance;
    if (orbiting && maxSin > -0.99) {
        camera.pitch = std::min(camera.pitch, std::asin(std::min(maxSin, 0.99)));
        return;
    }
    camera.target.y += below;
}

Camera overviewCamera(const Bounds& bounds)
{
    Camera camera;
    camera.yaw = -0.25 * std::numbers::pi;   // from -X, +Z towards the centre
    camera.pitch = -0.6;
    camera.orthographic = false;
    frame(camera, bounds);
    return camera;
}

Camera axisView(AxisView view, const Bounds& bounds)
{
    Camera camera;
    switch (view) {
    case AxisView::Top: camera.yaw = 0.0, camera.pitch = -0.5 * std::numbers::pi + 1e-3; break;   // pitch stays inside (-pi/2, pi/2)
    case AxisView::Front: camera.yaw = 0.0, camera.pitch = 0.0; break;
    case AxisView::Side: camera.yaw = 0.5 * std::numbers::pi, camera.pitch = 0.0; break;
    }
    frame(camera, bounds);
    camera.orthographic = true;   // as Blender's numpad views and Unity's axis clicks: no perspective
    return camera;
}

Camera lookThrough(const glm::dvec3& from, const glm::dvec3& fromNormal, const glm::dvec3& to, double toRadius)
{
    Camera camera;
    // On the side the patch faces (towards `to`), so the patch's own surface is not in the way.
    const double side = glm::dot(to - from, fromNormal) >= 0.0 ? 1.0 : -1.0;
    const glm::dvec3 eye = from + 0.01 * side * fromNormal;
    const glm::dvec3 d = to - eye;
    const double length = glm::length(d);
    if (!(length > 1e-6))
        return camera;
    const glm::dvec3 f = d / length;
    camera.target = to;
    camera.distance = length;
    camera.pitch = std::clamp(std::asin(std::clamp(f.y, -1.0, 1.0)), -0.5 * std::numbers::pi + 1e-3, 0.5 * std::numbers::pi - 1e-3);
    camera.yaw = std::atan2(-f.x, -f.z);
    // The other patch fills about a third of the view's height, and never less than 30 degrees.
    camera.fovY = std::clamp(2.0 * std::atan(3.0 * toRadius / length), 0.5236, 1.5708);
    return camera;
}

double axisParameter(const glm::dvec3& pivot, const glm::dvec3& axis, const Ray& ray)
{
    const glm::dvec3 w0 = pivot - ray.origin;
    const double b = glm::dot(axis, ray.direction);
    const double denom = 1.0 - b * b;
    if (denom < 1e-9)
        return 0.0;   // looking straight down the axis: no motion along it
    return (b * glm::dot(ray.direction, w0) - glm::dot(axis, w0)) / denom;
}

double distanceToSegment(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b)
{
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

} // namespace sightline::ui
