// docs/design.md §2's "Exact" contract for the GL sampler on the adversarial suite (ExactnessSuite.h):
// zero non-tie disagreements with the exact brute force, at production sample counts, at the
// origin and 1, 10 and 100 km from it, with and without decorrelated samples. Runs on llvmpipe
// through OSMesa; skipped where no OpenGL 4.5 core context can be made.

#include <gtest/gtest.h>

#include "ExactnessSuite.h"
#include "GlContextTest.h"
#include "visibility/GlBitmaskSampler.h"
#include "visibility/RayCastSampler.h"

using namespace sightline;
using namespace sightline::test;

namespace {

class GlExactness : public GlContextTest {
protected:
    std::vector<Method> glMethods()
    {
        // Beside the reference, so that every ray on which they differ is judged.
        return {{"raycast", [](const Scene& scene, const Patch& s, const Patch& r, const Question& q) {
                     return RayCastScene(scene).sample(s, r, {.jitter = q.jitter});
                 }},
                {"gl", [this](const Scene& scene, const Patch& s, const Patch& r, const Question& q) {
                     GlBitmaskSampler sampler(context->functions(), scene);
                     GlBitmaskStats stats;
                     HiddenSampleMap map = sampler.sample(s, r, GlBitmaskOptions{.jitter = q.jitter}, &stats);
                     gpuOccluders += stats.gpuOccluders;
                     cpuOccluders += stats.cpuOccluders;
                     flagged += stats.flaggedSamples;
                     return map;
                 }}};
    }
    std::size_t gpuOccluders = 0, cpuOccluders = 0, flagged = 0;
};

} // namespace

TEST_F(GlExactness, TheGlSamplerIsExactOnAdversarialScenes)
{
    expectExact(judgeSuite(suite({0.0, 1e3, 1e4, 1e5}, seeds(2)), glMethods()));
    std::printf("gl: %zu occluders drawn, %zu answered by the CPU, %zu samples flagged\n", gpuOccluders, cpuOccluders,
                flagged);
    // The GPU did the bulk of the work: most occluders are well conditioned.
    EXPECT_GT(gpuOccluders, 4 * cpuOccluders);
}

TEST_F(GlExactness, DecorrelatedSamplesAreExactToo)
{
    expectExact(judgeSuite(suite({0.0, 1e4}, seeds(1)), glMethods(), Variant::Jittered));
}
