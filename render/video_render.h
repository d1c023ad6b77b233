#pragma once
/// A scene's frames (a clip of its library, or its drivers) drawn headless on the GPU and encoded as
/// a video: the one loop behind `softtouch-cli render` and the editor's Render Video. Needs no X
/// server (render::EglContext, surfaceless EGL); one frame in memory; nothing published unless every
/// frame succeeded.

#include "io/export/video_encoder.h"
#include "io/pipeline/frame_source.h"
#include "render/camera.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace softtouch::render {

/// What to render.
struct VideoRenderOptions {
    io::VideoSettings video;        ///< Output, format, size, crf; `fps` is taken from the frames played.
    io::FrameRequest frames;        ///< Clip, frame count and rate (io/pipeline/frame_source.h).
    /// Where the camera stands; none: videoCameraPlacement() of the scene's rest bounds (the CLI's and the
    /// preview page's view). The editor passes its viewport's view.
    std::optional<CameraPlacement> camera;
    /// Called after each frame with (frames done, total); returning false cancels (nothing is written).
    std::function<bool(int, int)> progress;
};

/// What was written.
struct VideoRenderResult {
    int frames = 0;                      ///< Frames encoded.
    double fps = 0.0;                    ///< Frame rate.
    std::string codec;                   ///< Encoder used (libx264, mpeg4, gif, png).
    std::string context;                 ///< The OpenGL implementation that drew it.
    std::vector<std::string> warnings;   ///< Simulation and encoder warnings.
};

/// The camera of every video render: a 3/4 view from the front, above and to the left, framing the
/// rest bounds grown by a tenth on each side (room for the motion). The preview page
/// (`softtouch-cli preview`) stands its camera here too, so both draw the same picture.
CameraPlacement videoCameraPlacement(const Bounds& restBounds, float aspect);

/// Renders and encodes; errors name the file, the codec or the GL problem.
Result<VideoRenderResult> renderVideo(const Scene& scene, const VideoRenderOptions& options);

}  // namespace softtouch::render
