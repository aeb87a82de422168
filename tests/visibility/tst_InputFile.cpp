#include <fstream>

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/Error.h"
#include "base/InputFile.h"

using namespace sightline;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name)
{
    const fs::path dir = fs::temp_directory_path() / ("sightline_inputfile_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir / name;
}

std::string messageOf(const fs::path& path, std::uintmax_t limit = kMaxInputFileBytes)
{
    try {
        readInputFile(path, "scene", limit);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(InputFile, ReadsARegularFileWhole)
{
    const fs::path file = scratch("ok.obj");
    std::ofstream(file, std::ios::binary) << "v 0 0 0\n";
    EXPECT_EQ(readInputFile(file, "scene"), "v 0 0 0\n");
}

TEST(InputFile, RefusesWhatIsNotARegularFileBeforeReading)
{
    const fs::path fifo = scratch("pipe.glb");
    fs::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_NE(messageOf(fifo).find("FIFO"), std::string::npos);   // would block forever if opened
    EXPECT_NE(messageOf(scratch("")).find("a folder"), std::string::npos);
    EXPECT_NE(messageOf("/dev/zero").find("character device"), std::string::npos);
    const fs::path link = scratch("random.stl");
    fs::remove(link);
    fs::create_symlink("/dev/urandom", link);
    EXPECT_NE(messageOf(link).find("character device"), std::string::npos);
    EXPECT_NE(messageOf(scratch("missing.ply")).find("not found"), std::string::npos);
}

TEST(InputFile, RefusesAFileOverTheLimitWithoutAllocatingIt)
{
    const fs::path file = scratch("sparse.glb");
    { std::ofstream(file, std::ios::binary).put('x'); }
    fs::resize_file(file, kMaxInputFileBytes + 1);   // sparse: no disk used
    const std::string message = messageOf(file);
    EXPECT_NE(message.find("more than the limit of 1024 MB"), std::string::npos) << message;
    EXPECT_NE(message.find("sparse.glb"), std::string::npos);
    fs::remove(file);
}
