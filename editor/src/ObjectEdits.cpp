#include "editor/ObjectEdits.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/euler_angles.hpp>
#include <glm/gtx/matrix_decompose.hpp>

namespace sightline::ui {

namespace {
template <class... F> struct Overloaded : F... { using F::operator()...; };
template <class... F> Overloaded(F...) -> Overloaded<F...>;
} // namespace

glm::dvec3 pivotOf(const ObjectState& state)
{
    return std::visit(Overloaded{[](const Patch& p) { return p.centre(); },
                                 [](const glm::mat4& m) { return glm::dvec3(m[3]); }},
                      state);
}

std::array<glm::dvec3, 3> localAxesOf(const ObjectState& state)
{
    return std::visit(Overloaded{[](const Patch& p) {
                                     return std::array<glm::dvec3, 3>{glm::normalize(p.u), glm::normalize(p.v), p.normal()};
                                 },
                                 [](const glm::mat4& m) {
                                     std::array<glm::dvec3, 3> axes;
                                     for (int i = 0; i < 3; ++i) {
                                         const glm::dvec3 c(m[i]);
                                         const double len = glm::length(c);
                                         axes[std::size_t(i)] = len > 0.0 ? c / len : glm::dvec3(i == 0, i == 1, i == 2);
                                     }
                                     return axes;
                                 }},
                      state);
}

ObjectState translated(const ObjectState& state, const glm::dvec3& delta)
{
    return std::visit(Overloaded{[&](Patch p) -> ObjectState {
                                     p.corner += delta;
                                     return p;
                                 },
                                 [&](glm::mat4 m) -> ObjectState {
                                     m[3] += glm::vec4(glm::vec3(delta), 0.0f);
                                     return m;
                                 }},
                      state);
}

ObjectState rotated(const ObjectState& state, const glm::dvec3& axis, double angle)
{
    const glm::dmat4 r = glm::rotate(glm::dmat4(1.0), angle, axis);
    const glm::dmat3 r3(r);
    const glm::dvec3 pivot = pivotOf(state);
    return std::visit(Overloaded{[&](Patch p) -> ObjectState {
                                     p.u = r3 * p.u;
                                     p.v = r3 * p.v;
                                     p.corner = pivot - 0.5 * (p.u + p.v);
                                     return p;
                                 },
                                 [&](const glm::mat4& m) -> ObjectState {
                                     glm::dmat4 d(m);
                                     d = glm::translate(glm::dmat4(1.0), pivot) * r * glm::translate(glm::dmat4(1.0), -pivot) * d;
                                     return glm::mat4(d);
                                 }},
                      state);
}

ObjectState scaled(const ObjectState& state, int axis, double factor)
{
    return std::visit(Overloaded{[&](Patch p) -> ObjectState {
                                     const glm::dvec3 centre = p.centre();
                                     if (axis == 0)
                                         p.u *= factor;
                                     else if (axis == 1)
                                         p.v *= factor;
                                     p.corner = centre - 0.5 * (p.u + p.v);
                                     return p;
                                 },
                                 [&](glm::mat4 m) -> ObjectState {
                                     m[axis] *= float(factor);
                                     return m;
                                 }},
                      state);
}

Decomposed decompose(const glm::mat4& transform)
{
    Decomposed parts;
    parts.position = glm::dvec3(transform[3]);
    glm::dvec3 columns[3];
    for (int i = 0; i < 3; ++i) {
        columns[i] = glm::dvec3(transform[i]);
        parts.scale[i] = glm::length(columns[i]);
    }
    if (glm::determinant(glm::dmat3(transform)) < 0.0)
        parts.scale.x = -parts.scale.x;   // a mirror lives in the scale, rotations stay proper
    glm::dmat4 rotation(1.0);
    for (int i = 0; i < 3; ++i)
        rotation[i] = glm::dvec4(parts.scale[i] != 0.0 ? columns[i] / parts.scale[i] : glm::dvec3(i == 0, i == 1, i == 2), 0.0);
    double x = 0, y = 0, z = 0;
    glm::extractEulerAngleZYX(rotation, z, y, x);   // R = Rz * Ry * Rx: X applied first
    parts.rotationDegrees = glm::degrees(glm::dvec3(x, y, z));
    return parts;
}

glm::mat4 compose(const Decomposed& parts)
{
    const glm::dvec3 r = glm::radians(parts.rotationDegrees);
    glm::dmat4 m = glm::eulerAngleZYX(r.z, r.y, r.x);
    for (int i = 0; i < 3; ++i)
        m[i] *= parts.scale[i];
    m[3] = glm::dvec4(parts.position, 1.0);
    return glm::mat4(m);
}

} // namespace sightline::ui
