// The video encoder (plugins/VideoEncoder.h): files decoded again with libavformat (an
// independent reader) have the frames, size, rate and codec asked for, and each frame shows what
// was encoded (a square at a known place); bad names, sizes, rates and folders give one-line
// errors before anything is written, and a file is never left half written under its name.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <unistd.h>

#include "VideoDecoder.h"
#include "plugins/VideoEncoder.h"
#include "base/Error.h"

namespace sightline {
namespace {

namespace fs = std::filesystem;

fs::path freshFolder(const std::string& name)
{
    const fs::path folder = fs::temp_directory_path() / ("sightline-video-" + name + "-" + std::to_string(getpid()));
    fs::remove_all(folder);
    fs::create_directories(folder);
    return folder;
}

/// RGBA frame k: black, with a white 8x8 square whose top-left corner is at (4 + 3k, 6 + k).
std::vector<std::uint8_t> squareFrame(int width, int height, int k, bool bottomUp)
{
    std::vector<std::uint8_t> rgba(std::size_t(width) * height * 4, 0);
    for (int y = 6 + k; y < 14 + k; ++y)
        for (int x = 4 + 3 * k; x < 12 + 3 * k; ++x) {
            const int row = bottomUp ? height - 1 - y : y;
            std::uint8_t* p = &rgba[(std::size_t(row) * width + x) * 4];
            p[0] = p[1] = p[2] = p[3] = 255;
        }
    return rgba;
}

/// The centre of the bright pixels of a decoded frame.
std::pair<double, double> brightCentre(const test::DecodedVideo& video, std::size_t f)
{
    double sx = 0, sy = 0, n = 0;
    for (int y = 0; y < video.height; ++y)
        for (int x = 0; x < video.width; ++x)
            if (video.at(f, x, y, 1) > 128) {
                sx += x;
                sy += y;
                ++n;
            }
    return {n ? sx / n : -1.0, n ? sy / n : -1.0};
}

void expectSquaresWhereEncoded(const test::DecodedVideo& video, int frames)
{
    ASSERT_EQ(int(video.frames.size()), frames);
    for (int k = 0; k < frames; ++k) {
        const auto [x, y] = brightCentre(video, std::size_t(k));
        EXPECT_NEAR(x, 7.5 + 3 * k, 0.75) << "frame " << k;
        EXPECT_NEAR(y, 9.5 + k, 0.75) << "frame " << k;
    }
}

TEST(VideoEncoder, WritesH264InMp4WithEveryFrameWhereItWasDrawn)
{
    const fs::path file = freshFolder("mp4") / "squares.mp4";
    VideoSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.fps = 25.0;
    VideoEncoder encoder(file, settings);
    EXPECT_EQ(encoder.format().codec, "h264");
    for (int k = 0; k < 12; ++k)
        encoder.addFrame(squareFrame(64, 48, k, false).data(), 64 * 4);
    EXPECT_FALSE(fs::exists(file)) << "the file appears only when finished";
    encoder.finish();
    EXPECT_EQ(encoder.frames(), 12);

    const test::DecodedVideo video = test::decodeVideo(file.string());
    EXPECT_NE(video.container.find("mp4"), std::string::npos);
    EXPECT_EQ(video.codec, "h264");
    EXPECT_EQ(video.width, 64);
    EXPECT_EQ(video.height, 48);
    EXPECT_NEAR(video.fps, 25.0, 1e-9);
    expectSquaresWhereEncoded(video, 12);
    // Nothing else beside it: the temporary was renamed, not copied.
    EXPECT_EQ(std::distance(fs::directory_iterator(file.parent_path()), fs::directory_iterator()), 1);
}

TEST(VideoEncoder, WritesVp9InWebmAndFlipsBottomUpRows)
{
    const fs::path file = freshFolder("webm") / "squares.WEBM";   // the extension in any case
    VideoSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.fps = 12.5;
    VideoEncoder encoder(file, settings);
    for (int k = 0; k < 8; ++k)
        encoder.addFrame(squareFrame(64, 48, k, true).data(), 64 * 4, /*bottomUp=*/true);
    encoder.finish();
    const test::DecodedVideo video = test::decodeVideo(file.string());
    EXPECT_NE(video.container.find("webm"), std::string::npos);
    EXPECT_EQ(video.codec, "vp9");
    EXPECT_NEAR(video.fps, 12.5, 1e-9);
    expectSquaresWhereEncoded(video, 8);
}

std::string errorOf(const fs::path& file, const VideoSettings& settings)
{
    try {
        VideoEncoder encoder(file, settings);
    } catch (const Error& e) {
        return e.what();
    }
    return {};
}

TEST(VideoEncoder, RefusesBadNamesSizesRatesAndFoldersInOneLine)
{
    const fs::path folder = freshFolder("bad");
    VideoSettings ok;
    ok.width = 64;
    ok.height = 48;
    auto with = [&](int w, int h, double fps) {
        VideoSettings s = ok;
        s.width = w;
        s.height = h;
        s.fps = fps;
        return s;
    };
    struct Case {
        fs::path file;
        VideoSettings settings;
        std::string says;
    };
    const Case cases[] = {
        {folder / "clip.avi", ok, "unknown extension '.avi'; use .mp4 (H.264) or .webm (VP9)"},
        {folder / "clip", ok, "no extension; use .mp4"},
        {folder / "clip.mp4", with(65, 48, 30), "odd side: 4:2:0 video needs an even width and height (try 64x48)"},
        {folder / "clip.mp4", with(8, 48, 30), "too small"},
        {folder / "clip.mp4", with(16384, 720, 30), "too large"},
        {folder / "clip.mp4", with(8192, 8192, 30), "too large"},
        {folder / "clip.mp4", with(64, 48, 0.0), "frame rate"},
        {folder / "clip.mp4", with(64, 48, 1000.0), "frame rate"},
        {folder / "missing" / "clip.mp4", ok, "does not exist"},
        {fs::path("/proc") / "clip.mp4", ok, "cannot write in '/proc'"},
        {folder, ok, "no extension"},
    };
    for (const Case& c : cases) {
        const std::string error = errorOf(c.file, c.settings);
        EXPECT_NE(error.find(c.says), std::string::npos) << c.file << ": " << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    }
    fs::create_directories(folder / "dir.mp4");
    EXPECT_NE(errorOf(folder / "dir.mp4", ok).find("is a folder"), std::string::npos);
    // Nothing was written by any refusal.
    EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);
    EXPECT_EQ(evenVideoSize(1281, 721), std::make_pair(1280, 720));
    EXPECT_EQ(evenVideoSize(3, 5), std::make_pair(kMinVideoSide, kMinVideoSide));
}

TEST(VideoEncoder, AnUnfinishedRecordingLeavesTheOldFileAndNoTemporary)
{
    const fs::path folder = freshFolder("atomic");
    const fs::path file = folder / "clip.mp4";
    std::ofstream(file) << "the user's old video";
    {
        VideoSettings settings;
        settings.width = 32;
        settings.height = 32;
        VideoEncoder encoder(file, settings);
        for (int k = 0; k < 3; ++k)
            encoder.addFrame(squareFrame(32, 32, k, false).data(), 32 * 4);
        // Destroyed without finish(): a cancelled or failed recording.
    }
    std::stringstream text;
    text << std::ifstream(file).rdbuf();
    EXPECT_EQ(text.str(), "the user's old video");
    EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);
}

TEST(VideoEncoder, SavingThroughASymlinkReplacesItsTargetAndKeepsTheLink)
{
    const fs::path folder = freshFolder("symlink");
    fs::create_directories(folder / "videos");
    std::ofstream(folder / "videos" / "take.mp4") << "old";
    fs::create_symlink("videos/take.mp4", folder / "latest.mp4");
    VideoSettings settings;
    settings.width = 32;
    settings.height = 32;
    VideoEncoder encoder(folder / "latest.mp4", settings);
    for (int k = 0; k < 2; ++k)
        encoder.addFrame(squareFrame(32, 32, k, false).data(), 32 * 4);
    encoder.finish();
    EXPECT_TRUE(fs::is_symlink(folder / "latest.mp4"));
    EXPECT_EQ(test::decodeVideo((folder / "videos" / "take.mp4").string()).frames.size(), 2u);
}

} // namespace
} // namespace sightline
