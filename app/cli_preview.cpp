// softtouch-cli preview: a web page that plays an exported clip with three.js, as a game would.
#include "app/bundled_paths.h"
#include "app/cli_commands.h"
#include "app/cli_options.h"
#include "app/cli_support.h"

#include "io/pipeline/clip_preview.h"
#include "render/preview_page.h"

#include <cstdio>

namespace softtouch::cli {
namespace {

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

    const io::PreviewAssets assets{app::bundledFolder("web", "web"), app::bundledFolder("shaders", "io/shaders")};
    auto page = render::writePreviewPage(clipPath, outDir, size.first, size.second, assets);
    if (!page)
        return fail(page.message());
    const io::PreviewClip& clip = page->clip;
    if (!quiet)
        std::printf("wrote %s (%s clip %s: %d frames at %g fps, %s; %.1f MB)\n", page->index.c_str(),
                    io::previewKindName(clip.kind), clip.name.c_str(), clip.frames, clip.fps, clip.summary.c_str(),
                    double(page->bytes) / 1e6);
    return 0;
}

}  // namespace softtouch::cli
