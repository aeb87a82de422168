// `sightline-cli disagreement` as a user runs it, held to answers computed here: every ray of the
// approximation judged by the contract's brute force (ExactJudge) gives the false-blocked and
// false-free counts; the picture has a red pixel per false-blocked ray and a blue one per
// false-free ray; inner occluders never block a free ray; the exact GL pass differs on ties only.
#include <filesystem>
#include <fstream>

#include <QImage>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRunner.h"
#include "ExactJudge.h"
#include "TestScenes.h"
#include "plugins/SceneFormats.h"
#include "project/Approximation.h"
#include "project/Project.h"
#include "visibility/CpuBitmaskSampler.h"
#include "visibility/RayCastSampler.h"
#include "visibility/RayDisagreement.h"

using namespace sightline;
using namespace sightline::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

class DisagreementCli : public CliFolderTest {
protected:
    void SetUp() override
    {
        CliFolderTest::SetUp();
        // The CLI tests' wall with a hole, and a crate in the hole's lower half.
        writeWallWithHoleObj(folder / "wall.obj");
        const json project = crateInWallProject();
        std::ofstream(folder / "p.json") << project.dump(2);
    }

    /// False-blocked and false-free counts of `approximate` by the judge's verdict on every ray.
    std::pair<std::uint64_t, std::uint64_t> judgedErrors(const HiddenSampleMap& approximate)
    {
        const Project project = loadProject(folder / "p.json");
        const ExactJudge judge(worldTriangles(buildScene(project)), project.source, project.receiver);
        std::vector<std::pair<int, int>> rays;
        for (int j = 0; j < approximate.receiverCount(); ++j)
            for (int i = 0; i < approximate.sourceCount(); ++i)
                rays.emplace_back(j, i);
        const std::vector<RayKind> kinds = judge.kinds(rays);
        std::uint64_t falseBlocked = 0, falseFree = 0;
        for (std::size_t k = 0; k < rays.size(); ++k) {
            const bool blocked = approximate.blocked(rays[k].first, rays[k].second);
            falseBlocked += blocked && kinds[k] == RayKind::Free;
            falseFree += !blocked && kinds[k] == RayKind::Blocked;
        }
        return {falseBlocked, falseFree};
    }

    static int pixelsOf(const QImage& image, const std::uint8_t rgb[3])
    {
        int n = 0;
        for (int y = 0; y < image.height(); ++y)
            for (int x = 0; x < image.width(); ++x)
                n += image.pixel(x, y) == qRgb(rgb[0], rgb[1], rgb[2]);
        return n;
    }
};

} // namespace

TEST(Approximation, EverySpellingReadsBackAndBadOnesSayWhatIsAccepted)
{
    for (const char* name : {"table-256x128", "table-32x16", "gl", "gl-table-64x32", "samples-2", "samples-64",
                             "coarse-5000", "coarse-4", "inner-32", "inner-256"})
        EXPECT_EQ(approximationName(parseApproximation(name)), name);
    EXPECT_EQ(approximationName(parseApproximation("table")), "table-256x128");
    EXPECT_EQ(approximationName(parseApproximation("coarse")), "coarse-5000");
    EXPECT_EQ(approximationName(parseApproximation("inner")), "inner-32");
    for (const char* bad : {"", "tables", "table-", "table-0x16", "table-32x", "table-32x16x2", "samples", "samples-1",
                            "samples-65", "samples--2", "coarse-3", "coarse-1e4", "inner-3", "gl-", "GL", " table"}) {
        try {
            parseApproximation(bad);
            ADD_FAILURE() << "accepted \"" << bad << "\"";
        } catch (const std::exception& e) {
            EXPECT_NE(std::string(e.what()).find("samples-K"), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        }
    }
}

TEST_F(DisagreementCli, HoughTableErrorsAreTheRaysTheJudgeSaysItGotWrongAndThePictureShowsEach)
{
    const fs::path png = folder / "table.png";
    const json r = runJson("disagreement " + path("p.json") + " --approximation table-32x16 --json --image " + png.string());
    const Project project = loadProject(folder / "p.json");
    BitmaskOptions table;
    table.mode = MaskMode::Table, table.tableWidth = 32, table.tableHeight = 16;
    const HiddenSampleMap approximate = CpuBitmaskSampler(buildScene(project)).sample(project.source, project.receiver, table);
    const auto [falseBlocked, falseFree] = judgedErrors(approximate);
    EXPECT_EQ(r["approximation"], "table-32x16");
    EXPECT_EQ(r["rays"], 128 * 480);
    EXPECT_TRUE(r["judged"].get<bool>());
    EXPECT_EQ(r["exact_errors"], 0);
    EXPECT_EQ(r["false_blocked"], falseBlocked);
    EXPECT_EQ(r["false_free"], falseFree);
    EXPECT_GT(falseBlocked + falseFree, 100u) << "a 32x16 table errs on the wall's edges";
    EXPECT_EQ(r["blocked_approximate"], approximate.blockedCount());
    EXPECT_NEAR(r["disagreeing_fraction"].get<double>(), double(falseBlocked + falseFree) / (128.0 * 480.0), 1e-12);

    const QImage image(QString::fromStdString(png.string()));
    ASSERT_FALSE(image.isNull());
    EXPECT_EQ(image.width(), 24 * 17 - 1);
    EXPECT_EQ(image.height(), 20 * 9 - 1);
    EXPECT_EQ(pixelsOf(image, kFalseBlockedRgb), int(falseBlocked));
    EXPECT_EQ(pixelsOf(image, kFalseFreeRgb), int(falseFree));
    EXPECT_EQ(pixelsOf(image, kTieRgb), r["ties"].get<int>());
}

TEST_F(DisagreementCli, FewerSamplesErrWhereACellStraddlesAnEdge)
{
    const json r = runJson("disagreement " + path("p.json") + " --approximation samples-4 --json");
    // Here: each ray takes the answer of the ray between its cells' samples, by the reference.
    const Project project = loadProject(folder / "p.json");
    const Patch coarseSource = withFewerSamples(project.source, 4), coarseReceiver = withFewerSamples(project.receiver, 4);
    const HiddenSampleMap coarse = RayCastScene(buildScene(project)).sample(coarseSource, coarseReceiver);
    HiddenSampleMap approximate(project.source.sampleCount(), project.receiver.na, project.receiver.nb);
    for (int j = 0; j < approximate.receiverCount(); ++j)
        for (int i = 0; i < approximate.sourceCount(); ++i) {
            const int cj = (j / project.receiver.na / 4) * coarseReceiver.na + (j % project.receiver.na) / 4;
            const int ci = (i / project.source.na / 4) * coarseSource.na + (i % project.source.na) / 4;
            if (coarse.blocked(cj, ci))
                approximate.setBlocked(j, i);
        }
    const auto [falseBlocked, falseFree] = judgedErrors(approximate);
    EXPECT_EQ(r["false_blocked"], falseBlocked);
    EXPECT_EQ(r["false_free"], falseFree);
    EXPECT_GT(falseBlocked, 0u);
    EXPECT_GT(falseFree, 0u);
}

TEST_F(DisagreementCli, TheExactGlPassDiffersOnTiesOnly)
{
    const json r = runJson("disagreement " + path("p.json") + " --approximation gl --json");
    EXPECT_EQ(r["false_blocked"], 0);
    EXPECT_EQ(r["false_free"], 0);
    EXPECT_TRUE(r["judged"].get<bool>());
}

TEST_F(DisagreementCli, InnerOccludersNeverBlockAFreeRayAndCoarseOnesSayWhatTheyCost)
{
    writeTorusProject(folder, "torus.json");   // the coarse command's scene
    const json inner = runJson("disagreement " + path("torus.json") + " --approximation inner --json");
    EXPECT_EQ(inner["rays"], 1024 * 1024);
    EXPECT_EQ(inner["false_blocked"], 0);
    EXPECT_GT(inner["false_free"].get<int>(), 0);
    EXPECT_EQ(inner["meshes_replaced"], 1);
    const json coarse = runJson("disagreement " + path("torus.json") + " --approximation coarse-3000 --json");
    EXPECT_LE(coarse["triangles_approximate"].get<int>(), 3002);
    EXPECT_EQ(coarse["triangles_exact"], 192 * 48 * 2);
    EXPECT_GT(coarse["false_blocked"].get<int>() + coarse["false_free"].get<int>(), 0);
    EXPECT_LT(coarse["disagreeing_fraction"].get<double>(), 0.01);
}

TEST_F(DisagreementCli, BadRequestsGetOneLineAndNoFileIsReplaced)
{
    const std::string before = readAll(folder / "p.json");
    for (const std::string& arguments :
         std::vector<std::string>{"--approximation samples-1", "--approximation tables", "--approximation coarse-100000",
          "--image " + path("p.json"), "--image " + path("wall.obj"), "--image ''"}) {
        const CliRun run = runCli("disagreement " + path("p.json") + " " + arguments);
        EXPECT_NE(run.code, 0) << arguments;
        EXPECT_TRUE(oneLine(run.err)) << arguments << ": " << run.err;
    }
    EXPECT_EQ(readAll(folder / "p.json"), before);
    EXPECT_EQ(readAll(folder / "wall.obj").substr(0, 2), "v ");
}
