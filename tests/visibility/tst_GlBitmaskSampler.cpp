// The GL bitmask sampler on a headless context (OSMesa; EGL too where it works), against the
// closed forms, the brute-force caster, the Embree reference and the CPU sampler. Skipped, not
// failed, where no OpenGL 4.5 core context can be made.
#include <memory>

#include <gtest/gtest.h>

#include "BruteForceCaster.h"
#include "GlContextTest.h"
#include "TestScenes.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/Error.h"
#include "visibility/GlBitmaskSampler.h"
#include "visibility/RayCastSampler.h"
#include "visibility/gl/HeadlessContext.h"

using namespace sightline;
using namespace sightline::test;

namespace {

class GlBitmask : public GlContextTest {
protected:
    static GlBitmaskSampler sampler(const Scene& scene) { return GlBitmaskSampler(context->functions(), worldTriangles(scene)); }
};

} // namespace

TEST_F(GlBitmask, EmptySceneWallAndHalfPlane)
{
    EXPECT_EQ(sampler(Scene{}).sample(xyPatch(0, 32, 32), xyPatch(2, 32, 32)).blockedCount(), 0u);
    const Scene wall = sceneOf({quad({-10, -10, 1}, {20, 0, 0}, {0, 20, 0})});
    const HiddenSampleMap all = sampler(wall).sample(xyPatch(0, 32, 32), xyPatch(2, 32, 32));
    EXPECT_EQ(all.blockedCount(), all.rayCount());

    const double edge = 0.437;
    const Scene half = sceneOf({quad({-50, -50, 1}, {50 + float(edge), 0, 0}, {0, 100, 0})});
    const Patch source = xyPatch(0, 13, 7), receiver = xyPatch(3, 52, 9);
    const HiddenSampleMap map = sampler(half).sample(source, receiver);
    std::uint64_t mismatches = 0;
    for (int j = 0; j < receiver.sampleCount(); ++j)
        for (int i = 0; i < source.sampleCount(); ++i) {
            const double x = source.sample(i).x + (receiver.sample(j).x - source.sample(i).x) / 3.0;
            mismatches += (x < edge) != map.blocked(j, i);
        }
    EXPECT_EQ(mismatches, 0u);
}

TEST_F(GlBitmask, AgreesWithBruteForceOnRandomScenes)
{
    int checked = 0;
    for (unsigned seed = 1; seed <= 24; ++seed) {
        const RandomCase c = randomCase(seed);
        if (!c.valid())
            continue;   // the generator made an invalid pair; refusal is tested separately
        ++checked;
        const HiddenSampleMap map = sampler(c.scene).sample(c.source, c.receiver);
        const BruteForceMap reference = bruteForceSample(worldTriangles(c.scene), c.source, c.receiver);
        EXPECT_EQ(mismatchesOutsideGrazing(map, reference), 0u) << "seed " << seed;
    }
    EXPECT_GE(checked, 16);
}

TEST_F(GlBitmask, JitteredSamplesMatchBruteForceAndTheCpuSampler)
{
    // The shader's hash must give SourceJitter's offsets: brute force casts to the shifted
    // positions (and the CPU sampler is held to the same brute force in tst_CpuBitmaskSampler).
    const SourceJitter jitter{.seed = 4242};
    int checked = 0;
    std::uint64_t changed = 0;
    for (unsigned seed = 1; seed <= 16; ++seed) {
        const RandomCase c = randomCase(seed);
        if (!c.valid())
            continue;
        ++checked;
        const HiddenSampleMap map = sampler(c.scene).sample(c.source, c.receiver, GlBitmaskOptions{.jitter = jitter});
        const BruteForceMap reference = bruteForceSample(worldTriangles(c.scene), c.source, c.receiver, 1e-5, jitter);
        EXPECT_EQ(mismatchesOutsideGrazing(map, reference), 0u) << "seed " << seed;
        changed += map.differenceCount(sampler(c.scene).sample(c.source, c.receiver));
    }
    EXPECT_GE(checked, 10);
    EXPECT_GT(changed, 0u);   // the jitter took effect
}

TEST_F(GlBitmask, WatertightCullingNeverChangesTheAnswer)
{
    // Closed boxes in the shaft (one mirrored), and one enclosing the receiver, where culling
    // must not apply (its front faces are the blockers).
    Scene scene;
    const std::uint32_t box = scene.addMesh(closedBox());
    for (int i = 0; i < 12; ++i) {
        glm::mat4 m(1.0f);
        m[0][0] = (i == 3 ? -0.2f : 0.2f) + 0.02f * float(i % 4);
        m[1][1] = 0.15f + 0.03f * float(i % 3);
        m[2][2] = 0.2f;
        m[3] = glm::vec4(0.1f + 0.08f * float(i), 0.15f + 0.06f * float((i * 5) % 11), 0.5f + 0.09f * float(i), 1.0f);
        scene.instances.push_back({"box", box, m});
    }
    const Patch source = xyPatch(0, 16, 16), receiver = xyPatch(2, 24, 24);
    GlBitmaskSampler gl(context->functions(), scene);
    const HiddenSampleMap culled = gl.sample(source, receiver, GlBitmaskOptions{});
    const HiddenSampleMap plain = gl.sample(source, receiver, GlBitmaskOptions{.watertightCulling = false});
    EXPECT_GT(culled.blockedCount(), 0u);
    EXPECT_LE(culled.differenceCount(plain) * 10000, culled.rayCount());
    EXPECT_LE(culled.differenceCount(RayCastScene(scene).sample(source, receiver)) * 10000, culled.rayCount());

    glm::mat4 room(1.0f);
    room[0][0] = room[1][1] = 3.0f;
    room[3] = glm::vec4(0.5f, 0.5f, 2.0f, 1.0f);   // z in [1.5, 2.5]: the receiver at z = 2 is inside
    Scene enclosed;
    enclosed.instances.push_back({"room", enclosed.addMesh(closedBox()), room});
    const HiddenSampleMap inside = GlBitmaskSampler(context->functions(), enclosed).sample(xyPatch(0, 8, 8), xyPatch(2, 8, 8));
    EXPECT_EQ(inside.blockedCount(), inside.rayCount());

    // Culling does run: a lone wall wrongly flagged watertight, facing the source (normal -z),
    // is dropped with culling on; nothing else would unblock its rays.
    Mesh wall = quad({-10, -10, 1}, {0, 20, 0}, {20, 0, 0});
    wall.watertight = true;
    Scene misflagged;
    misflagged.addMeshInstance(wall);
    GlBitmaskSampler wallSampler(context->functions(), misflagged);
    EXPECT_EQ(wallSampler.sample(xyPatch(0, 8, 8), xyPatch(2, 8, 8), GlBitmaskOptions{}).blockedCount(), 0u);
    EXPECT_EQ(wallSampler.sample(xyPatch(0, 8, 8), xyPatch(2, 8, 8), GlBitmaskOptions{.watertightCulling = false}).blockedCount(),
              64u * 64u);
}

TEST_F(GlBitmask, MatchesCpuAndReferenceAcrossSampleCounts)
{
    // Every target count from 1 (<= 128 source samples) to 8 (1024), receivers up to 128x96.
    const Mesh soup = randomSoup(5, 300, -0.3f, 1.3f, 0.3f, 1.7f, 0.15f);
    const Scene scene = sceneOf({soup});
    const RayCastScene reference(scene);
    const CpuBitmaskSampler cpu(scene);
    GlBitmaskSampler gpu = sampler(scene);
    struct Grid { int na, nb, rna, rnb; };
    for (const Grid g : {Grid{1, 1, 16, 16}, Grid{16, 8, 40, 24}, Grid{13, 11, 17, 9}, Grid{32, 16, 24, 24},
                         Grid{32, 32, 32, 32}, Grid{64, 16, 16, 16}, Grid{8, 8, 128, 96}}) {
        const Patch source = xyPatch(0, g.na, g.nb), receiver = xyPatch(2, g.rna, g.rnb);
        const HiddenSampleMap expected = reference.sample(source, receiver);
        const HiddenSampleMap map = gpu.sample(source, receiver);
        const HiddenSampleMap onCpu = cpu.sample(source, receiver, {.strategy = CpuStrategy::Bitmask});
        const std::string grid = std::to_string(g.na) + "x" + std::to_string(g.nb) + " / " +
                                 std::to_string(g.rna) + "x" + std::to_string(g.rnb);
        EXPECT_LE(map.differenceCount(expected) * 10000, map.rayCount()) << grid;
        // GL (float) and CPU (double) compute the same mathematics: differences are grazing rays.
        EXPECT_LE(map.differenceCount(onCpu) * 10000, map.rayCount()) << grid;
        EXPECT_GT(expected.blockedCount(), 0u) << grid;
    }
}

TEST_F(GlBitmask, RefusesInvalidInput)
{
    GlBitmaskSampler gpu = sampler(Scene{});
    EXPECT_THROW(gpu.sample(xyPatch(0, 50, 40), xyPatch(2, 8, 8)), Error);
    EXPECT_THROW(gpu.sample(xyPatch(0, 8, 8), xyPatch(0, 8, 8)), Error);
}
