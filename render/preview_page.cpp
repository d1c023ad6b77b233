#include "render/preview_page.h"

#include "io/files/atomic_file.h"
#include "render/video_render.h"

#include <array>
#include <numbers>
#include <system_error>

namespace softtouch::render {

Result<PreviewPage> writePreviewPage(const std::filesystem::path& clipPath, const std::filesystem::path& outDir, int width,
                                     int height, const io::PreviewAssets& assets) {
    auto clip = io::inspectPreviewClip(clipPath);
    if (!clip)
        return clip.status();
    const CameraPlacement placement = videoCameraPlacement(clip->restBounds, float(width) / float(height));
    const auto array3 = [](const Eigen::Vector3f& v) { return std::array<float, 3>{v.x(), v.y(), v.z()}; };
    io::PreviewCamera camera;
    camera.eye = array3(placement.eye);
    camera.centre = array3(placement.centre);
    camera.up = array3(placement.up);
    camera.fovYDegrees = float(placement.fovY * 180.0 / std::numbers::pi);
    camera.nearPlane = placement.nearPlane;
    camera.farPlane = placement.farPlane;
    auto page = io::buildPreviewPage(clip.value(), camera, assets);
    if (!page)
        return page.status();
    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    if (ec)
        return Status::error("cannot create " + outDir.string() + ": " + ec.message());
    PreviewPage written;
    written.index = outDir / "index.html";
    if (Status s = io::writeFileAtomically(written.index, page.value()); !s)
        return s;
    written.clip = std::move(clip.value());
    written.bytes = page.value().size();
    return written;
}

}  // namespace softtouch::render
