#include "demo/bench/Fittings.h"

#include <cmath>

#include <glm/vec4.hpp>

namespace sightline::demo::bench {

Mesh balustrade(const std::string& name, float length)
{
    Builder b(name);
    bevelBox(b, {0.0f, 0.0f, -0.04f}, {0.08f, 1.06f, 0.04f}, 0.01f);
    bevelBox(b, {length - 0.08f, 0.0f, -0.04f}, {length, 1.06f, 0.04f}, 0.01f);
    box(b, {0.05f, 0.95f, -0.035f}, {length - 0.05f, 1.02f, 0.035f});
    box(b, {0.05f, 0.08f, -0.025f}, {length - 0.05f, 0.12f, 0.025f});
    const int balusters = int((length - 0.2f) / 0.14f);
    const float step = (length - 0.16f) / float(balusters + 1);
    for (int k = 1; k <= balusters; ++k) {
        const float x = 0.08f + step * float(k);
        box(b, {x - 0.016f, 0.1f, -0.016f}, {x + 0.016f, 0.97f, 0.016f});
    }
    return std::move(b.mesh);
}

Mesh stair(const std::string& name, int steps, float rise, float run, float width)
{
    Builder b(name);
    const float length = float(steps) * run, height = float(steps) * rise;
    const float hyp = std::sqrt(length * length + height * height), c = length / hyp, s = height / hyp;
    // Stringers: 28 cm deep boards along the slope, their top edge through the treads' nosings.
    const mat4 slope(glm::vec4(c, s, 0, 0), glm::vec4(-s, c, 0, 0), glm::vec4(0, 0, 1, 0), glm::vec4(0, 0, 0, 1));
    for (float z : {-0.05f, width})
        b.with(slope, [&] { box(b, {-0.1f, -0.3f, z}, {hyp + 0.1f, -0.02f, z + 0.05f}); });
    for (int k = 0; k < steps; ++k) {
        const float top = float(k + 1) * rise;
        box(b, {float(k) * run - 0.03f, top - 0.04f, 0.005f}, {float(k + 1) * run + 0.001f, top, width - 0.005f});
    }
    // Handrail 0.9 m above the nosings on posts at the bottom and top.
    const vec3 low(0.1f, rise + 0.9f, width + 0.025f), high(length - 0.1f, height + 0.9f, width + 0.025f);
    rod(b, low - 0.1f * glm::normalize(high - low), high + 0.1f * glm::normalize(high - low), 0.025f, 0.025f, 8);
    rod(b, {0.1f, rise - 0.05f, width + 0.025f}, low + vec3(0.0f, 0.03f, 0.0f), 0.03f, 0.03f, 8);
    rod(b, {length - 0.1f, height - 0.05f, width + 0.025f}, high + vec3(0.0f, 0.03f, 0.0f), 0.03f, 0.03f, 8);
    return std::move(b.mesh);
}

Mesh desk()
{
    Builder b("desk");
    bevelBox(b, {-0.8f, 0.71f, -0.4f}, {0.8f, 0.74f, 0.4f}, 0.008f);
    for (float x : {-0.76f, 0.73f})
        box(b, {x, 0.0f, -0.36f}, {x + 0.03f, 0.715f, 0.36f});   // panel legs
    box(b, {-0.74f, 0.35f, -0.38f}, {0.74f, 0.7f, -0.36f});       // modesty panel
    return std::move(b.mesh);
}

Mesh deskScreen(float length)
{
    Builder b("desk_screen");
    bevelBox(b, {-0.5f * length, 0.0f, -0.02f}, {0.5f * length, 1.25f, 0.02f}, 0.01f);
    return std::move(b.mesh);
}

Mesh monitor()
{
    Builder b("monitor");
    bevelBox(b, {-0.3f, 0.9f, -0.03f}, {0.3f, 1.25f, 0.0f}, 0.005f);
    box(b, {-0.02f, 0.74f, -0.07f}, {0.02f, 0.95f, -0.03f});
    bevelBox(b, {-0.11f, 0.739f, -0.16f}, {0.11f, 0.755f, 0.02f}, 0.004f);
    return std::move(b.mesh);
}

Mesh cabinet()
{
    Builder b("cabinet");
    bevelBox(b, {-0.4f, 0.05f, -0.225f}, {0.4f, 0.75f, 0.225f}, 0.01f);
    box(b, {-0.38f, 0.0f, -0.2f}, {0.38f, 0.06f, 0.2f});   // plinth
    return std::move(b.mesh);
}

mat4 columnAt(vec2 at, float height)
{
    mat4 m = translate({at.x, 0.0f, at.y});
    m[1] *= height / kCeiling;
    return m;
}

} // namespace sightline::demo::bench
