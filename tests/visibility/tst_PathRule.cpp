// The path rule (base/PathRule.h): relative paths written in a file stay inside its folder.
#include <fstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "base/Error.h"
#include "base/PathRule.h"

using namespace sightline;
namespace fs = std::filesystem;

namespace {

class PathRule : public ::testing::Test {
protected:
    fs::path root, project;
    void SetUp() override
    {
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        root = fs::temp_directory_path() / ("sightline_pathrule_" + std::string(test->name()) + "_" + std::to_string(::getpid()));
        fs::remove_all(root);
        project = root / "levels";
        fs::create_directories(project / "props");
        fs::create_directories(root / "levels2");
        std::ofstream(root / "secret.bin") << "x";
    }
    void TearDown() override { fs::remove_all(root); }

    std::string refusal(const std::string& written) const
    {
        try {
            resolveWrittenPath(written, project, false, "p.json", "scene");
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    }
};

} // namespace

TEST_F(PathRule, RelativePathsInsideTheFolderResolve)
{
    EXPECT_EQ(resolveWrittenPath("props/box.obj", project, false, "p.json", "scene"), project / "props" / "box.obj");
    EXPECT_EQ(resolveWrittenPath("props/../a.glb", project, false, "p.json", "scene"), project / "a.glb");
    EXPECT_TRUE(resolvesInside(project / "missing" / "later.glb", project)) << "need not exist yet";
}

TEST_F(PathRule, RelativePathsThatLeaveAreRefusedInOneLine)
{
    const std::string message = refusal("../secret.bin");
    EXPECT_EQ(message, "p.json: scene '../secret.bin' leaves the project's folder; pass --allow-outside-paths to allow it");
    EXPECT_FALSE(refusal("props/../../secret.bin").empty());
    EXPECT_FALSE(refusal("../levels2/x.glb").empty()) << "a sibling folder sharing the name's prefix is outside";
    EXPECT_EQ(resolveWrittenPath("../secret.bin", project, true, "p.json", "scene"), root / "secret.bin")
        << "allowed when the user says so";
}

TEST_F(PathRule, SymlinksOutOfTheFolderAreFollowed)
{
    fs::create_symlink(root / "secret.bin", project / "innocent.glb");
    fs::create_symlink(root, project / "props" / "up");
    EXPECT_FALSE(refusal("innocent.glb").empty());
    EXPECT_FALSE(refusal("props/up/secret.bin").empty());
    fs::create_symlink("props", project / "alias");   // a link that stays inside is fine
    EXPECT_TRUE(refusal("alias/box.obj").empty());
}

TEST_F(PathRule, AbsolutePathsAreTakenAsWritten)
{
    EXPECT_EQ(resolveWrittenPath((root / "secret.bin").string(), project, false, "p.json", "scene"), root / "secret.bin");
}

TEST_F(PathRule, AProjectReachedThroughASymlinkJudgesByItsRealFolder)
{
    fs::create_symlink(project, root / "shortcut");
    EXPECT_TRUE(resolvesInside(root / "shortcut" / "props" / "box.obj", root / "shortcut"));
    EXPECT_FALSE(resolvesInside(root / "shortcut" / ".." / "secret.bin", root / "shortcut"));
}

TEST(DescribeFailure, OutOfMemorySaysWhatWasBeingDone)
{
    EXPECT_EQ(describeFailure(std::bad_alloc(), "running 'shaft'"),
              "out of memory while running 'shaft' (ask for fewer samples, frames or pixels)");
    EXPECT_EQ(describeFailure(Error("p.json: bad"), "running 'shaft'"), "p.json: bad");
}
