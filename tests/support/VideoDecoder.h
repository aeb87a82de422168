#pragma once
// Decodes a video file with libavformat/libavcodec for the recording tests: every frame as RGB
// (3 bytes a pixel, top row first), with the stream's codec, size and frame rate. An independent
// reader of what plugins/VideoEncoder.h wrote: it shares no code with the encoder.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

namespace sightline::test {

struct DecodedVideo {
    std::string container;   ///< libavformat's demuxer name, e.g. "mov,mp4,m4a,3gp,3g2,mj2"
    std::string codec;       ///< "h264", "vp9"
    int width = 0, height = 0;
    double fps = 0.0;        ///< the stream's average frame rate
    std::vector<std::vector<std::uint8_t>> frames;   ///< RGB24, width * height * 3 each

    /// Pixel (x, y) of frame f, channel c (0 R, 1 G, 2 B).
    int at(std::size_t f, int x, int y, int c) const { return frames[f][(std::size_t(y) * width + x) * 3 + c]; }
};

/// Throws std::runtime_error when the file cannot be read as a video.
inline DecodedVideo decodeVideo(const std::string& file)
{
    DecodedVideo video;
    AVFormatContext* input = nullptr;
    if (avformat_open_input(&input, file.c_str(), nullptr, nullptr) < 0)
        throw std::runtime_error("cannot open " + file);
    struct Closer {
        AVFormatContext*& input;
        AVCodecContext* codec = nullptr;
        AVFrame* frame = nullptr;
        AVPacket* packet = nullptr;
        SwsContext* scaler = nullptr;
        ~Closer()
        {
            sws_freeContext(scaler);
            av_packet_free(&packet);
            av_frame_free(&frame);
            avcodec_free_context(&codec);
            avformat_close_input(&input);
        }
    } closer{input};
    if (avformat_find_stream_info(input, nullptr) < 0)
        throw std::runtime_error("no stream info in " + file);
    const int stream = av_find_best_stream(input, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
    if (stream < 0)
        throw std::runtime_error("no video stream in " + file);
    const AVStream* s = input->streams[stream];
    const AVCodec* decoder = avcodec_find_decoder(s->codecpar->codec_id);
    if (!decoder)
        throw std::runtime_error("no decoder for " + file);
    closer.codec = avcodec_alloc_context3(decoder);
    avcodec_parameters_to_context(closer.codec, s->codecpar);
    if (avcodec_open2(closer.codec, decoder, nullptr) < 0)
        throw std::runtime_error("cannot open the decoder for " + file);
    video.container = input->iformat->name;
    video.codec = avcodec_get_name(s->codecpar->codec_id);
    video.width = s->codecpar->width;
    video.height = s->codecpar->height;
    video.fps = av_q2d(s->avg_frame_rate);
    closer.frame = av_frame_alloc();
    closer.packet = av_packet_alloc();

    auto drain = [&] {
        while (avcodec_receive_frame(closer.codec, closer.frame) == 0) {
            const AVFrame* f = closer.frame;
            closer.scaler = sws_getCachedContext(closer.scaler, f->width, f->height, AVPixelFormat(f->format), f->width,
                                                 f->height, AV_PIX_FMT_RGB24, SWS_BILINEAR, nullptr, nullptr, nullptr);
            std::vector<std::uint8_t> rgb(std::size_t(f->width) * f->height * 3);
            std::uint8_t* planes[1] = {rgb.data()};
            const int strides[1] = {f->width * 3};
            sws_scale(closer.scaler, f->data, f->linesize, 0, f->height, planes, strides);
            video.frames.push_back(std::move(rgb));
        }
    };
    while (av_read_frame(input, closer.packet) >= 0) {
        if (closer.packet->stream_index == stream)
            avcodec_send_packet(closer.codec, closer.packet);
        av_packet_unref(closer.packet);
        drain();
    }
    avcodec_send_packet(closer.codec, nullptr);
    drain();
    return video;
}

} // namespace sightline::test
