// dense-mesh: scanned-statues of 1-4 cm triangles in the shaft, ray casting's case.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "demo/bench/SceneKinds.h"
#include "demo/bench/ScannedStatue.h"
#include "demo/bench/Stage.h"

namespace sightline::demo::bench {
namespace {

struct Statue {
    vec3 centre;
    StatueShape shape;
    float plinthTop;   // 0: the statue stands on a pedestal column up to its base instead
};

/// Cells per face edge for a leg of about `leg` metres; then all statues scaled together into the
/// kind's 45k-115k triangles.
void resolve(std::vector<Statue>& statues, float leg)
{
    std::size_t total = 0;
    for (Statue& s : statues) {
        const vec3 r = s.shape.radii;
        const float meanRadius = (r.x + r.y + r.z) / 3.0f * (1.0f + 0.5f * s.shape.amplitude);
        s.shape.resolution = std::max(16, int(std::ceil(1.5708f * meanRadius / leg)));
        total += statueTriangles(s.shape.resolution);
    }
    const double bound = total > 115000 ? 115000.0 : total < 45000 ? 45000.0 : double(total);
    const double factor = std::sqrt(bound / double(total));
    for (Statue& s : statues)
        s.shape.resolution = std::max(16, int(std::floor(s.shape.resolution * factor)));
}

} // namespace

BenchScene denseMesh(std::uint64_t seed)
{
    Stage stage(seed, 0xDE45E5CA7ull);
    Rng& rng = stage.rng;
    const bool single = seed % 2 == 1;
    const float distance = rng.range(8.0f, 16.0f);
    const vec2 from(2.0f, 5.0f), to(2.0f + distance, 5.0f + rng.range(-0.8f, 0.8f));
    stage.setPatches(from, {rng.range(1.0f, 1.5f), rng.range(1.4f, 1.8f), rng.range(0.25f, 0.45f)}, to,
                     {rng.range(1.5f, 2.0f), rng.range(1.6f, 2.0f), rng.range(0.2f, 0.35f)}, 0.02f);
    stage.putNew(tiles("floor", {0.0f, 1.0f}, {distance + 4.0f, 9.0f}, 0.0f, 1.0f, 1.0f));

    std::vector<Statue> statues;
    const int bumps = rng.between(5, 14);
    const float amplitude = rng.range(0.08f, 0.28f);
    if (single) {
        // One statue on a plinth, as big as the shaft: open underneath, as scans of standing
        // figures are, so it carries no watertight flag.
        const float t = rng.range(0.35f, 0.65f), r = rng.range(0.65f, 0.95f), ry = r * rng.range(1.05f, 1.4f);
        const float top = 0.25f * ry + rng.range(0.05f, 0.25f);
        Statue s{vec3(0.0f), StatueShape{{r, ry, r * rng.range(0.85f, 1.1f)}, 0, bumps, amplitude, {}}, top};
        const vec2 at = stage.along(t, stage.halfWidth(t) * rng.range(-0.6f, 0.6f));
        s.centre = {at.x, top + 0.8f * ry, at.y};
        s.shape.cutBelow = top - s.centre.y;
        statues.push_back(s);
    } else {
        // Smaller closed ones to either side, so part of the shaft is open.
        const int count = rng.between(2, 3);
        const float firstSide = rng.unit() < 0.5f ? -1.0f : 1.0f;
        for (int k = 0; k < count; ++k) {
            const float t = 0.25f + 0.5f * (float(k) + rng.range(0.15f, 0.85f)) / float(count);
            const float r = rng.range(0.38f, 0.58f), ry = r * rng.range(1.0f, 1.5f);
            const float lateral = (k % 2 ? -firstSide : firstSide) * stage.halfWidth(t) * rng.range(0.2f, 0.7f);
            const vec2 height = stage.heightRange(t);
            const vec2 at = stage.along(t, lateral);
            const float y = std::max(0.02f + 1.35f * ry, rng.range(height.x + 0.4f * ry, height.y - 0.4f * ry));
            statues.push_back({{at.x, y, at.y}, StatueShape{{r, ry, r * rng.range(0.85f, 1.15f)}, 0, bumps, amplitude, {}}, 0.0f});
        }
    }
    resolve(statues, rng.range(0.012f, 0.024f));
    for (std::size_t k = 0; k < statues.size(); ++k) {
        const Statue& s = statues[k];
        stage.putNew(scannedStatue("statue_" + std::to_string(k), s.shape, rng), translate(s.centre));
        Builder base("plinth_" + std::to_string(k));
        const float half = 0.8f * std::max(s.shape.radii.x, s.shape.radii.z);
        if (s.plinthTop > 0.0f) {
            bevelBox(base, {s.centre.x - half, 0.0f, s.centre.z - half}, {s.centre.x + half, s.plinthTop, s.centre.z + half}, 0.02f);
        } else {
            // A pedestal column into the statue's underside (the statue hides its top).
            const float top = s.centre.y - 0.5f * s.shape.radii.y;
            if (top > 0.1f)
                bevelBox(base, {s.centre.x - 0.25f * half, 0.0f, s.centre.z - 0.25f * half},
                         {s.centre.x + 0.25f * half, top, s.centre.z + 0.25f * half}, 0.01f);
        }
        if (!base.mesh.indices.empty())
            stage.putNew(std::move(base.mesh));
    }
    return std::move(stage).finish(single ? "statue" : "group");
}

} // namespace sightline::demo::bench
