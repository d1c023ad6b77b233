#pragma once
/// Video output of rendered frames through libavcodec / libavformat: MP4 (H.264 via libx264, or
/// MPEG-4 Part 2 when libx264 is missing, with a warning), animated GIF, or a PNG sequence. Streaming
/// (one frame in memory) and atomic: everything is written under temporary names and renamed only by
/// finish(), so a failed or cancelled render leaves an existing file untouched and nothing behind.

#include "core/base/result.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace softtouch::io {

/// Kind of video output.
enum class VideoFormat {
    Mp4,         ///< H.264 (libx264, yuv420p, CRF) in MP4; MPEG-4 Part 2 fallback.
    Gif,         ///< Animated GIF, 256-colour palette with ordered dithering, looping.
    PngSequence, ///< DIR/frame_0000.png, frame_0001.png, ... (RGBA).
};

/// The format an output path asks for: a path ending in '/' or an existing directory is a PNG
/// sequence, ".mp4" MP4, ".gif" GIF (case-insensitive); anything else nullopt.
std::optional<VideoFormat> videoFormatFromPath(const std::filesystem::path& path);

/// Name of the file frame `index` of a PNG sequence gets in `directory`.
std::filesystem::path pngSequenceFramePath(const std::filesystem::path& directory, int index);

/// What to encode.
struct VideoSettings {
    std::filesystem::path output;          ///< File (MP4, GIF) or directory (PNG sequence, created if missing).
    VideoFormat format = VideoFormat::Mp4; ///< Output kind.
    int width = 960;                       ///< Pixels, [16, 8192]; even for MP4 (yuv420p).
    int height = 540;                      ///< Pixels, [16, 8192]; even for MP4 (yuv420p).
    double fps = 24.0;                     ///< Frames per second, (0, 240].
    int crf = 20;                          ///< H.264 constant rate factor, [0, 51]: lower is better and larger.
    std::string mp4Encoder;                ///< MP4 encoder by libavcodec name; empty: libx264, else mpeg4 with a warning.
};

/// Streams RGBA frames into a video. Not copyable; destroying it before finish() discards everything.
class VideoEncoder {
public:
    /// Checks the settings, finds the encoder and opens the temporary output. Errors name the file
    /// and the codec.
    static Result<std::unique_ptr<VideoEncoder>> open(const VideoSettings& settings);
    ~VideoEncoder();
    VideoEncoder(const VideoEncoder&) = delete;
    VideoEncoder& operator=(const VideoEncoder&) = delete;

    /// Encodes one frame: width*height*4 bytes of RGBA8, rows top-down.
    Status writeFrame(std::span<const std::uint8_t> rgba);
    /// Flushes the encoder, finishes the container and renames the temporaries over the targets.
    Status finish();
    /// Discards everything written so far; existing files stay as they were.
    void abort();

    /// Frames written so far.
    int frameCount() const;
    /// The codec in use, as libavcodec names it ("libx264", "mpeg4", "gif", "png").
    std::string codecName() const;
    /// Things worth telling the user (the fallback encoder).
    const std::vector<std::string>& warnings() const;

private:
    struct Impl;
    explicit VideoEncoder(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
};

/// What libavformat reads back from a video file (for tests and checks).
struct VideoProbe {
    std::string codec;  ///< Codec name of the first video stream ("h264", "gif", ...).
    int width = 0;      ///< Pixels.
    int height = 0;     ///< Pixels.
    double fps = 0.0;   ///< The stream's average frame rate (or its r_frame_rate when unset).
    int frames = 0;     ///< Packets of the video stream, counted by reading the whole file.
};

/// Opens a video file with libavformat; errors name the file.
Result<VideoProbe> probeVideo(const std::filesystem::path& path);

}  // namespace softtouch::io
