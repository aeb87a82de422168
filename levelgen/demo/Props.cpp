#include "demo/Props.h"

#include <cmath>
#include <vector>

namespace sightline::demo::parts {

Mesh plant(const PlantShape& s)
{
    Rng rng(s.seed);
    Builder p(s.name, false);
    if (s.hanging) {
        for (int i = 0; i < 3; ++i)   // down into the basket's rim
            rod(p, vec3(0, 0, 0), onCircle(0.16f, float(i) / 3.0f, -0.81f), 0.004f, 0.004f, 4);
    } else {
        rod(p, vec3(0, 0.2f, 0), vec3(0, s.stemTop, 0), 0.025f, 0.012f, 6);
        for (int i = 0; i < 3; ++i) {
            const vec3 from(0, s.stemTop * rng.range(0.55f, 0.9f), 0);
            const vec3 dir = rng.inBall();
            const vec3 to = s.crownCentre + vec3(0.7f * s.crownRadii.x * dir.x, 0.5f * s.crownRadii.y * std::abs(dir.y),
                                                 0.7f * s.crownRadii.z * dir.z);
            rod(p, from, to, 0.01f, 0.005f, 4);
        }
    }
    for (int i = 0; i < s.leaves; ++i) {
        const vec3 c = s.crownCentre + rng.inBall() * s.crownRadii;
        const vec3 n = rng.direction();
        vec3 d = rng.direction();
        d = d - n * glm::dot(d, n);
        if (glm::dot(d, d) < 1e-4f)
            d = std::abs(n.x) < 0.9f ? vec3(1, 0, 0) - n * n.x : vec3(0, 1, 0) - n * n.y;
        d = glm::normalize(d);
        const vec3 e = glm::cross(n, d);
        const float length = rng.range(0.03f, 0.08f), width = length * rng.range(0.3f, 0.5f);
        const vec3 base = c - 0.5f * length * d;
        p.triangle(base - 0.5f * width * e, c + 0.5f * length * d, base + 0.5f * width * e);
    }
    return std::move(p.mesh);
}

Mesh pot()
{
    Builder b("pot");
    lathe(b, {{0, 0}, {0.14f, 0}, {0.19f, 0.29f}, {0.2f, 0.33f}, {0.175f, 0.33f}, {0, 0.3f}}, 12);
    return std::move(b.mesh);
}

Mesh basket()
{
    Builder b("basket");
    lathe(b, {{0, -0.98f}, {0.12f, -0.97f}, {0.2f, -0.9f}, {0.22f, -0.8f}, {0.2f, -0.8f}, {0, -0.82f}}, 12);
    return std::move(b.mesh);
}

Mesh pillar()
{
    Builder b("pillar");
    bevelBox(b, {-0.32f, 0, -0.32f}, {0.32f, 0.16f, 0.32f}, 0.02f);                       // plinth
    lathe(b, {{0, 0.15f}, {0.27f, 0.15f}, {0.27f, 0.21f}, {0.235f, 0.26f}, {0.21f, 0.34f}, {0.21f, 1.4f},
              {0.19f, 2.8f}, {0.23f, 2.88f}, {0.26f, 2.96f}, {0.26f, 3.0f}, {0, 3.0f}},
          20);
    bevelBox(b, {-0.3f, 2.99f, -0.3f}, {0.3f, kCeiling, 0.3f}, 0.015f);                     // abacus
    return std::move(b.mesh);
}

Mesh railing()
{
    Builder b("railing");
    bevelBox(b, {0, 0, -0.04f}, {0.08f, 1.06f, 0.04f}, 0.01f);
    bevelBox(b, {0.05f, 0.96f, -0.035f}, {2.03f, 1.03f, 0.035f}, 0.012f);
    bevelBox(b, {0.05f, 0.06f, -0.025f}, {2.03f, 0.11f, 0.025f}, 0.008f);
    for (int k = 0; k < 19; ++k)
        b.with(translate({0.14f + 0.1f * float(k), 0, 0}), [&] {
            lathe(b, {{0, 0.1f},     {0.014f, 0.1f},  {0.014f, 0.2f},  {0.021f, 0.26f}, {0.025f, 0.32f},
                      {0.018f, 0.4f}, {0.012f, 0.5f}, {0.012f, 0.74f}, {0.018f, 0.82f}, {0.014f, 0.9f},
                      {0.014f, 0.97f}, {0, 0.97f}},
                  6);
        });
    return std::move(b.mesh);
}

Mesh railingPost()
{
    Builder b("railing_post");
    bevelBox(b, {0, 0, -0.04f}, {0.08f, 1.06f, 0.04f}, 0.01f);
    return std::move(b.mesh);
}

Mesh chairWood()
{
    Builder b("chair_wood");
    bevelBox(b, {-0.22f, 0.43f, -0.21f}, {0.22f, 0.47f, 0.22f}, 0.01f);
    for (float x : {-0.18f, 0.18f}) {
        box(b, {x - 0.02f, 0, 0.16f}, {x + 0.02f, 0.44f, 0.2f});
        box(b, {x - 0.021f, 0, -0.2f}, {x + 0.021f, 0.96f, -0.16f});
        box(b, {x - 0.012f, 0.15f, -0.17f}, {x + 0.012f, 0.18f, 0.17f});
    }
    for (float y : {0.6f, 0.72f, 0.84f})
        box(b, {-0.17f, y, -0.195f}, {0.17f, y + 0.06f, -0.17f});
    return std::move(b.mesh);
}

Mesh chairBistro()
{
    Builder b("chair_bistro");
    lathe(b, {{0, 0.44f}, {0.2f, 0.44f}, {0.21f, 0.455f}, {0.2f, 0.47f}, {0, 0.47f}}, 16);
    for (int i = 0; i < 4; ++i) {
        const float a = 0.125f + 0.25f * float(i);
        rod(b, onCircle(0.19f, a, 0.0f), onCircle(0.13f, a, 0.45f), 0.012f, 0.016f, 6);
    }
    const vec3 l(-0.15f, 0.45f, -0.13f), r(0.15f, 0.45f, -0.13f);
    rod(b, l, l + vec3(-0.01f, 0.45f, -0.06f), 0.011f, 0.011f, 6);
    rod(b, r, r + vec3(0.01f, 0.45f, -0.06f), 0.011f, 0.011f, 6);
    for (int i = 0; i < 5; ++i) {   // curved top rail: a polyline of rods
        const float a0 = 0.575f + 0.35f * float(i) / 5.0f, a1 = 0.575f + 0.35f * float(i + 1) / 5.0f;
        const vec3 p0 = onCircle(0.19f, a0, 0.86f), p1 = onCircle(0.19f, a1, 0.86f);
        const vec3 overlap = 0.012f * glm::normalize(p1 - p0);   // no two caps meet edge to edge
        rod(b, p0 - overlap, p1 + overlap, 0.02f, 0.02f, 6);
    }
    return std::move(b.mesh);
}

Mesh tableRound()
{
    Builder b("table_round");
    lathe(b, {{0, 0.715f}, {0.54f, 0.715f}, {0.56f, 0.735f}, {0.545f, 0.76f}, {0, 0.76f}}, 32);
    lathe(b, {{0, 0.03f}, {0.06f, 0.03f}, {0.06f, 0.1f}, {0.032f, 0.4f}, {0.045f, 0.52f}, {0.034f, 0.62f},
              {0.065f, 0.69f}, {0, 0.72f}},
          12);
    bevelBox(b, {-0.32f, 0, -0.04f}, {0.32f, 0.05f, 0.04f}, 0.01f);
    bevelBox(b, {-0.041f, 0.001f, -0.32f}, {0.041f, 0.049f, 0.32f}, 0.01f);
    return std::move(b.mesh);
}

Mesh tableLong()
{
    Builder b("table_long");
    bevelBox(b, {-1.2f, 0.72f, -0.45f}, {1.2f, 0.77f, 0.45f}, 0.012f);
    for (float x : {-1.1f, 1.1f})
        for (float z : {-0.36f, 0.36f})
            bevelBox(b, {x - 0.035f, 0, z - 0.035f}, {x + 0.035f, 0.73f, z + 0.035f}, 0.008f);
    bevelBox(b, {-1.08f, 0.62f, -0.345f}, {1.08f, 0.725f, -0.325f}, 0.005f);
    bevelBox(b, {-1.08f, 0.62f, 0.325f}, {1.08f, 0.725f, 0.345f}, 0.005f);
    return std::move(b.mesh);
}

Mesh bookcase(const char* name, std::uint64_t seed)
{
    Rng rng(seed);
    Builder b(name);
    bevelBox(b, {-0.6f, 0, -0.175f}, {-0.57f, 2.0f, 0.175f}, 0.006f);      // sides
    bevelBox(b, {0.57f, 0, -0.175f}, {0.6f, 2.0f, 0.175f}, 0.006f);
    box(b, {-0.58f, 0.01f, -0.176f}, {0.58f, 1.99f, -0.16f});                 // back
    box(b, {-0.58f, 0.0f, -0.17f}, {0.58f, 0.08f, 0.16f});                    // plinth
    bevelBox(b, {-0.58f, 1.97f, -0.17f}, {0.58f, 2.0f, 0.17f}, 0.006f);     // top
    for (int s = 0; s < 4; ++s) {
        const float y = 0.08f + 0.42f * float(s);   // shelf surface
        if (s > 0)
            box(b, {-0.58f, y - 0.03f, -0.17f}, {0.58f, y, 0.17f});
        if (s == 2)
            continue;   // an empty shelf
        for (float x = -0.56f; x < 0.5f;) {
            const float w = rng.range(0.025f, 0.06f), h = rng.range(0.22f, 0.36f), depth = rng.range(0.17f, 0.27f);
            if (rng.unit() < 0.1f) {   // a gap
                x += rng.range(0.04f, 0.15f);
                continue;
            }
            box(b, {x, y - 0.003f, -0.15f}, {x + w - 0.002f, y + h, -0.15f + depth});
            x += w;
        }
    }
    box(b, {-0.58f, 1.73f, -0.17f}, {0.58f, 1.76f, 0.17f});                   // upper shelf, empty
    return std::move(b.mesh);
}

Mesh crate(const char* name, float size)
{
    Builder b(name);
    const float h = 0.5f * size;
    bevelBox(b, {-h, 0, -h}, {h, size, h}, 0.02f);
    for (float y : {0.2f * size, 0.8f * size})   // bands
        box(b, {-h - 0.01f, y - 0.03f, -h - 0.01f}, {h + 0.01f, y + 0.03f, h + 0.01f});
    return std::move(b.mesh);
}

Mesh pendantLamp(const char* name, float drop)
{
    Builder b(name);
    rod(b, vec3(0, -0.67f - drop, 0), vec3(0, 0.001f, 0), 0.006f, 0.006f, 6);
    b.xf = translate({0, -drop, 0});
    lathe(b, {{0, -0.6f}, {0.1f, -0.64f}, {0.19f, -0.73f}, {0.24f, -0.86f}, {0.25f, -0.86f}, {0.2f, -0.71f},
              {0.1f, -0.615f}, {0, -0.575f}},
          16);
    // bulb (a sphere of radius 6 cm)
    std::vector<vec2> bulb;
    for (int k = 0; k <= 6; ++k) {
        const glm::dvec2 cs = cosSin(float(k) / 12.0f);   // half a turn, bottom to top
        bulb.push_back({k == 0 || k == 6 ? 0.0f : 0.06f * float(cs.y), -0.72f - 0.06f * float(cs.x)});
    }
    lathe(b, {bulb[0], bulb[1], bulb[2], bulb[3], bulb[4], bulb[5], bulb[6]}, 8);
    return std::move(b.mesh);
}

Mesh vaseOnPlinth()
{
    Builder b("vase_plinth");
    bevelBox(b, {-0.22f, 0, -0.22f}, {0.22f, 0.9f, 0.22f}, 0.015f);
    lathe(b, {{0, 0.899f}, {0.07f, 0.899f}, {0.12f, 0.95f}, {0.15f, 1.05f}, {0.14f, 1.15f}, {0.1f, 1.24f},
              {0.06f, 1.3f}, {0.055f, 1.36f}, {0.07f, 1.4f}, {0.045f, 1.38f}, {0, 1.37f}},
          16);
    return std::move(b.mesh);
}

Mesh sofa()
{
    Builder b("sofa");
    bevelBox(b, {-0.9f, 0.1f, -0.4f}, {0.9f, 0.42f, 0.45f}, 0.05f);   // seat
    bevelBox(b, {-0.9f, 0.1f, -0.45f}, {0.9f, 0.85f, -0.22f}, 0.06f);   // back
    for (float x : {-1.0f, 0.78f})
        bevelBox(b, {x, 0.05f, -0.45f}, {x + 0.22f, 0.62f, 0.45f}, 0.06f);   // arms
    for (float x : {-0.9f, 0.9f})
        for (float z : {-0.36f, 0.36f})
            b.with(translate({x, 0, z}), [&] { cylinder(b, 0.03f, 0.0f, 0.12f, 6); });
    return std::move(b.mesh);
}

Mesh tableLow()
{
    Builder b("table_low");
    bevelBox(b, {-0.6f, 0.36f, -0.35f}, {0.6f, 0.42f, 0.35f}, 0.015f);
    bevelBox(b, {-0.55f, 0.06f, -0.3f}, {0.55f, 0.09f, 0.3f}, 0.008f);   // magazine shelf
    for (float x : {-0.52f, 0.52f})
        for (float z : {-0.27f, 0.27f})
            b.with(translate({x, 0, z}), [&] {
                lathe(b, {{0, 0}, {0.022f, 0}, {0.03f, 0.08f}, {0.022f, 0.2f}, {0.026f, 0.37f}, {0, 0.37f}}, 6);
            });
    return std::move(b.mesh);
}

} // namespace sightline::demo::parts
