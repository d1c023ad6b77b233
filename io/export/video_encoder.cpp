#include "io/export/video_encoder.h"

#include "io/export/vertex_cache_internal.h"
#include "io/files/atomic_file.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <system_error>

namespace softtouch::io {
namespace {

std::string avError(int code) {
    char text[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, text, sizeof(text));
    return text;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

/// The GIF palette: 6 x 7 x 6 levels of R, G, B (252 colours) plus 4 extra greys. A fixed palette keeps
/// encoding streaming (no pass over all frames) and ordered dithering hides the banding.
constexpr int kLevelsR = 6, kLevelsG = 7, kLevelsB = 6;

std::array<std::uint32_t, 256> gifPalette() {
    std::array<std::uint32_t, 256> palette{};
    int i = 0;
    for (int r = 0; r < kLevelsR; ++r)
        for (int g = 0; g < kLevelsG; ++g)
            for (int b = 0; b < kLevelsB; ++b) {
                const std::uint32_t R = std::uint32_t(r * 255 / (kLevelsR - 1));
                const std::uint32_t G = std::uint32_t(g * 255 / (kLevelsG - 1));
                const std::uint32_t B = std::uint32_t(b * 255 / (kLevelsB - 1));
                palette[std::size_t(i++)] = 0xFF000000u | (R << 16) | (G << 8) | B;  // PAL8: native ARGB
            }
    for (std::uint32_t grey : {64u, 96u, 160u, 192u})
        palette[std::size_t(i++)] = 0xFF000000u | (grey << 16) | (grey << 8) | grey;
    return palette;
}

/// Quantises one channel to `levels` with a 4x4 Bayer threshold in [0,1).
int quantise(int value, int levels, float threshold) {
    const float scaled = float(value) * float(levels - 1) / 255.0f;
    return std::min(levels - 1, int(scaled + threshold));
}

}  // namespace

std::optional<VideoFormat> videoFormatFromPath(const std::filesystem::path& path) {
    const std::string text = path.string();
    std::error_code ignored;
    if (!text.empty() && (text.back() == '/' || std::filesystem::is_directory(path, ignored)))
        return VideoFormat::PngSequence;
    const std::string extension = lower(path.extension().string());
    if (extension == ".mp4")
        return VideoFormat::Mp4;
    if (extension == ".gif")
        return VideoFormat::Gif;
    return std::nullopt;
}

std::filesystem::path pngSequenceFramePath(const std::filesystem::path& directory, int index) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%04d.png", index);
    return directory / name;
}

struct VideoEncoder::Impl {
    VideoSettings settings;
    std::filesystem::path target;      ///< Final file (MP4, GIF) or directory (PNG).
    std::filesystem::path temporary;   ///< MP4/GIF: the file being written.
    std::vector<std::pair<std::filesystem::path, std::filesystem::path>> stagedPngs; ///< (temporary, final).
    bool createdDirectory = false;     ///< PNG: we made the directory (removed again on abort).
    AVFormatContext* format = nullptr;
    AVStream* stream = nullptr;
    AVCodecContext* codec = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* packet = nullptr;
    SwsContext* scaler = nullptr;
    std::array<std::uint32_t, 256> palette{};
    std::string codecName;
    std::vector<std::string> warnings;
    int frames = 0;
    bool finished = false;
    bool headerWritten = false;  ///< The muxer then owns buffered packets that only its trailer frees.

    Status error(const std::string& what) const {
        return Status::error("cannot write " + detail::quoted(target) + " (" + (codecName.empty() ? "video" : codecName) +
                             "): " + what);
    }

    void freeCodec() {
        sws_freeContext(scaler);
        scaler = nullptr;
        av_frame_free(&frame);
        av_packet_free(&packet);
        avcodec_free_context(&codec);
        if (format != nullptr) {
            if (headerWritten)
                av_write_trailer(format);  // into the temporary that discard() removes; frees the muxer's packets
            headerWritten = false;
            if (format->pb != nullptr)
                avio_closep(&format->pb);
            avformat_free_context(format);
            format = nullptr;
        }
    }

    void discard() {
        freeCodec();
        std::error_code ignored;
        if (!temporary.empty()) {
            std::filesystem::remove(temporary, ignored);
            detail::forgetTemporary(temporary);
        }
        temporary.clear();
        for (const auto& staged : stagedPngs) {
            std::filesystem::remove(staged.first, ignored);
            detail::forgetTemporary(staged.first);
        }
        stagedPngs.clear();
        if (createdDirectory)
            std::filesystem::remove(target, ignored);  // only when still empty
        createdDirectory = false;
    }

    /// Sends a frame (or nullptr to flush) and writes every packet that comes out.
    Status encode(AVFrame* input) {
        if (const int sent = avcodec_send_frame(codec, input); sent < 0)
            return error("the encoder refused a frame: " + avError(sent));
        for (;;) {
            const int received = avcodec_receive_packet(codec, packet);
            if (received == AVERROR(EAGAIN) || received == AVERROR_EOF)
                return Status::success();
            if (received < 0)
                return error("encoding failed: " + avError(received));
            Status written = writePacket();
            av_packet_unref(packet);
            if (!written)
                return written;
        }
    }

    Status writePacket() {
        if (settings.format == VideoFormat::PngSequence) {
            const int index = int(stagedPngs.size());
            const std::filesystem::path final = pngSequenceFramePath(target, index);
            const std::filesystem::path staged = detail::temporaryPathFor(final);
            std::FILE* file = std::fopen(staged.c_str(), "wb");
            if (file == nullptr)
                return Status::error("cannot write " + detail::quoted(final) + " (png): " + std::strerror(errno));
            stagedPngs.emplace_back(staged, final);
            const bool ok = std::fwrite(packet->data, 1, std::size_t(packet->size), file) == std::size_t(packet->size);
            if (std::fclose(file) != 0 || !ok)
                return Status::error("cannot write " + detail::quoted(final) + " (png): " + std::strerror(errno));
            return Status::success();
        }
        av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
        packet->stream_index = stream->index;
        if (const int written = av_interleaved_write_frame(format, packet); written < 0)
            return error("the muxer failed: " + avError(written));
        return Status::success();
    }

    Status openCodec(const AVCodec* encoder, AVPixelFormat pixelFormat) {
        codecName = encoder->name;
        codec = avcodec_alloc_context3(encoder);
        const AVRational rate = av_d2q(settings.fps, 100000);
        codec->width = settings.width;
        codec->height = settings.height;
        codec->pix_fmt = pixelFormat;
        codec->time_base = AVRational{rate.den, rate.num};
        codec->framerate = rate;
        if (settings.format == VideoFormat::Mp4) {
            codec->gop_size = std::max(1, int(std::lround(settings.fps)) * 2);
            if (codecName == "libx264") {
                av_opt_set(codec->priv_data, "crf", std::to_string(settings.crf).c_str(), 0);
                av_opt_set(codec->priv_data, "preset", "medium", 0);
            } else {
                // MPEG-4 Part 2 has no CRF; a fixed quantiser in 2..31 plays the same role.
                codec->flags |= AV_CODEC_FLAG_QSCALE;
                codec->global_quality = FF_QP2LAMBDA * (2 + settings.crf * 29 / 51);
            }
        }
        if (format != nullptr && (format->oformat->flags & AVFMT_GLOBALHEADER))
            codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
        if (const int opened = avcodec_open2(codec, encoder, nullptr); opened < 0)
            return error("cannot open the encoder: " + avError(opened));
        frame = av_frame_alloc();
        packet = av_packet_alloc();
        frame->format = pixelFormat;
        frame->width = settings.width;
        frame->height = settings.height;
        if (const int allocated = av_frame_get_buffer(frame, 0); allocated < 0)
            return error("cannot allocate a frame: " + avError(allocated));
        return Status::success();
    }

    Status openContainer(const char* muxer) {
        if (const int made = avformat_alloc_output_context2(&format, nullptr, muxer, temporary.c_str()); made < 0 || !format)
            return error(std::string("libavformat has no ") + muxer + " muxer: " + avError(made));
        return Status::success();
    }

    Status startContainer() {
        stream = avformat_new_stream(format, nullptr);
        if (stream == nullptr)
            return error("cannot add a video stream");
        stream->time_base = codec->time_base;
        stream->avg_frame_rate = codec->framerate;
        if (const int copied = avcodec_parameters_from_context(stream->codecpar, codec); copied < 0)
            return error("cannot set the stream parameters: " + avError(copied));
        if (const int opened = avio_open(&format->pb, temporary.c_str(), AVIO_FLAG_WRITE); opened < 0)
            return error("cannot create " + detail::quoted(temporary) + ": " + avError(opened));
        if (const int header = avformat_write_header(format, nullptr); header < 0)
            return error("cannot write the header: " + avError(header));
        headerWritten = true;
        return Status::success();
    }
};

VideoEncoder::VideoEncoder(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}

VideoEncoder::~VideoEncoder() {
    if (m_impl && !m_impl->finished)
        m_impl->discard();
}

Result<std::unique_ptr<VideoEncoder>> VideoEncoder::open(const VideoSettings& settings) {
    // libav* report through their own logger; our errors carry what matters. Only its errors get through.
    av_log_set_level(AV_LOG_ERROR);
    auto impl = std::make_unique<Impl>();
    impl->settings = settings;
    impl->target = settings.output;
    impl->codecName = settings.format == VideoFormat::Mp4 ? "libx264" : settings.format == VideoFormat::Gif ? "gif" : "png";
    const auto fail = [&](Status s) {
        impl->discard();
        return s;
    };
    if (settings.width < 16 || settings.height < 16 || settings.width > 8192 || settings.height > 8192)
        return impl->error("size " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                           " is outside 16..8192 per side");
    if (!(std::isfinite(settings.fps) && settings.fps > 0.0 && settings.fps <= 240.0))
        return impl->error("fps must be in (0, 240], got " + detail::formatNumber(settings.fps));
    if (settings.crf < 0 || settings.crf > 51)
        return impl->error("crf must be in [0, 51], got " + std::to_string(settings.crf));
    std::error_code fsError;

    if (settings.format == VideoFormat::PngSequence) {
        if (!std::filesystem::is_directory(impl->target, fsError)) {
            if (!std::filesystem::create_directory(impl->target, fsError))
                return impl->error("cannot create the directory: " + fsError.message());
            impl->createdDirectory = true;
        }
        // Frames a killed render staged here (frame_NNNN.png.tmp-PID-N), whatever their number.
        removeStaleTemporaries(impl->target, [](const std::string& name) {
            return name.rfind("frame_", 0) == 0 && name.size() > 10 && name.compare(name.size() - 4, 4, ".png") == 0;
        });
        const AVCodec* png = avcodec_find_encoder(AV_CODEC_ID_PNG);
        if (png == nullptr)
            return fail(impl->error("libavcodec has no PNG encoder"));
        if (Status s = impl->openCodec(png, AV_PIX_FMT_RGBA); !s)
            return fail(s);
        return std::unique_ptr<VideoEncoder>(new VideoEncoder(std::move(impl)));
    }

    const std::filesystem::path parent = impl->target.has_parent_path() ? impl->target.parent_path() : ".";
    if (!std::filesystem::is_directory(parent, fsError))
        return impl->error("the directory " + detail::quoted(parent) + " does not exist");
    removeStaleTemporaries(impl->target);  // what a killed render of the same file left
    impl->temporary = detail::temporaryPathFor(impl->target);
    if (settings.format == VideoFormat::Mp4) {
        if (settings.width % 2 != 0 || settings.height % 2 != 0)
            return impl->error("MP4 (yuv420p) needs an even width and height, got " + std::to_string(settings.width) +
                               "x" + std::to_string(settings.height));
        const AVCodec* encoder = nullptr;
        if (!settings.mp4Encoder.empty()) {
            impl->codecName = settings.mp4Encoder;
            encoder = avcodec_find_encoder_by_name(settings.mp4Encoder.c_str());
            if (encoder == nullptr || encoder->type != AVMEDIA_TYPE_VIDEO)
                return impl->error("libavcodec has no video encoder of that name");
        } else if (encoder = avcodec_find_encoder_by_name("libx264"); encoder == nullptr) {
            encoder = avcodec_find_encoder(AV_CODEC_ID_MPEG4);
            if (encoder == nullptr)
                return impl->error("libavcodec has neither libx264 nor an MPEG-4 encoder");
            impl->warnings.push_back("libx264 is not available in this libavcodec; " + detail::quoted(impl->target) +
                                     " is encoded with " + encoder->name + " (MPEG-4 Part 2) instead of H.264");
        }
        if (Status s = impl->openContainer("mp4"); !s)
            return fail(s);
        if (Status s = impl->openCodec(encoder, AV_PIX_FMT_YUV420P); !s)
            return fail(s);
        impl->scaler = sws_getContext(settings.width, settings.height, AV_PIX_FMT_RGBA, settings.width, settings.height,
                                      AV_PIX_FMT_YUV420P, SWS_BICUBIC, nullptr, nullptr, nullptr);
        if (impl->scaler == nullptr)
            return fail(impl->error("swscale cannot convert RGBA to yuv420p"));
    } else {
        const AVCodec* encoder = avcodec_find_encoder(AV_CODEC_ID_GIF);
        if (encoder == nullptr)
            return impl->error("libavcodec has no GIF encoder");
        if (Status s = impl->openContainer("gif"); !s)
            return fail(s);
        if (Status s = impl->openCodec(encoder, AV_PIX_FMT_PAL8); !s)
            return fail(s);
        impl->palette = gifPalette();
    }
    if (Status s = impl->startContainer(); !s)
        return fail(s);
    return std::unique_ptr<VideoEncoder>(new VideoEncoder(std::move(impl)));
}

Status VideoEncoder::writeFrame(std::span<const std::uint8_t> rgba) {
    Impl& d = *m_impl;
    if (d.finished || d.codec == nullptr)
        return d.error("the encoder is closed");
    const int w = d.settings.width, h = d.settings.height;
    if (rgba.size() != std::size_t(w) * std::size_t(h) * 4)
        return d.error("frame of " + std::to_string(rgba.size()) + " bytes, expected " + std::to_string(w) + "x" +
                       std::to_string(h) + " RGBA");
    if (const int writable = av_frame_make_writable(d.frame); writable < 0)
        return d.error("cannot reuse the frame buffer: " + avError(writable));
    if (d.settings.format == VideoFormat::Mp4) {
        const std::uint8_t* source[1] = {rgba.data()};
        const int stride[1] = {w * 4};
        sws_scale(d.scaler, source, stride, 0, h, d.frame->data, d.frame->linesize);
    } else if (d.settings.format == VideoFormat::Gif) {
        static constexpr float kBayer[4][4] = {{0.0f, 8.0f, 2.0f, 10.0f}, {12.0f, 4.0f, 14.0f, 6.0f},
                                               {3.0f, 11.0f, 1.0f, 9.0f}, {15.0f, 7.0f, 13.0f, 5.0f}};
        for (int y = 0; y < h; ++y) {
            std::uint8_t* out = d.frame->data[0] + std::ptrdiff_t(y) * d.frame->linesize[0];
            const std::uint8_t* in = rgba.data() + std::size_t(y) * std::size_t(w) * 4;
            for (int x = 0; x < w; ++x) {
                const float t = (kBayer[y & 3][x & 3] + 0.5f) / 16.0f;
                const int r = quantise(in[4 * x], kLevelsR, t);
                const int g = quantise(in[4 * x + 1], kLevelsG, t);
                const int b = quantise(in[4 * x + 2], kLevelsB, t);
                out[x] = std::uint8_t((r * kLevelsG + g) * kLevelsB + b);
            }
        }
        std::memcpy(d.frame->data[1], d.palette.data(), 256 * sizeof(std::uint32_t));
    } else {
        for (int y = 0; y < h; ++y)
            std::memcpy(d.frame->data[0] + std::ptrdiff_t(y) * d.frame->linesize[0],
                        rgba.data() + std::size_t(y) * std::size_t(w) * 4, std::size_t(w) * 4);
    }
    d.frame->pts = d.frames;
    if (Status s = d.encode(d.frame); !s)
        return s;
    ++d.frames;
    return Status::success();
}

Status VideoEncoder::finish() {
    Impl& d = *m_impl;
    if (d.finished)
        return Status::success();
    if (d.codec == nullptr)
        return d.error("the encoder is closed");
    if (Status s = d.encode(nullptr); !s) {
        d.discard();
        return s;
    }
    if (d.format != nullptr) {
        d.headerWritten = false;
        if (const int trailer = av_write_trailer(d.format); trailer < 0) {
            Status s = d.error("cannot finish the file: " + avError(trailer));
            d.discard();
            return s;
        }
        if (const int closed = avio_closep(&d.format->pb); closed < 0) {
            Status s = d.error("cannot close the file: " + avError(closed));
            d.discard();
            return s;
        }
    }
    std::error_code renameError;
    if (!d.temporary.empty()) {
        std::filesystem::rename(d.temporary, d.target, renameError);
        if (renameError) {
            Status s = d.error("cannot replace it: " + renameError.message());
            d.discard();
            return s;
        }
        detail::forgetTemporary(d.temporary);
        d.temporary.clear();
    }
    for (const auto& [staged, final] : d.stagedPngs) {
        std::filesystem::rename(staged, final, renameError);
        if (renameError)
            return Status::error("cannot replace " + detail::quoted(final) + ": " + renameError.message());
        detail::forgetTemporary(staged);
    }
    d.stagedPngs.clear();
    d.createdDirectory = false;
    d.freeCodec();
    d.finished = true;
    return Status::success();
}

void VideoEncoder::abort() {
    m_impl->discard();
    m_impl->finished = true;
}

int VideoEncoder::frameCount() const { return m_impl->frames; }
std::string VideoEncoder::codecName() const { return m_impl->codecName; }
const std::vector<std::string>& VideoEncoder::warnings() const { return m_impl->warnings; }

Result<VideoProbe> probeVideo(const std::filesystem::path& path) {
    AVFormatContext* format = nullptr;
    if (const int opened = avformat_open_input(&format, path.c_str(), nullptr, nullptr); opened < 0)
        return Status::error("cannot read " + detail::quoted(path) + " as a video: " + avError(opened));
    const auto close = [&] { avformat_close_input(&format); };
    if (const int info = avformat_find_stream_info(format, nullptr); info < 0) {
        close();
        return Status::error("cannot read the streams of " + detail::quoted(path) + ": " + avError(info));
    }
    const int index = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
    if (index < 0) {
        close();
        return Status::error(detail::quoted(path) + " has no video stream");
    }
    const AVStream* stream = format->streams[index];
    VideoProbe probe;
    probe.codec = avcodec_get_name(stream->codecpar->codec_id);
    probe.width = stream->codecpar->width;
    probe.height = stream->codecpar->height;
    const AVRational rate = stream->avg_frame_rate.num > 0 ? stream->avg_frame_rate : stream->r_frame_rate;
    probe.fps = rate.den > 0 ? av_q2d(rate) : 0.0;
    AVPacket* packet = av_packet_alloc();
    while (av_read_frame(format, packet) >= 0) {
        if (packet->stream_index == index)
            ++probe.frames;
        av_packet_unref(packet);
    }
    av_packet_free(&packet);
    close();
    return probe;
}

}  // namespace softtouch::io
