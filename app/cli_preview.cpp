// softtouch-cli preview: a web page that plays an exported clip with three.js, as a game would.
#include "app/bundled_paths.h"
#include "app/cli_commands.h"
#include "app/cli_options.h"
#include "app/cli_support.h"

#include "io/files/atomic_file.h"
#include "io/pipeline/clip_preview.h"
#include "render/video_render.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

namespace softtouch::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPreviewAbout = R"(Write DIR/index.html, one self-contained page that plays an exported clip in a web browser with
three.js, the way a game engine plays it: skinned and morph glTF through three.js's own loader,
skinning and morph targets; vertex animation textures and lattice caches through SoftTouch's shipped
engine shaders (io/shaders/) in WebGL 2. Open it from disk; no server is needed. The camera starts
where 'softtouch-cli render' puts it (drag to orbit; Reset view goes back), with play, pause, a frame
slider and the keys Space, Left, Right and Home.
)";

constexpr const char* kPreviewAfter = R"(The page's address takes options after '#': frame=N shows frame N and stops, until=T plays
and stops T seconds in (both take lists: frame=6,12&until=0.4,1.3), size=WxH draws at that size, matte
draws a white silhouette on black, readback writes each stop's picture as a PNG into the page (tests use
these).
)";

std::array<float, 3> array3(const Eigen::Vector3f& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

int runPreview(const std::vector<std::string>& args) {
    std::string clipPath, outDir;
    std::pair<int, int> size{960, 540};
    bool quiet = false;
    CommandLine line("preview", kPreviewAbout, kPreviewAfter);
    line.positional("CLIP", clipPath,
                    "What 'bake' wrote: a .glb/.gltf of --format skin, pca, glb or gltf; a VAT's .vat.json (or its base "
                    "path); a lattice cache's .lattice.bin (or its base path). The page carries every file the clip "
                    "names, so those files (a glTF's buffers and images, a VAT's textures, a lattice cache's mesh) must "
                    "be regular files in the clip's folder or a folder below it (a link must lead there too); and a "
                    "glTF three.js cannot play (data outside its buffers, nodes in a cycle, a required extension the "
                    "page cannot decode) is refused with the reason.");
    line.text("--out", outDir, {"DIR", "Folder for index.html (created if missing).", true});
    line.value("--size", sizeReader(size), {"WxH", "The picture size the camera is framed for (default 960x540, as render's)."});
    line.flag("--quiet", quiet, "No summary line.");
    if (const auto exit = line.parse(args))
        return *exit;

    auto clip = io::inspectPreviewClip(clipPath);
    if (!clip)
        return fail(clip.message());
    const float aspect = float(size.first) / float(size.second);
    const render::CameraPlacement placement = render::videoCameraPlacement(clip->restBounds, aspect);
    io::PreviewCamera camera;
    camera.eye = array3(placement.eye);
    camera.centre = array3(placement.centre);
    camera.up = array3(placement.up);
    camera.fovYDegrees = float(placement.fovY * 180.0 / M_PI);
    camera.nearPlane = placement.nearPlane;
    camera.farPlane = placement.farPlane;
    const io::PreviewAssets assets{app::bundledFolder("web", "web"), app::bundledFolder("shaders", "io/shaders")};
    auto page = io::buildPreviewPage(clip.value(), camera, assets);
    if (!page)
        return fail(page.message());
    std::error_code ec;
    fs::create_directories(outDir, ec);
    if (ec)
        return fail("cannot create " + outDir + ": " + ec.message());
    const fs::path index = fs::path(outDir) / "index.html";
    if (Status s = io::writeFileAtomically(index, page.value()); !s)
        return fail(s.message());
    if (!quiet)
        std::printf("wrote %s (%s clip %s: %d frames at %g fps, %s; %.1f MB)\n", index.c_str(),
                    io::previewKindName(clip->kind), clip->name.c_str(), clip->frames, clip->fps, clip->summary.c_str(),
                    double(page.value().size()) / 1e6);
    return 0;
}

}  // namespace softtouch::cli
