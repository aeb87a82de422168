// docs/design.md §2's "Exact" contract on adversarial input: every exact CPU-side method (the Embree
// reference, the CPU bitmask sampler with every strategy and both kernels, decorrelated samples,
// bumpy receivers, small sources with the patches' roles swapped) against an exact double brute
// force (ExactJudge.h), at production sample counts, at the origin and 1, 10 and 100 km from it.
// Zero disagreements outside ties.

#include <gtest/gtest.h>

#include "ExactnessSuite.h"
#include "bitmask/Strategy.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/RayCastSampler.h"

using namespace sightline;
using namespace sightline::test;

namespace {

/// Every exact CPU-side method: the reference, and the CPU sampler's strategies and kernels.
std::vector<Method> cpuMethods()
{
    const auto cpu = [](CpuStrategy strategy, bool simd) {
        return [=](const Scene& scene, const Patch& s, const Patch& r, const Question& q) {
            BitmaskOptions options;
            options.strategy = strategy;
            options.simd = simd;
            options.jitter = q.jitter;
            options.heights = q.heights;
            return CpuBitmaskSampler(scene).sample(s, r, options);
        };
    };
    return {
        {"raycast",
         [](const Scene& scene, const Patch& s, const Patch& r, const Question& q) {
             return RayCastScene(scene).sample(s, r, {.jitter = q.jitter, .heights = q.heights});
         }},
        {"cpu", cpu(CpuStrategy::Auto, true)},
        {"cpu-bitmask", cpu(CpuStrategy::Bitmask, true)},
        {"cpu-scalar", cpu(CpuStrategy::Bitmask, false)},
        {"cpu-hybrid", cpu(CpuStrategy::Hybrid, true)},
        {"cpu-raycast", cpu(CpuStrategy::RayCast, true)},
    };
}

} // namespace

TEST(Exactness, EveryCpuMethodIsExactOnAdversarialScenesAtTheOrigin)
{
    expectExact(judgeSuite(suite({0.0}, seeds(4)), cpuMethods()));
}

TEST(Exactness, EveryCpuMethodIsExactOnAdversarialScenesFarFromTheOrigin)
{
    expectExact(judgeSuite(suite({1e3, 1e4, 1e5}, seeds(2)), cpuMethods()));
}

TEST(Exactness, DecorrelatedSamplesAreExactToo)
{
    // Every receiver sample sees the source grid shifted by its own offset (§6.2); the judge casts
    // to the same shifted samples.
    expectExact(judgeSuite(suite({0.0, 1e4}, seeds(2)), cpuMethods(), Variant::Jittered));
}

TEST(Exactness, BumpyReceiversAreExactToo)
{
    // Each receiver sample raised towards the source by its own height (§8).
    expectExact(judgeSuite(suite({0.0, 1e4}, seeds(2)), cpuMethods(), Variant::Bumpy));
}

TEST(Exactness, SmallSourcesAreExactWithThePatchesRolesSwapped)
{
    // 32x8 sources against the cases' receivers (16x32 to 128x32): the CPU sampler backprojects
    // onto the receiver (its patches swap roles), in tiles of up to 32x32 past 1024 samples.
    const std::vector<AdversarialCase> cases = suite({0.0, 1e4, 1e5}, seeds(2));
    std::size_t swapped = 0, tiled = 0;
    for (const AdversarialCase& c : cases) {
        const auto [source, receiver] = askedPatches(c, Variant::SmallSource);
        swapped += bitmask::swapPatchRoles(source, receiver, {});
        tiled += bitmask::receiverTilesToSwap(source, receiver, {}).has_value();
    }
    EXPECT_GT(swapped, cases.size() / 4);
    EXPECT_GT(tiled, cases.size() / 8);
    expectExact(judgeSuite(cases, cpuMethods(), Variant::SmallSource));
}
