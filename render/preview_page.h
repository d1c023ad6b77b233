#pragma once
/// The clip preview page written to a folder, its camera standing where `render` stands: the one way both
/// `softtouch-cli preview` and the editor's Export… make it (io/pipeline/clip_preview.h builds the page).

#include "core/base/result.h"
#include "io/pipeline/clip_preview.h"

#include <cstddef>
#include <filesystem>

namespace softtouch::render {

/// What was written.
struct PreviewPage {
    std::filesystem::path index;  ///< outDir/index.html.
    io::PreviewClip clip;         ///< The clip as the page plays it.
    std::size_t bytes = 0;        ///< Of the page.
};

/// Writes the preview page of the export at `clip` (what `bake` wrote) to `outDir`/index.html (the folder made
/// when missing; the page replaced whole or not at all), framed for a `width` x `height` picture as
/// videoCameraPlacement() frames a render. Errors name the clip's file, the missing asset or the folder.
Result<PreviewPage> writePreviewPage(const std::filesystem::path& clip, const std::filesystem::path& outDir, int width,
                                     int height, const io::PreviewAssets& assets);

}  // namespace softtouch::render
