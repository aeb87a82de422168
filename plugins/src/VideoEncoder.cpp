#include "plugins/VideoEncoder.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <mutex>
#include <random>
#include <system_error>

#include <unistd.h>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/error.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include "base/AtomicFile.h"
#include "base/Error.h"

namespace sightline {

namespace fs = std::filesystem;

namespace {

std::string avError(int code)
{
    char text[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, text, sizeof text);
    return text;
}

std::string lowerExtension(const fs::path& file)
{
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

} // namespace

VideoFormat videoFormatFor(const fs::path& file)
{
    const std::string ext = lowerExtension(file);
    VideoFormat format;
    if (ext == ".mp4" || ext == ".m4v") {
        format = {"mp4", "h264", ""};
        // libx264 where Debian's libavcodec has it (it does); else any H.264 encoder it offers.
        const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
        if (!codec)
            codec = avcodec_find_encoder(AV_CODEC_ID_H264);
        if (!codec)
            throw Error("video '" + file.string() + "': this libavcodec has no H.264 encoder; record to .webm instead");
        format.encoder = codec->name;
    } else if (ext == ".webm") {
        if (const AVCodec* vp9 = avcodec_find_encoder_by_name("libvpx-vp9"))
            format = {"webm", "vp9", vp9->name};
        else if (const AVCodec* vp8 = avcodec_find_encoder_by_name("libvpx"))
            format = {"webm", "vp8", vp8->name};
        else
            throw Error("video '" + file.string() + "': this libavcodec has no VP9 or VP8 encoder; record to .mp4 instead");
    } else if (ext.empty()) {
        throw Error("video '" + file.string() + "': no extension; use .mp4 (H.264) or .webm (VP9)");
    } else {
        throw Error("video '" + file.string() + "': unknown extension '" + ext + "'; use .mp4 (H.264) or .webm (VP9)");
    }
    return format;
}

void checkVideoSettings(const VideoSettings& s)
{
    const std::string size = std::to_string(s.width) + "x" + std::to_string(s.height);
    if (s.width < kMinVideoSide || s.height < kMinVideoSide)
        throw Error("video size " + size + " is too small: each side must be at least " + std::to_string(kMinVideoSide));
    if (s.width > kMaxVideoSide || s.height > kMaxVideoSide || (long long)s.width * s.height > kMaxVideoPixels)
        throw Error("video size " + size + " is too large: at most " + std::to_string(kMaxVideoSide) +
                    " a side and 8192x4320 pixels in all");
    if (s.width % 2 != 0 || s.height % 2 != 0) {
        const auto [w, h] = evenVideoSize(s.width, s.height);
        throw Error("video size " + size + " has an odd side: 4:2:0 video needs an even width and height (try " +
                    std::to_string(w) + "x" + std::to_string(h) + ")");
    }
    if (!(s.fps > 0.0) || !(s.fps <= kMaxVideoFps))
        throw Error("video frame rate must be in (0, " + std::to_string(int(kMaxVideoFps)) + "] frames per second");
    if (s.quality < 0 || s.quality > 51)
        throw Error("video quality must be in [0, 51] (lower is better)");
}

std::pair<int, int> evenVideoSize(int width, int height)
{
    return {std::max(kMinVideoSide, width & ~1), std::max(kMinVideoSide, height & ~1)};
}

struct VideoEncoder::Impl {
    fs::path target;        ///< the name the user gave (messages)
    fs::path replaced;      ///< the file the rename replaces: a symlink's target, so the link stays
    fs::path temp;
    fs::path folder;        ///< where the temporary and the video go
    VideoFormat format;
    VideoSettings settings;
    AVFormatContext* muxer = nullptr;
    AVCodecContext* codec = nullptr;
    AVStream* stream = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* packet = nullptr;
    SwsContext* scaler = nullptr;
    int frames = 0;
    bool finished = false;

    ~Impl()
    {
        sws_freeContext(scaler);
        av_packet_free(&packet);
        av_frame_free(&frame);
        avcodec_free_context(&codec);
        if (muxer) {
            if (muxer->pb)
                avio_closep(&muxer->pb);
            avformat_free_context(muxer);
        }
        if (!finished && !temp.empty()) {
            std::error_code ec;
            fs::remove(temp, ec);
        }
    }

    [[noreturn]] void fail(const std::string& doing, int code) const
    {
        throw Error("video '" + target.string() + "': " + doing + ": " + avError(code));
    }

    /// The temporary file beside the target (so the final rename stays on one file system), and the
    /// file the rename replaces: through a symlink, the file it names, keeping the link (as every
    /// save does, base/AtomicFile.h).
    void placeTemporary()
    {
        const fs::path& file = target;
        std::error_code ec;
        if (fs::is_directory(file, ec))
            throw Error("video '" + file.string() + "': is a folder");
        std::error_code linkError;
        const bool link = fs::is_symlink(fs::symlink_status(file, ec));   // ec set for a file not there yet
        replaced = link ? fs::weakly_canonical(file, linkError) : file;
        if (linkError)
            throw Error("video '" + file.string() + "': cannot follow the symlink (" + linkError.message() + ")");
        folder = replaced.has_parent_path() ? replaced.parent_path() : fs::path(".");
        if (!fs::is_directory(folder, ec))
            throw Error("video '" + file.string() + "': the folder '" + folder.string() + "' does not exist");
        temp = folder / atomicTempName(replaced, static_cast<unsigned long>(getpid()), static_cast<unsigned long>(std::random_device{}()));
    }

    /// The muxer, the stream and the encoder, opened with the settings' size, rate and quality.
    void openEncoder()
    {
        // libav's own log lines would break the one-line error rule; its errors reach the user through
        // av_strerror in our messages instead.
        static std::once_flag quiet;
        std::call_once(quiet, [] { av_log_set_level(AV_LOG_QUIET); });
        // The muxer is named, not guessed from the temporary's name; the url lets MP4's faststart
        // pass reopen the file.
        int rc = avformat_alloc_output_context2(&muxer, nullptr, format.container.c_str(), temp.c_str());
        if (rc < 0 || !muxer)
            fail("no " + format.container + " muxer", rc);
        const AVCodec* encoder = avcodec_find_encoder_by_name(format.encoder.c_str());
        stream = avformat_new_stream(muxer, nullptr);
        codec = avcodec_alloc_context3(encoder);
        frame = av_frame_alloc();
        packet = av_packet_alloc();
        if (!stream || !codec || !frame || !packet)
            throw Error("video '" + target.string() + "': out of memory");

        // A fixed rate: frame k at k / fps exactly (a rational time base, not rounded milliseconds).
        const AVRational rate = av_d2q(settings.fps, 100000);
        AVCodecContext* c = codec;
        c->width = settings.width;
        c->height = settings.height;
        c->pix_fmt = AV_PIX_FMT_YUV420P;   // what players decode everywhere
        c->time_base = av_inv_q(rate);
        c->framerate = rate;
        c->gop_size = std::max(1, int(std::lround(2.0 * settings.fps)));   // a key frame every 2 s, for seeking
        // Rendered images are full-range RGB; tag the video as BT.709, which the conversion below uses.
        c->colorspace = AVCOL_SPC_BT709;
        c->color_primaries = AVCOL_PRI_BT709;
        c->color_trc = AVCOL_TRC_BT709;
        c->color_range = AVCOL_RANGE_MPEG;
        if (muxer->oformat->flags & AVFMT_GLOBALHEADER)
            c->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
        AVDictionary* options = encoderOptions();
        rc = avcodec_open2(c, encoder, &options);
        av_dict_free(&options);
        if (rc < 0)
            fail("cannot open the " + format.encoder + " encoder", rc);
        rc = avcodec_parameters_from_context(stream->codecpar, c);
        if (rc < 0)
            fail("stream parameters", rc);
        stream->time_base = c->time_base;
        stream->avg_frame_rate = rate;
    }

    /// The encoder's quality and speed options (sets the codec's bit rate where libvpx needs one).
    AVDictionary* encoderOptions()
    {
        AVDictionary* options = nullptr;
        if (format.codec == "h264") {
            av_dict_set(&options, "preset", "veryfast", 0);   // 2 cores: encoding must not dominate rendering
            av_dict_set(&options, "crf", std::to_string(settings.quality).c_str(), 0);
            return options;
        }
        // libvpx: constant quality on its 0-63 scale, realtime speed.
        const int crf = std::clamp(int(std::lround(settings.quality * 63.0 / 51.0)) + 10, 4, 63);
        codec->bit_rate = 0;
        av_dict_set(&options, "crf", std::to_string(crf).c_str(), 0);
        av_dict_set(&options, "deadline", "realtime", 0);
        av_dict_set(&options, "cpu-used", "8", 0);
        if (format.codec == "vp9")
            av_dict_set(&options, "row-mt", "1", 0);
        else
            codec->bit_rate = (long long)settings.width * settings.height * 4;   // VP8 needs a ceiling with crf
        return options;
    }

    /// The temporary file opened and the container's header written.
    void openOutput()
    {
        int rc = avio_open(&muxer->pb, temp.c_str(), AVIO_FLAG_WRITE);
        if (rc < 0) {
            temp.clear();   // nothing was created
            throw Error("video '" + target.string() + "': cannot write in '" + folder.string() + "': " + avError(rc));
        }
        AVDictionary* muxOptions = nullptr;
        if (format.container == "mp4")
            av_dict_set(&muxOptions, "movflags", "+faststart", 0);   // index first: plays while downloading
        rc = avformat_write_header(muxer, &muxOptions);
        av_dict_free(&muxOptions);
        if (rc < 0)
            fail("writing the header", rc);
    }

    /// The frame the images are converted into, and the conversion: RGB full range in, BT.709
    /// limited range out (the tags openEncoder sets).
    void prepareFrames()
    {
        frame->format = codec->pix_fmt;
        frame->width = codec->width;
        frame->height = codec->height;
        const int rc = av_frame_get_buffer(frame, 0);
        if (rc < 0)
            fail("frame buffer", rc);
        scaler = sws_getContext(codec->width, codec->height, AV_PIX_FMT_RGBA, codec->width, codec->height, AV_PIX_FMT_YUV420P,
                                SWS_BILINEAR, nullptr, nullptr, nullptr);
        if (!scaler)
            throw Error("video '" + target.string() + "': no RGBA to YUV 4:2:0 conversion");
        const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
        sws_setColorspaceDetails(scaler, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);
    }

    /// Sends `input` (nullptr drains) and writes every packet the encoder has ready.
    void encode(const AVFrame* input)
    {
        int rc = avcodec_send_frame(codec, input);
        if (rc < 0)
            fail("encoding frame " + std::to_string(frames), rc);
        for (;;) {
            rc = avcodec_receive_packet(codec, packet);
            if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF)
                return;
            if (rc < 0)
                fail("encoding", rc);
            av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
            packet->stream_index = stream->index;
            rc = av_interleaved_write_frame(muxer, packet);   // takes the packet's data
            if (rc < 0)
                fail("writing", rc);
        }
    }
};

VideoEncoder::VideoEncoder(const fs::path& file, const VideoSettings& settings) : impl_(std::make_unique<Impl>())
{
    Impl& m = *impl_;
    m.target = file;
    m.settings = settings;
    m.format = videoFormatFor(file);
    checkVideoSettings(settings);
    m.placeTemporary();
    m.openEncoder();
    m.openOutput();
    m.prepareFrames();
}

VideoEncoder::~VideoEncoder() = default;

void VideoEncoder::addFrame(const std::uint8_t* rgba, std::ptrdiff_t stride, bool bottomUp)
{
    Impl& m = *impl_;
    if (m.finished)
        throw Error("video '" + m.target.string() + "': frame added after finish()");
    int rc = av_frame_make_writable(m.frame);
    if (rc < 0)
        m.fail("frame buffer", rc);
    const std::uint8_t* first = bottomUp ? rgba + (m.settings.height - 1) * stride : rgba;
    const int lineStride = int(bottomUp ? -stride : stride);
    const std::uint8_t* const planes[1] = {first};
    const int strides[1] = {lineStride};
    sws_scale(m.scaler, planes, strides, 0, m.settings.height, m.frame->data, m.frame->linesize);
    m.frame->pts = m.frames;
    m.encode(m.frame);
    ++m.frames;
}

void VideoEncoder::finish()
{
    Impl& m = *impl_;
    if (m.finished)
        return;
    m.encode(nullptr);
    int rc = av_write_trailer(m.muxer);
    if (rc < 0)
        m.fail("writing the trailer", rc);
    rc = avio_closep(&m.muxer->pb);
    if (rc < 0)
        m.fail("closing", rc);
    std::error_code ec;
    fs::rename(m.temp, m.replaced, ec);
    if (ec)
        throw Error("video '" + m.target.string() + "': cannot replace it: " + ec.message());
    m.finished = true;
}

int VideoEncoder::frames() const { return impl_->frames; }
const VideoFormat& VideoEncoder::format() const { return impl_->format; }
const fs::path& VideoEncoder::file() const { return impl_->target; }

} // namespace sightline
