// softtouch-cli render: simulate a scene and write a video, headless (EGL, no X server).
#include "app/cli_commands.h"
#include "app/cli_options.h"
#include "app/cli_support.h"
#include "core/base/ranges.h"

#include "io/documents/project_file.h"
#include "io/export/video_encoder.h"
#include "render/video_render.h"

#include <cstdio>
#include <optional>

namespace softtouch::cli {
namespace {

constexpr const char* kRenderAbout = R"(Simulate SCENE from its rest state (frame i at i/fps s, as bake does) and draw every frame with the
GPU renderer in a headless EGL context (no X server needed; Mesa's llvmpipe when there is no GPU),
from a 3/4 view framing the scene's rest bounds. Output by --out: .mp4 (H.264, yuv420p; MPEG-4
Part 2 with a warning when libx264 is missing), .gif (256 colours, looping), or a directory
(ending in '/' or existing) of frame_0000.png, ... . Nothing is replaced unless the render succeeds.
)";

}  // namespace

int runRender(const std::vector<std::string>& args) {
    std::string scenePath, outPath, clipName;
    std::pair<int, int> size{960, 540};
    std::optional<double> frames, fps, crf;
    bool quiet = false;
    CommandLine line("render", kRenderAbout);
    line.positional("SCENE", scenePath, "The project to simulate (*.softtouch).");
    line.text("--out", outPath, {"FILE.mp4|FILE.gif|DIR/", "The video, or a folder for PNG frames.", true});
    line.value("--size", sizeReader(size), {"WxH", "Frame size in pixels (default 960x540; 16..8192; even for MP4)."});
    line.text("--clip", clipName, {"NAME", "A clip of the scene's clip library (default: its default clip, else the drivers)."});
    line.number("--fps", fps, {ranges::kMinFps, 240}, {"F", "Frames per second (default: the clip's or the scene's rate; at most 240)."});
    line.number("--frames", frames, ranges::kFrames,
                {"N", "Frames to render (default: the clip's or the scene's length; a loop clip cycles)."});
    line.number("--crf", crf, {0, 51, true}, {"N", "H.264 quality, 0..51, lower is better (default 20)."});
    line.flag("--quiet", quiet, "No progress output.");
    if (const auto exit = line.parse(args))
        return *exit;
    const auto format = io::videoFormatFromPath(outPath);
    if (!format)
        return line.usage("cannot tell the video format from '" + outPath + "'; use .mp4, .gif or a directory ending in '/'");
    if (*format == io::VideoFormat::Mp4 && (size.first % 2 != 0 || size.second % 2 != 0))
        return line.usage("--size " + std::to_string(size.first) + "x" + std::to_string(size.second) +
                          ": MP4 (H.264 in yuv420p) needs an even width and height");

    auto project = io::loadProjectToRun(scenePath);
    if (!project)
        return fail(project.message());
    render::VideoRenderOptions options;
    options.video.output = outPath;
    options.video.format = *format;
    options.video.width = size.first;
    options.video.height = size.second;
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
    std::filesystem::path madeFolder;
    if (const std::string problem = makeOutputFolders(outPath, madeFolder); !problem.empty())
        return fail(problem);
    auto rendered = render::renderVideo(project->scene, options);
    if (!rendered) {
        removeEmptyFolders(madeFolder);  // a failed render leaves no folder it made behind
        return fail(rendered.message());
    }
    const std::size_t shown = std::min<std::size_t>(rendered->warnings.size(), 5);
    for (std::size_t i = 0; i < shown; ++i)
        std::fprintf(stderr, "softtouch-cli: warning: %s\n", rendered->warnings[i].c_str());
    std::printf("wrote %s (%s, %dx%d, %d frames at %g fps; %s)\n", outPath.c_str(), rendered->codec.c_str(),
                options.video.width, options.video.height, rendered->frames, rendered->fps, rendered->context.c_str());
    return 0;
}

}  // namespace softtouch::cli
