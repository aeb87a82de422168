// Saving: the old file survives any failure, keeps its mode and its symlink, and interrupted
// saves' leftovers are cleaned up without touching a live writer's.
#include <chrono>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/AtomicFile.h"
#include "base/Error.h"

using namespace sightline;
namespace fs = std::filesystem;

namespace {

class AtomicSave : public ::testing::Test {
protected:
    fs::path dir;
    void SetUp() override
    {
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() / ("sightline_atomic_" + std::string(test->name()) + "_" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
};

std::string contents(const fs::path& file)
{
    std::stringstream s;
    s << std::ifstream(file, std::ios::binary).rdbuf();
    return s.str();
}

mode_t modeOf(const fs::path& file)
{
    struct stat st {};
    EXPECT_EQ(::stat(file.c_str(), &st), 0) << file;
    return st.st_mode & 07777;
}

/// A pid that no process has: a child that has exited and been reaped.
pid_t deadPid()
{
    const pid_t child = ::fork();
    if (child == 0)
        ::_exit(0);
    int status = 0;
    ::waitpid(child, &status, 0);
    return child;
}

void age(const fs::path& file, std::chrono::minutes by)
{
    fs::last_write_time(file, fs::file_time_type::clock::now() - by);
}

} // namespace

TEST_F(AtomicSave, KeepsTheExistingFilesMode)
{
    const fs::path file = dir / "private.json";
    writeFileAtomically(file, "one");
    ASSERT_EQ(::chmod(file.c_str(), 0600), 0);
    writeFileAtomically(file, "two");
    EXPECT_EQ(contents(file), "two");
    EXPECT_EQ(modeOf(file), mode_t(0600));
}

TEST_F(AtomicSave, ANewFileGetsTheUmasksDefault)
{
    const mode_t old = ::umask(0);
    writeFileAtomically(dir / "open.json", "x");
    ::umask(027);
    writeFileAtomically(dir / "group.json", "x");
    ::umask(old);
    EXPECT_EQ(modeOf(dir / "open.json"), mode_t(0666));
    EXPECT_EQ(modeOf(dir / "group.json"), mode_t(0640));
}

TEST_F(AtomicSave, WritesThroughASymlinkAndKeepsIt)
{
    fs::create_directories(dir / "real");
    const fs::path target = dir / "real" / "project.json";
    writeFileAtomically(target, "old");
    const fs::path link = dir / "link.json";
    fs::create_symlink("real/project.json", link);   // relative, resolved from the link's folder
    writeFileAtomically(link, "new");
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
    EXPECT_EQ(fs::read_symlink(link), fs::path("real/project.json"));
    EXPECT_EQ(contents(target), "new");
    // The temporary lived beside the target, and nothing is left over.
    for (const auto& entry : fs::directory_iterator(dir / "real"))
        EXPECT_EQ(entry.path().filename(), "project.json");

    // A dangling link: the save creates its target.
    fs::create_symlink("real/later.json", dir / "later.json");
    writeFileAtomically(dir / "later.json", "made");
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "later.json")));
    EXPECT_EQ(contents(dir / "real" / "later.json"), "made");
}

TEST_F(AtomicSave, RemovesADeadWritersStaleTemporaryAndKeepsALiveOnes)
{
    const fs::path file = dir / "mask.npy";
    const fs::path dead = dir / atomicTempName(file, static_cast<unsigned long>(deadPid()), 1);
    const fs::path deadButFresh = dir / atomicTempName(file, static_cast<unsigned long>(deadPid()), 2);
    const fs::path live = dir / atomicTempName(file, static_cast<unsigned long>(::getpid()), 3);
    const fs::path otherFile = dir / atomicTempName(dir / "other.npy", static_cast<unsigned long>(deadPid()), 4);
    for (const fs::path& p : {dead, deadButFresh, live, otherFile})
        std::ofstream(p) << "partial";
    age(dead, std::chrono::minutes(60));
    age(live, std::chrono::minutes(60));
    age(otherFile, std::chrono::minutes(60));

    writeFileAtomically(file, "whole");
    EXPECT_EQ(contents(file), "whole");
    EXPECT_FALSE(fs::exists(dead)) << "a dead writer's old temporary is removed";
    EXPECT_TRUE(fs::exists(deadButFresh)) << "a recent one is kept (its pid may belong to another namespace)";
    EXPECT_TRUE(fs::exists(live)) << "a live writer's temporary is never removed";
    EXPECT_TRUE(fs::exists(otherFile)) << "only the saved file's own temporaries are considered";
}

TEST_F(AtomicSave, RemovesOldTemporariesWithoutAPidOnlyWhenOld)
{
    const fs::path file = dir / "p.json";
    const fs::path ancient = dir / ".p.json.tmp-123456789";   // the name before pids were recorded
    const fs::path recent = dir / ".p.json.tmp-987654321";
    std::ofstream(ancient) << "partial";
    std::ofstream(recent) << "partial";
    age(ancient, std::chrono::minutes(120));
    writeFileAtomically(file, "x");
    EXPECT_FALSE(fs::exists(ancient));
    EXPECT_TRUE(fs::exists(recent));
}

// Only names this writer makes are temporaries: a user's own ".p.json.tmp-notes" stays, however old.
TEST_F(AtomicSave, KeepsFilesThatOnlyLookLikeTemporaries)
{
    const fs::path file = dir / "p.json";
    const fs::path notes = dir / ".p.json.tmp-notes";
    const fs::path dashed = dir / (".p.json.tmp-" + std::to_string(deadPid()) + "-draft");
    std::ofstream(notes) << "mine";
    std::ofstream(dashed) << "mine";
    age(notes, std::chrono::minutes(600));
    age(dashed, std::chrono::minutes(600));
    writeFileAtomically(file, "x");
    EXPECT_TRUE(fs::exists(notes));
    EXPECT_TRUE(fs::exists(dashed));
}

TEST_F(AtomicSave, RefusesToReplaceAFolder)
{
    fs::create_directories(dir / "out.npy");
    try {
        writeFileAtomically(dir / "out.npy", "x");
        FAIL() << "a folder was replaced";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("is a folder"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_directory(dir / "out.npy"));
}
