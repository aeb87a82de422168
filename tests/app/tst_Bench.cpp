// sightline-cli bench: every method against the reference, CSV and chart.
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <unistd.h>

#include <QImage>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRunner.h"
#include "bench/Bench.h"
#include "bench/BenchChart.h"
#include "bench/TunedEmbree.h"
#include "project/Project.h"
#include "base/Error.h"
#include "visibility/ExactJudge.h"
#include "visibility/RayCastSampler.h"

using namespace sightline;
namespace fs = std::filesystem;

namespace {

/// A wall with a hole and a crate between two tilted patches.
fs::path writeProject(const fs::path& folder)
{
    fs::create_directories(folder);
    test::writeWallWithHoleObj(folder / "wall.obj");
    const nlohmann::json project = {
        {"version", 1},
        {"scene", "wall.obj"},
        {"source", {{"corner", {0, 0, 0}}, {"u", {1, 0, 0}}, {"v", {0, 1, 0}}}},
        {"receiver", {{"corner", {-0.5, -0.2, 4}}, {"u", {2, 0, 0.3}}, {"v", {0, 1.4, 0}}}},
        {"occluders", {{{"mesh", "box"}, {"transform", {0.4, 0, 0, 0, 0, 0.3, 0, 0, 0, 0, 0.4, 0, 0.5, 0.15, 2.2, 1}}}}},
    };
    std::ofstream(folder / "p.json") << project.dump();
    return folder / "p.json";
}

} // namespace

TEST(Bench, EveryMethodAgainstTheReference)
{
    const fs::path folder = fs::temp_directory_path() / ("sightline_bench_" + std::to_string(getpid()));
    bench::Settings settings;
    settings.projects = {writeProject(folder).string()};
    settings.methods = bench::parseMethods("raycast,cpu,cpu-bitmask,cpu-hybrid,cpu-table-16x8");
    settings.sourceCounts = {32, 128};
    settings.receiverSides = {16, 24};
    settings.repeat = 1;
    settings.minBatchMs = 0.0;
    int progressCalls = 0;
    const auto rows = bench::run(settings, [&](const bench::Row&) { ++progressCalls; });
    ASSERT_EQ(rows.size(), 5u * 2u * 2u);
    EXPECT_EQ(progressCalls, 20);
    for (std::size_t k = 0; k < rows.size(); ++k)   // timed in rounds, reported in method order
        EXPECT_EQ(rows[k].method, settings.methods[k % 5]);
    for (const bench::Row& r : rows) {
        // The CPU sampler's rows name the strategy it ran; Auto's is one of the two it chooses from.
        if (r.method == "raycast")
            EXPECT_EQ(r.variant, "");
        else if (r.method == "cpu-bitmask" || r.method == "cpu-table-16x8")
            EXPECT_TRUE(r.variant.starts_with("bitmask")) << r.method << ' ' << r.variant;
        else if (r.method == "cpu-hybrid")
            EXPECT_TRUE(r.variant.starts_with("hybrid")) << r.variant;
        else
            EXPECT_TRUE(r.variant.starts_with("bitmask") || r.variant.starts_with("raycast")) << r.variant;
        EXPECT_EQ(r.rays, std::uint64_t(r.sourceSamples) * std::uint64_t(r.receiverSide * r.receiverSide));
        EXPECT_GT(r.ms, 0.0);
        EXPECT_GT(r.threadMs, 0.0);
        EXPECT_EQ(r.runs, 1);
        EXPECT_EQ(r.referenceErrors, 0u) << r.method;
        if (r.method == "raycast") {
            EXPECT_TRUE(r.judged);
            EXPECT_EQ(r.wronglyBlocked + r.wronglyFree + r.ties, 0u);
        } else if (r.method == "cpu-table-16x8") {
            EXPECT_GT(r.errorFraction(), 0.001) << r.sourceSamples;   // a coarse table is visibly wrong
        } else {
            EXPECT_TRUE(r.judged) << r.method;                        // exact modes: ties only
            EXPECT_EQ(r.wronglyBlocked + r.wronglyFree, 0u) << r.method;
        }
    }
    const std::string csv = bench::toCsv(rows);
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 21);
    EXPECT_EQ(csv.rfind("project,method,source_samples,receiver,rays,ms,blocked,wrongly_blocked,wrongly_free,error_fraction,"
                        "light_mae,dense_light_mae,thread_ms,ties,variant,runs\n", 0), 0u);

    const fs::path png = folder / "chart.png";
    bench::writeChart(rows, png);
    QImage image(QString::fromStdString(png.string()));
    ASSERT_FALSE(image.isNull());
    EXPECT_EQ(image.width(), 1100);
    EXPECT_EQ(image.height(), 700);
    int coloured = 0;   // markers and text: pixels that are not white or grey
    for (int yy = 0; yy < image.height(); yy += 2)
        for (int xx = 0; xx < image.width(); xx += 2) {
            const QColor c = image.pixelColor(xx, yy);
            coloured += std::max({c.red(), c.green(), c.blue()}) - std::min({c.red(), c.green(), c.blue()}) > 60;
        }
    EXPECT_GT(coloured, 200);
    fs::remove_all(folder);
}

TEST(Bench, TheTunedTracerKeepsTheFastestOfItsTraversals)
{
    // Every traversal a user could tune (either end, coherent or not) casts every segment: each
    // agrees with the exact reference but for a few float misjudgements, and with the others.
    const fs::path folder = fs::temp_directory_path() / ("sightline_tuned_" + std::to_string(getpid()));
    bench::Settings settings;
    settings.projects = {writeProject(folder).string()};
    const Project project = loadProject(settings.projects[0]);
    const Scene scene = buildScene(project);
    const RayCastScene reference(scene);
    const bench::TunedEmbree tuned(worldTriangles(scene));
    for (const auto& [na, nb, side] : {std::tuple{8, 4, 16}, std::tuple{32, 32, 24}, std::tuple{5, 3, 7}}) {
        Patch source = project.source, receiver = project.receiver;
        source.na = na, source.nb = nb, receiver.na = receiver.nb = side;
        const HiddenSampleMap truth = reference.sample(source, receiver);
        ASSERT_GT(truth.blockedCount(), truth.rayCount() / 10);
        ASSERT_LT(truth.blockedCount(), truth.rayCount() * 9 / 10);
        for (const bench::TunedTraversal& traversal : bench::tunedTraversals()) {
            const HiddenSampleMap map = tuned.sample(source, receiver, 2, traversal);
            EXPECT_LE(double(map.differenceCount(truth)), 1e-3 * double(truth.rayCount())) << traversal.name() << ' ' << na;
        }
    }

    settings.methods = bench::parseMethods("embree-tuned");
    settings.sourceCounts = {32};
    settings.receiverSides = {16};
    settings.repeat = 1;
    const auto rows = bench::run(settings, {});
    ASSERT_EQ(rows.size(), 1u);
    std::vector<std::string> names;
    for (const bench::TunedTraversal& traversal : bench::tunedTraversals())
        names.push_back(traversal.name());
    EXPECT_EQ(names.size(), 4u);
    EXPECT_NE(std::find(names.begin(), names.end(), rows[0].variant), names.end()) << rows[0].variant;
    EXPECT_NE(bench::toCsv(rows).find("," + rows[0].variant + "," + std::to_string(rows[0].runs) + "\n"), std::string::npos);
    // A call of 512 rays: timed until its batch took Settings::minBatchMs (20 ms by default), up
    // to kMaxRunsPerRound runs in the one round.
    EXPECT_GT(rows[0].runs, 1);
    EXPECT_LE(rows[0].runs, bench::kMaxRunsPerRound);
    fs::remove_all(folder);
}

TEST(Bench, DifferencesFromTheReferenceAreJudgedTiesOrErrors)
{
    // A wall x in [0, 1], y in [-1, 1] at z = 1 between a source at z = 0 and a receiver at z = 2,
    // both 4x4 samples over x in [-0.75, 0.75]: samples at x = -0.5625 ... 0.5625, none on the
    // wall's edge x = 0. A second wall's edge lies exactly under the rays joining the samples at
    // x = -0.1875 (a tie for each of them).
    WorldTriangles triangles;
    const auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
        triangles.vertices.insert(triangles.vertices.end(), {a, b, c, a, c, d});
        triangles.instanceOf.insert(triangles.instanceOf.end(), {0, 0});
    };
    quad({0.0f, -1.0f, 1.0f}, {1.0f, -1.0f, 1.0f}, {1.0f, 1.0f, 1.0f}, {0.0f, 1.0f, 1.0f});
    quad({-0.1875f, -1.0f, 0.9f}, {-0.1875f, 1.0f, 0.9f}, {-0.4f, 1.0f, 0.9f}, {-0.4f, -1.0f, 0.9f});
    Patch source, receiver;
    source.corner = {-0.75, -0.75, 0.0}, source.u = {1.5, 0.0, 0.0}, source.v = {0.0, 1.5, 0.0};
    receiver = source;
    receiver.corner.z = 2.0;
    source.na = source.nb = receiver.na = receiver.nb = 4;
    const HiddenSampleMap truth = RayCastScene(triangles).sample(source, receiver);
    const ExactJudge judge(triangles, source, receiver);
    // A clear error each way and a flipped tie: receiver sample 0 (x = -0.5625, column 0) to
    // source sample 0 is free, receiver sample 3 (x = 0.5625) to source sample 3 is blocked by the
    // first wall, and receiver sample 1 (x = -0.1875) to source sample 1 (the same x) grazes the
    // second wall's edge.
    ASSERT_EQ(judge.ray(0, 0), RayKind::Free);
    ASSERT_EQ(judge.ray(3, 3), RayKind::Blocked);
    ASSERT_EQ(judge.ray(1, 1), RayKind::EdgeTie);
    HiddenSampleMap map = truth;
    const auto flip = [&](int j, int i) { map.row(j)[std::size_t(i >> 6)] ^= std::uint64_t(1) << (i & 63); };
    ASSERT_FALSE(truth.blocked(0, 0));
    ASSERT_TRUE(truth.blocked(3, 3));
    flip(0, 0), flip(3, 3), flip(1, 1);
    bench::Row row;
    int judges = 0;
    bench::judgeDifferences(row, map, truth, [&]() -> const ExactJudge& { ++judges; return judge; });
    EXPECT_TRUE(row.judged);
    EXPECT_EQ(row.wronglyBlocked, 1u);
    EXPECT_EQ(row.wronglyFree, 1u);
    EXPECT_EQ(row.ties, 1u);
    EXPECT_EQ(row.referenceErrors, 0u);
    EXPECT_EQ(judges, 1);
    // No difference: nothing judged, no judge made.
    bench::judgeDifferences(row, truth, truth, [&]() -> const ExactJudge& { ++judges; return judge; });
    EXPECT_TRUE(row.judged);
    EXPECT_EQ(row.wronglyBlocked + row.wronglyFree + row.ties, 0u);
    EXPECT_EQ(judges, 1);
    // The judge siding with the method: the reference is wrong (counted, not hidden).
    bench::judgeDifferences(row, truth, map, [&]() -> const ExactJudge& { return judge; });
    EXPECT_EQ(row.referenceErrors, 2u);
    EXPECT_EQ(row.ties, 1u);
}

TEST(Bench, SettingsAreChecked)
{
    EXPECT_THROW(bench::parseMethods("raycast,warp"), Error);
    EXPECT_THROW(bench::parseMethods("cpu-table-3x1"), Error);
    EXPECT_THROW(bench::parseMethods("gl-table-256x8193"), Error);
    EXPECT_THROW(bench::parseMethods("gl-table-256"), Error);
    EXPECT_EQ(bench::parseMethods("gl,gl-table-256x128"), (std::vector<std::string>{"gl", "gl-table-256x128"}));
    EXPECT_THROW(bench::parseMethods(""), Error);
    EXPECT_EQ(bench::sourceGrid(32), std::make_pair(8, 4));
    EXPECT_EQ(bench::sourceGrid(128), std::make_pair(16, 8));
    EXPECT_EQ(bench::sourceGrid(1024), std::make_pair(32, 32));
    EXPECT_EQ(bench::sourceGrid(7), std::make_pair(7, 1));
}

TEST(Bench, ShadowRowsCompareTheLightWithEqualSamplesAndADenseReference)
{
    const fs::path folder = fs::temp_directory_path() / ("sightline_bench_shadow_" + std::to_string(getpid()));
    bench::Settings settings;
    settings.projects = {writeProject(folder).string()};
    settings.methods = bench::parseMethods("raycast,cpu,cpu-jitter,raycast-jitter");
    settings.sourceCounts = {16, 256};
    settings.receiverSides = {16};
    settings.repeat = 1;
    settings.denseSide = 64;
    const auto rows = bench::run(settings);
    ASSERT_EQ(rows.size(), 8u);
    std::map<std::pair<std::string, int>, const bench::Row*> rowOf;
    const auto byMethod = [&](const char* method, int sources) { return *rowOf.at({method, sources}); };
    for (const bench::Row& r : rows) {
        rowOf[{r.method, r.sourceSamples}] = &r;
        // Exact methods: the light at equal samples within the 1/1024 (in fact 0 or a
        // grazing ray); every row has its error against the dense reference.
        EXPECT_LE(r.lightMae, 1.0 / 1024) << r.method;
        ASSERT_GE(r.denseMae, 0.0) << r.method;
        EXPECT_LT(r.denseMae, 0.25) << r.method;
    }
    // More light samples, closer to the dense light.
    EXPECT_LT(byMethod("raycast", 256).denseMae, byMethod("raycast", 16).denseMae);
    // Jittered rows are compared with the reference cast to the same jittered samples.
    EXPECT_EQ(byMethod("raycast-jitter", 16).lightMae, 0.0);
    EXPECT_NE(byMethod("raycast-jitter", 16).denseMae, byMethod("raycast", 16).denseMae);

    const fs::path png = folder / "shadow.png";
    bench::writeChart(rows, png, bench::ChartKind::ShadowError);
    EXPECT_FALSE(QImage(QString::fromStdString(png.string())).isNull());
    const std::string csv = bench::toCsv(rows);
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 9);
    EXPECT_EQ(csv.back(), '\n');
    fs::remove_all(folder);
}
