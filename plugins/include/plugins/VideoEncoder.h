#pragma once
// Video files from rendered frames: H.264 in MP4, or VP9 (VP8 where VP9 is missing)
// in WebM, chosen by the file's extension, at a fixed frame rate. Built on Debian's libavcodec,
// libavformat and libswscale; no Qt, no GL: the caller renders, this only encodes.
//
// Saving never leaves a half file under the user's name: frames go to a temporary beside the
// target (the ".NAME.tmp-PID-NONCE" of base/AtomicFile.h), and finish() renames it over the
// target once the trailer is written. An encoder destroyed before finish() (an error, a cancelled
// recording) removes its temporary and leaves the target as it was. A target that is a symlink keeps
// the link: the file it names is replaced.
//
// Frame sizes are checked before anything is written: the 4:2:0 chroma of H.264 and VP9 halves
// both sides, so width and height must be even (callers that take a window's size round down, see
// evenVideoSize), from kMinVideoSide to kMaxVideoSide, and at most an 8K frame in area (H.264
// level 6.2's largest frame).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace sightline {

inline constexpr int kMinVideoSide = 16;
inline constexpr int kMaxVideoSide = 8192;
inline constexpr long long kMaxVideoPixels = 8192LL * 4320LL;
inline constexpr double kMaxVideoFps = 240.0;

/// The container and codec a file's extension asks for.
struct VideoFormat {
    std::string container;   ///< libavformat's muxer name: "mp4" or "webm"
    std::string codec;       ///< "h264", "vp9" or "vp8"
    std::string encoder;     ///< the libavcodec encoder used, e.g. "libx264", "libvpx-vp9"
};

/// ".mp4" or ".m4v": H.264 in MP4; ".webm": VP9 (VP8 where this libavcodec lacks VP9) in WebM.
/// Case-insensitive.
/// Throws sightline::Error for another extension ("video 'x.avi': unknown extension '.avi'; use
/// .mp4 (H.264) or .webm (VP9)") or when this libavcodec has no encoder for it.
VideoFormat videoFormatFor(const std::filesystem::path& file);

struct VideoSettings {
    int width = 1280;
    int height = 720;
    double fps = 30.0;   ///< frames per second, in (0, kMaxVideoFps]; stored as a rational
    /// Constant quality: x264's CRF (0-51, lower is better; 20 looks clean on thin rays) and its
    /// counterpart for libvpx (mapped to its 0-63 scale).
    int quality = 20;
};

/// Throws sightline::Error with one line when a size or rate cannot be encoded (odd sides, too
/// small, too large, a non-positive or excessive rate).
void checkVideoSettings(const VideoSettings& settings);

/// The largest even size not above (width, height), at least kMinVideoSide a side: what a window
/// of any size records at.
std::pair<int, int> evenVideoSize(int width, int height);

class VideoEncoder {
public:
    /// Opens the temporary file and the encoder. Throws sightline::Error: an unknown extension,
    /// bad settings, a folder that does not exist or cannot be written, a target that is a folder.
    VideoEncoder(const std::filesystem::path& file, const VideoSettings& settings);
    /// Without finish(): the temporary is removed, the target untouched.
    ~VideoEncoder();
    VideoEncoder(const VideoEncoder&) = delete;
    VideoEncoder& operator=(const VideoEncoder&) = delete;

    /// Adds one frame of width x height RGBA8 pixels whose rows lie `stride` bytes apart. With
    /// `bottomUp` the first row in memory is the image's bottom row (an OpenGL read-back), flipped
    /// while converting at no extra cost. Frame k is shown at time k / fps.
    void addFrame(const std::uint8_t* rgba, std::ptrdiff_t stride, bool bottomUp = false);
    /// Drains the encoder, writes the trailer and renames the temporary over the target. Throws
    /// sightline::Error (a full disk, say); the target is then untouched.
    void finish();

    int frames() const;
    const VideoFormat& format() const;
    const std::filesystem::path& file() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace sightline
