#include "render/video_render.h"

#include "render/egl_context.h"
#include "render/mesh_renderer.h"

#include "io/files/memory_budget.h"

#include <algorithm>
#include <string>

namespace softtouch::render {

CameraPlacement videoCameraPlacement(const Bounds& restBounds, float aspect) {
    Bounds bounds = restBounds;
    const Vec3 margin = 0.1 * (bounds.max - bounds.min);
    bounds.min -= margin;
    bounds.max += margin;
    return framePlacement(bounds, Eigen::Vector3f(-0.6f, -0.45f, -1.0f), aspect);
}

namespace {

/// Bytes a render holds at its peak, from `/usr/bin/time` on the guppy at 1024², 2048² and 4096²
/// (docs/design/reliability.md, "Limits"): the program and Mesa ~200 MB; per pixel ~44 bytes for the 4x
/// multisampled colour and depth, the resolve and the read-back; for MP4, x264 (preset medium) ~20
/// more, and ~3.6 for each frame it holds for its look-ahead and B-frames (up to ~50).
std::uint64_t renderMemoryBytes(const io::VideoSettings& settings, int frames) {
    const double pixels = double(settings.width) * double(settings.height);
    double perPixel = 44.0;
    if (settings.format == io::VideoFormat::Mp4)
        perPixel += 20.0 + 3.6 * double(std::min(frames, 50));
    return std::uint64_t(200e6 + pixels * perPixel);
}

}  // namespace

Result<VideoRenderResult> renderVideo(const Scene& scene, const VideoRenderOptions& options) {
    VideoRenderResult result;
    auto created = io::FrameSource::create(scene, options.frames, &result.warnings);
    if (!created)
        return Status::error(created.message());
    io::FrameSource& source = created.value();

    io::VideoSettings settings = options.video;
    settings.fps = source.fps();
    // Checked before anything of that size exists: at 8192x8192 a driver or the encoder that runs out
    // of memory half-way aborts or crashes (a batch job died of SIGSEGV) instead of failing.
    const std::string size = std::to_string(settings.width) + "x" + std::to_string(settings.height);
    if (Status s = io::checkMemoryFor(renderMemoryBytes(settings, source.frameCount()),
                                      "rendering " + size + " (" + std::to_string(source.frameCount()) + " frames)",
                                      "render at a smaller size (half the width and height needs about a quarter)");
        !s)
        return s;
    auto encoder = io::VideoEncoder::open(settings);
    if (!encoder)
        return Status::error(encoder.message());
    auto context = EglContext::create(settings.width, settings.height, 4);
    if (!context)
        return Status::error("cannot create a headless OpenGL context: " + context.message());
    MeshRenderer renderer;
    if (Status s = renderer.initialize(); !s)
        return s;
    for (const SceneObject& object : scene.objects) {
        auto id = renderer.addObject(object.mesh, object.lattice);
        if (!id) {
            renderer.release();
            return Status::error("object '" + object.name + "': " + id.message());
        }
    }
    const Bounds bounds = restBounds(scene);
    renderer.setPlanes(scene.world.planes, float(1.2 * bounds.diagonal()));
    renderer.setColliders(scene.world.colliders);
    const float aspect = float(settings.width) / float(settings.height);
    const Camera camera = cameraFor(options.camera.value_or(videoCameraPlacement(bounds, aspect)), aspect);

    std::vector<std::uint8_t> pixels;
    std::vector<Vec3f> positions, normals;
    const int frameCount = source.frameCount();
    Status rendered = Status::success();
    for (int f = 0; f < frameCount && rendered; ++f) {
        source.seek(f, &result.warnings);
        for (std::size_t i = 0; i < source.simulation().objectCount(); ++i)
            showSceneObject(renderer, int(i), source.simulation(), i, source.nodes(i), source.seconds(), positions, normals);
        context.value()->bindFramebuffer();
        renderer.draw(camera, settings.width, settings.height);
        rendered = context.value()->readPixels(pixels);
        if (rendered)
            rendered = encoder.value()->writeFrame(pixels);
        if (rendered && options.progress && !options.progress(f + 1, frameCount))
            rendered = Status::cancelled("the render was cancelled; nothing was written");
    }
    renderer.release();
    if (!rendered) {
        encoder.value()->abort();
        return rendered;
    }
    if (Status s = encoder.value()->finish(); !s)
        return s;
    result.warnings.insert(result.warnings.begin(), encoder.value()->warnings().begin(), encoder.value()->warnings().end());
    result.frames = encoder.value()->frameCount();
    result.fps = settings.fps;
    result.codec = encoder.value()->codecName();
    result.context = context.value()->description();
    return result;
}

}  // namespace softtouch::render
