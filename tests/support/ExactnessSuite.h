#pragma once
// Runs sampling methods over the adversarial suite (AdversarialScenes.h) and judges each against
// the exact brute force (ExactJudge.h): the driver of the exactness tests (tst_Exactness for the
// CPU-side methods, tst_GlExactness for the GL sampler).

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "AdversarialScenes.h"
#include "ExactJudge.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/SourceJitter.h"

namespace sightline::test {

/// What a case asks besides the scene and the patches: decorrelated source samples, a bumpy
/// receiver.
struct Question {
    SourceJitter jitter{};
    const ReceiverHeights* heights = nullptr;
};

struct Method {
    std::string name;
    std::function<HiddenSampleMap(const Scene&, const Patch&, const Patch&, const Question&)> sample;
};

/// How each case is asked: plainly, or with jitter and bumps made from the case's seed, or with
/// a source of at most 8 rows (its 32 columns kept, so the categories that put an occluder on a
/// source column still do): more receiver samples than source samples, so the CPU sampler swaps
/// the patches' roles, receivers past 1024 samples split into tiles (BitmaskOptions::swapRoles).
enum class Variant { Plain, Jittered, Bumpy, SmallSource };

/// The patches a case is asked with under `variant` (SmallSource cuts the source's rows; the
/// others keep the case's).
inline std::pair<Patch, Patch> askedPatches(const AdversarialCase& c, Variant variant)
{
    Patch source = c.source;
    if (variant == Variant::SmallSource)
        source.nb = std::min(source.nb, 8);
    return {source, c.receiver};
}

struct Tally {
    std::uint64_t wronglyBlocked = 0, wronglyFree = 0, judged = 0, ties = 0;
    std::string firstExample;
};

/// Runs `methods` on every case, judges each against the brute force, and returns per method the
/// non-tie errors (summed over the cases), printing a line per case that has any.
inline std::map<std::string, Tally> judgeSuite(const std::vector<AdversarialCase>& cases, const std::vector<Method>& methods,
                                        Variant variant = Variant::Plain)
{
    std::map<std::string, Tally> tallies;
    for (std::size_t n = 0; n < cases.size(); ++n) {
        const AdversarialCase& c = cases[n];
        const auto [source, receiver] = askedPatches(c, variant);
        Question question;
        ReceiverHeights heights;
        std::vector<glm::dvec3> displaced;
        if (variant == Variant::Jittered)
            question.jitter.seed = std::uint32_t(n + 1);
        if (variant == Variant::Bumpy) {
            // Bumps up to a tenth of the distance between the patches, towards the source.
            const double distance = glm::length(receiver.centre() - source.centre());
            heights = randomHeights(receiver, unsigned(n + 1), 0.1 * distance);
            question.heights = &heights;
            displaced = displacedSamples(source, receiver, heights);
        }
        std::vector<HiddenSampleMap> maps;
        for (const Method& m : methods)
            maps.push_back(m.sample(c.scene, source, receiver, question));
        std::vector<const HiddenSampleMap*> pointers;
        for (const HiddenSampleMap& m : maps)
            pointers.push_back(&m);
        const auto rays = raysToJudge(pointers, 2048, 7u);
        const ExactJudge judge(worldTriangles(c.scene), source, receiver, question.jitter,
                               displaced.empty() ? nullptr : &displaced);
        for (std::size_t k = 0; k < methods.size(); ++k) {
            const Verdict v = judge.judge(maps[k], rays);
            Tally& t = tallies[methods[k].name];
            t.wronglyBlocked += v.wronglyBlocked;
            t.wronglyFree += v.wronglyFree;
            t.judged += v.judged;
            t.ties += v.edgeTies + v.endTies;
            if (v.nonTie()) {
                std::printf("  %-12s %-48s %8llu wrongly blocked %8llu wrongly free (%dx%d receiver)\n",
                            methods[k].name.c_str(), c.name.c_str(), (unsigned long long)v.wronglyBlocked,
                            (unsigned long long)v.wronglyFree, receiver.na, receiver.nb);
                if (t.firstExample.empty())
                    t.firstExample = c.name + ", ray (j " + std::to_string(v.examples[0].first) + ", i " +
                                     std::to_string(v.examples[0].second) + ")";
            }
        }
    }
    return tallies;
}

inline std::vector<AdversarialCase> suite(const std::vector<double>& offsets, int seeds)
{
    std::vector<AdversarialCase> cases;
    for (Adversary kind : allAdversaries())
        for (int seed = 1; seed <= seeds; ++seed)
            for (double offset : offsets)
                cases.push_back(adversarialCase(kind, unsigned(seed), offset));
    return cases;
}

inline void expectExact(const std::map<std::string, Tally>& tallies)
{
    for (const auto& [name, t] : tallies) {
        std::printf("%-12s judged %10llu rays: %llu wrongly blocked, %llu wrongly free, %llu ties\n", name.c_str(),
                    (unsigned long long)t.judged, (unsigned long long)t.wronglyBlocked, (unsigned long long)t.wronglyFree,
                    (unsigned long long)t.ties);
        EXPECT_EQ(t.wronglyBlocked + t.wronglyFree, 0u) << name << ": first at " << t.firstExample;
    }
}

/// Seeds per category: a few in CI; SIGHTLINE_EXACTNESS_SEEDS=N for a longer sweep by hand.
inline int seeds(int ci)
{
    const char* text = std::getenv("SIGHTLINE_EXACTNESS_SEEDS");
    return text ? std::max(1, std::atoi(text)) : ci;
}


} // namespace sightline::test
