// Coarse occluders kept in a project ("coarse_occluders", project/CoarseOccluders.h) and the sweep
// that charts them (project/CoarseSweep.h): the key survives a round trip with what it does not
// know, every malformed entry is one line naming it, the rays between the patches are answered by
// the stand-in (bit for bit what the coarse level's own exact sampling says) while the level keeps
// its full mesh elsewhere, and a sweep's counts are the differences of the two exact answers.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "TestScenes.h"
#include "plugins/SceneFormats.h"
#include "project/CoarseOccluders.h"
#include "project/CoarseSweep.h"
#include "project/Project.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"

using namespace sightline;
using namespace sightline::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

class CoarseOccluders : public ::testing::Test {
protected:
    fs::path folder;

    void SetUp() override
    {
        folder = fs::temp_directory_path() /
                 ("sightline-coarse-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(folder);
        fs::create_directories(folder);
        // Object 0: a lumpy closed torus of 18,432 triangles across the view; object 1: an open
        // quad off to the side (no inner stand-in can stand in an open mesh).
        Scene level;
        level.addMeshInstance(closedTorus({0.5, 0.5, 2.0}, 0.6, 0.25, 192, 48, 0.15));
        level.addMeshInstance(quad({3, 0, 2}, {1, 0, 0}, {0, 1, 0}, "panel"));
        saveScene(level, folder / "torus.glb");
    }
    void TearDown() override { fs::remove_all(folder); }

    json document(const json& coarse) const
    {
        json d = {{"version", 1},
                  {"scene", "torus.glb"},
                  {"source", {{"corner", {-0.5, -0.5, 0}}, {"u", {2, 0, 0}}, {"v", {0, 2, 0}}, {"samples", {32, 32}}}},
                  {"receiver", {{"corner", {-0.3, -0.4, 4}}, {"u", {1.8, 0, 0.2}}, {"v", {0, 1.8, 0}}, {"samples", {32, 32}}}}};
        if (!coarse.is_null())
            d["coarse_occluders"] = coarse;
        return d;
    }
    Project project(const json& coarse) const { return parseProject(document(coarse), folder, "p.json"); }

    static std::string errorOf(const std::function<void()>& f)
    {
        try {
            f();
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    }
};

HiddenSampleMap exactMap(const Scene& scene, const Project& p)
{
    BitmaskOptions options;
    options.threads = 2;
    return CpuBitmaskSampler(scene).sample(p.source, p.receiver, options);
}

} // namespace

TEST_F(CoarseOccluders, KeyRoundTripsWithWhatItDoesNotKnow)
{
    const json list = json::array({{{"instance", 0}, {"kind", "closest"}, {"triangles", 2000}, {"note", "statue"}},
                                   {{"instance", 1}, {"kind", "inner"}, {"resolution", 24}}});
    const Project p = project(list);
    const std::vector<CoarseOccluder> read = coarseOccluders(p);
    ASSERT_EQ(read.size(), 2u);
    EXPECT_EQ(read[0].kind, CoarseKind::Closest);
    EXPECT_EQ(read[0].triangles, 2000u);
    EXPECT_EQ(read[0].extra, json({{"note", "statue"}}));
    EXPECT_EQ(read[1].kind, CoarseKind::Inner);
    EXPECT_EQ(read[1].resolution, 24);
    EXPECT_EQ(coarseOccludersJson(read), list);
    saveProject(p, folder / "saved.json");
    const Project again = loadProject(folder / "saved.json");
    EXPECT_EQ(coarseOccludersJson(coarseOccluders(again)), list);
    EXPECT_TRUE(coarseOccluders(project(json())).empty());
}

TEST_F(CoarseOccluders, MalformedEntriesAreOneLineNamingTheKey)
{
    const std::vector<std::pair<json, std::string>> bad = {
        {json::object(), "'coarse_occluders' must be an array"},
        {json::array({1}), "coarse_occluders[0] must be an object"},
        {json::array({{{"kind", "closest"}}}), "coarse_occluders[0] must be an object with instance"},
        {json::array({{{"instance", -1}, {"kind", "closest"}}}), "coarse_occluders[0].instance must be a whole number"},
        {json::array({{{"instance", 1.5}, {"kind", "closest"}}}), "coarse_occluders[0].instance must be a whole number"},
        {json::array({{{"instance", 18446744073709551615ull}, {"kind", "closest"}}}), "coarse_occluders[0].instance"},
        {json::array({{{"instance", 0}, {"kind", "smallest"}}}), "coarse_occluders[0].kind must be"},
        {json::array({{{"instance", 0}, {"kind", "closest"}, {"triangles", 3}}}), "coarse_occluders[0].triangles"},
        {json::array({{{"instance", 0}, {"kind", "closest"}, {"triangles", 1e12}}}), "coarse_occluders[0].triangles"},
        {json::array({{{"instance", 0}, {"kind", "inner"}, {"resolution", 100000}}}), "coarse_occluders[0].resolution"},
        {json::array({{{"instance", 0}, {"kind", "closest"}}, {{"instance", 0}, {"kind", "inner"}}}), "listed twice"},
    };
    for (const auto& [value, expected] : bad) {
        const std::string message = errorOf([&] { (void)project(value); });   // refused on load
        EXPECT_NE(message.find(expected), std::string::npos) << value.dump() << " -> " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_EQ(message.rfind("p.json: ", 0), 0u) << message;
    }
    // What only the level can say: an object it does not have, an inner stand-in for an open mesh.
    EXPECT_NE(errorOf([&] { (void)buildRayScene(project(json::array({{{"instance", 2}, {"kind", "closest"}}}))); })
                  .find("coarse_occluders[0].instance 2 does not exist (the scene has 2 objects)"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { (void)buildRayScene(project(json::array({{{"instance", 1}, {"kind", "inner"}}}))); })
                  .find("not closed"),
              std::string::npos);
}

TEST_F(CoarseOccluders, RaysBetweenThePatchesAreAnsweredByTheStandIn)
{
    const Project full = project(json());
    const Scene original = buildScene(full);
    for (const json& entry : {json{{"instance", 0}, {"kind", "closest"}, {"triangles", 1500}},
                              json{{"instance", 0}, {"kind", "inner"}, {"resolution", 20}}}) {
        const Project p = project(json::array({entry}));
        const Scene rays = buildRayScene(p);
        // The same level, object 0's mesh replaced, object 1 and the placed transforms untouched.
        Scene expected = original;
        CoarseOccluder spec = coarseOccluders(p)[0];
        expected.meshes[expected.instances[0].mesh] = coarseOccluderMesh(original.meshes[original.instances[0].mesh], spec);
        ASSERT_EQ(rays.instances.size(), original.instances.size());
        EXPECT_EQ(rays.triangleCount(), expected.triangleCount());
        EXPECT_LT(rays.triangleCount(), original.triangleCount());
        EXPECT_EQ(rays.instances[1].transform, original.instances[1].transform);
        const HiddenSampleMap coarseMap = exactMap(rays, p), expectedMap = exactMap(expected, p);
        EXPECT_EQ(coarseMap, expectedMap) << entry.dump();
        // The full level is what buildScene (drawing, AO, lights) still gives.
        EXPECT_EQ(buildScene(p).triangleCount(), original.triangleCount());
        if (spec.kind == CoarseKind::Inner) {   // conservative: no ray blocked that the torus lets through
            const HiddenSampleMap fullMap = exactMap(original, p);
            std::uint64_t falseBlocked = 0;
            for (int j = 0; j < fullMap.receiverCount(); ++j)
                for (int w = 0; w < fullMap.wordsPerRow(); ++w)
                    falseBlocked += std::uint64_t(std::popcount(coarseMap.row(j)[std::size_t(w)] & ~fullMap.row(j)[std::size_t(w)]));
            EXPECT_EQ(falseBlocked, 0u);
        }
    }
    // A cache hands back the same stand-in without simplifying again.
    CoarseMeshCache cache;
    CoarseOccluder spec;
    spec.triangles = 1500;
    const Mesh& once = cache.standIn(original.meshes[0], spec);
    EXPECT_EQ(&cache.standIn(original.meshes[0], spec), &once);
}

TEST_F(CoarseOccluders, SweepCountsAreTheDifferencesOfTheTwoExactAnswers)
{
    const Project p = project(json());
    const Scene original = buildScene(p);
    CoarseSweepRequest request;
    request.counts = {4000, 1000};
    request.instance = 0;
    request.repeat = 1;
    request.threads = 2;
    std::size_t progressCalls = 0;
    request.progress = [&](const CoarseSweep& s) { return ++progressCalls == s.points.size(); };
    const CoarseSweep sweep = sweepCoarseOccluders(original, p.source, p.receiver, nullptr, request);
    EXPECT_EQ(progressCalls, 2u);
    ASSERT_EQ(sweep.points.size(), 2u);
    EXPECT_EQ(sweep.rays, 1024u * 1024u);
    EXPECT_EQ(sweep.triangles, original.triangleCount());
    const HiddenSampleMap exact = exactMap(original, p);
    for (const CoarseSweepPoint& point : sweep.points) {
        Scene coarse = original;
        CoarseOccluder spec;
        spec.triangles = point.asked;
        applyCoarseOccluders({spec}, coarse);
        EXPECT_EQ(point.triangles, coarse.triangleCount());
        const HiddenSampleMap map = exactMap(coarse, p);
        std::uint64_t onlyCoarse = 0, onlyFull = 0;
        for (int j = 0; j < exact.receiverCount(); ++j)
            for (int i = 0; i < p.source.sampleCount(); ++i) {
                onlyCoarse += map.blocked(j, i) && !exact.blocked(j, i);
                onlyFull += exact.blocked(j, i) && !map.blocked(j, i);
            }
        EXPECT_EQ(point.falseBlocked, onlyCoarse) << point.asked;
        EXPECT_EQ(point.falseFree, onlyFull) << point.asked;
        EXPECT_GT(point.ms, 0.0);
    }
    EXPECT_GT(sweep.points[1].disagreeing(), 0u);   // 1,000 of 18,432 triangles is not the torus
    // A progress that says stop ends the sweep after that point.
    request.progress = [](const CoarseSweep&) { return false; };
    EXPECT_EQ(sweepCoarseOccluders(original, p.source, p.receiver, nullptr, request).points.size(), 1u);
    // Bad requests.
    request.counts = {3};
    EXPECT_NE(errorOf([&] { (void)sweepCoarseOccluders(original, p.source, p.receiver, nullptr, request); }).find("[4, 100000000]"),
              std::string::npos);
    request.counts = {100};
    request.instance = 9;
    EXPECT_NE(errorOf([&] { (void)sweepCoarseOccluders(original, p.source, p.receiver, nullptr, request); }).find("does not exist"),
              std::string::npos);
    EXPECT_EQ(defaultSweepCounts(18432), (std::vector<std::size_t>{9216, 4608, 2304, 1152, 576, 288, 144}));
    EXPECT_EQ(defaultSweepCounts(150), (std::vector<std::size_t>{75}));
    EXPECT_TRUE(defaultSweepCounts(6).empty());
}

// The editor keeps one sampler and gives it the stand-in's level: the answer must be the one a
// sampler built for that level gives.
TEST_F(CoarseOccluders, ASamplerGivenTheStandInsLevelAnswersForIt)
{
    const Project p = project(json::array({{{"instance", 0}, {"kind", "closest"}, {"triangles", 1500}}}));
    const Scene full = buildScene(p), rays = buildRayScene(p);
    BitmaskOptions options;
    options.threads = 2;
    CpuBitmaskSampler kept(full);
    const HiddenSampleMap before = kept.sample(p.source, p.receiver, options);
    EXPECT_EQ(before, exactMap(full, p));
    kept.setScene(rays);
    const HiddenSampleMap after = kept.sample(p.source, p.receiver, options);
    EXPECT_GT(after.differenceCount(before), 0u);
    EXPECT_EQ(after, exactMap(rays, p));
}
