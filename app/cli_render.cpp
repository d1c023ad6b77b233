// softtouch-cli render: simulate a scene and write a video, headless (EGL, no X server).
#include "app/cli_commands.h"
#include "app/cli_support.h"
#include "core/ranges.h"

#include "io/project_file.h"
#include "io/video_encoder.h"
#include "render/video_render.h"

#include <cmath>
#include <cstdio>
#include <optional>

namespace softtouch::cli {
namespace {

constexpr const char* kRenderUsage = R"(Usage: softtouch-cli render SCENE --out FILE.mp4|FILE.gif|DIR/ [options]

Simulate SCENE from its rest state (frame i at i/fps s, as bake does) and draw every frame with the
GPU renderer in a headless EGL context (no X server needed; Mesa's llvmpipe when there is no GPU),
from a 3/4 view framing the scene's rest bounds. Output by --out: .mp4 (H.264, yuv420p; MPEG-4
Part 2 with a warning when libx264 is missing), .gif (256 colours, looping), or a directory
(ending in '/' or existing) of frame_0000.png, ... . Nothing is replaced unless the render succeeds.

Options:
  --out PATH        Output (required).
  --size WxH        Frame size in pixels (default 960x540; 16..8192; even for MP4).
  --clip NAME       A clip of the scene's clip library (default: its default clip, else the drivers).
  --fps F           Frames per second (default: the clip's or the scene's rate; at most 240).
  --frames N        Frames to render (default: the clip's or the scene's length; a loop clip cycles).
  --crf N           H.264 quality, 0..51, lower is better (default 20).
  --quiet           No progress output.
)";

int renderUsage(const std::string& message) { return usageError(message, "render"); }

}  // namespace

int runRender(const std::vector<std::string>& args) {
    std::string scenePath, outPath, clipName, sizeText = "960x540";
    std::optional<double> frames, fps, crf;
    bool quiet = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--help" || a == "-h") {
            std::fputs(kRenderUsage, stdout);
            return 0;
        }
        if (a == "--quiet") {
            quiet = true;
        } else if (a == "--out" || a == "--size" || a == "--clip" || a == "--fps" || a == "--frames" || a == "--crf") {
            if (i + 1 >= args.size())
                return renderUsage(a + " needs a value");
            const std::string& v = args[++i];
            if (a == "--out") {
                outPath = v;
            } else if (a == "--size") {
                sizeText = v;
            } else if (a == "--clip") {
                clipName = v;
            } else {
                const auto n = parseNumber(v);
                if (!n)
                    return renderUsage(a + " expects a number, got '" + v + "'");
                (a == "--frames" ? frames : a == "--fps" ? fps : crf) = *n;
            }
        } else if (!a.empty() && a[0] == '-') {
            return renderUsage("unknown option '" + a + "'");
        } else if (scenePath.empty()) {
            scenePath = a;
        } else {
            return renderUsage("unexpected argument '" + a + "'");
        }
    }
    if (scenePath.empty())
        return renderUsage("render needs a SCENE file");
    if (outPath.empty())
        return renderUsage("render needs --out FILE.mp4, FILE.gif or DIR/");
    const auto format = io::videoFormatFromPath(outPath);
    if (!format)
        return renderUsage("cannot tell the video format from '" + outPath + "'; use .mp4, .gif or a directory ending in '/'");
    const auto size = parseSize(sizeText);
    if (!size)
        return renderUsage("--size expects WIDTHxHEIGHT with whole numbers in 16..8192, got '" + sizeText + "'");
    if (frames && (*frames < 1 || *frames > ranges::kMaxFrames || std::floor(*frames) != *frames))
        return renderUsage("--frames must be a whole number in [1, 1000000], got " + formatValue(*frames));
    if (fps && (*fps < ranges::kMinFps || *fps > 240))
        return renderUsage("--fps must be in [1, 240], got " + formatValue(*fps));
    if (crf && (*crf < 0 || *crf > 51 || std::floor(*crf) != *crf))
        return renderUsage("--crf must be a whole number in [0, 51], got " + formatValue(*crf));

    auto project = io::loadProject(scenePath);
    if (!project)
        return fail(project.message());
    render::VideoRenderOptions options;
    options.video.output = outPath;
    options.video.format = *format;
    options.video.width = size->first;
    options.video.height = size->second;
    options.video.crf = crf ? int(*crf) : 20;
    options.frames.clips = &project->clips;
    options.frames.clip = clipName;
    options.frames.frames = frames ? int(*frames) : 0;
    options.frames.fps = fps.value_or(0.0);
    if (!quiet)
        options.progress = [](int done, int total) {
            if (done == total || done % 24 == 0)
                std::fprintf(stderr, "\rrendering frame %d/%d%s", done, total, done == total ? "\n" : "");
            return true;
        };
    auto rendered = render::renderVideo(project->scene, options);
    if (!rendered)
        return fail(rendered.message());
    const std::size_t shown = std::min<std::size_t>(rendered->warnings.size(), 5);
    for (std::size_t i = 0; i < shown; ++i)
        std::fprintf(stderr, "softtouch-cli: warning: %s\n", rendered->warnings[i].c_str());
    std::printf("wrote %s (%s, %dx%d, %d frames at %g fps; %s)\n", outPath.c_str(), rendered->codec.c_str(),
                options.video.width, options.video.height, rendered->frames, rendered->fps, rendered->context.c_str());
    return 0;
}

}  // namespace softtouch::cli
