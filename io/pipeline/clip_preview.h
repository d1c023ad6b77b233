#pragma once
/// The clip preview page (`softtouch-cli preview`): one self-contained HTML file that plays an exported
/// clip with three.js in a browser, as a game engine would play it (docs/formats.md, "Preview page").
/// The page holds the player (web/preview.js), three.js's modules from the npm package (an import map of
/// data: URLs, so it opens from disk with no server), the clip's files in base64 and the shipped engine
/// shaders (io/shaders/).

#include "core/base/result.h"
#include "core/geometry/mesh.h"

#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace softtouch::io {

/// How a clip plays in a runtime.
enum class PreviewKind {
    Skinned,  ///< glTF skin and joint animation (`bake --format skin`).
    Morph,    ///< glTF morph targets and a weights animation (`--format glb|gltf|pca`).
    Vat,      ///< Vertex animation textures (`--format vat`).
    Lattice,  ///< Lattice cache (`--format lattice`).
};

/// "skinned", "morph", "vat", "lattice".
const char* previewKindName(PreviewKind kind);

/// Whether the page plays what the export called `format` writes ("skin", "pca", "glb", "gltf", "vat",
/// "lattice"; io/export/export_formats.h): the kinds a game plays, not point caches or meshes.
bool previewPlays(std::string_view format);

/// An exported clip as the page needs it.
struct PreviewClip {
    PreviewKind kind = PreviewKind::Morph;
    std::string name;                          ///< File name shown on the page.
    std::string main;                          ///< The glTF to load (mesh of VAT and lattice too).
    std::vector<std::filesystem::path> files;  ///< Every file the page embeds (names are unique).
    Bounds restBounds;                         ///< Of the rest mesh's positions, metres.
    int frames = 0;                            ///< >= 1.
    double fps = 0.0;                          ///< > 0.
    bool loop = true;                          ///< Played in a loop.
    bool closesLoop = false;                   ///< The animation has a closing key at frames / fps (= frame 0).
    std::string summary;                       ///< One line: "8 bones", "2 morph targets", ...
    std::string kindData;                      ///< JSON the player needs for VAT and lattice (else empty).
};

/// Recognises an export by its name and contents: a .glb/.gltf with a skin or with morph targets and a
/// weights animation; a VAT (`BASE.vat.json` or any of its files, or BASE); a lattice cache
/// (`BASE.lattice.bin`, `.lattice.glb`, or BASE). Errors name the file and what is missing.
Result<PreviewClip> inspectPreviewClip(const std::filesystem::path& path);

/// Where the page's camera stands (render::videoCameraPlacement, so the page draws what `render` draws).
struct PreviewCamera {
    std::array<float, 3> eye{};
    std::array<float, 3> centre{};
    std::array<float, 3> up{};
    float fovYDegrees = 35.0f;
    float nearPlane = 0.01f;
    float farPlane = 100.0f;
};

/// Where the page's own files are: `webRoot` holds preview.js and node_modules/three (the npm package
/// web/package.json pins); `shaderDir` holds lattice_deform.glsl and vat_deform.glsl.
struct PreviewAssets {
    std::filesystem::path webRoot;
    std::filesystem::path shaderDir;
};

/// The page's HTML; errors name the missing asset (three.js not installed: run scripts/install-deps.sh).
Result<std::string> buildPreviewPage(const PreviewClip& clip, const PreviewCamera& camera, const PreviewAssets& assets);

/// The three.js import map of the modules `script` imports, and theirs in turn, each a data: URL, with
/// every import rewritten to the map's names ("three/<path in the package>"); `script` is returned
/// rewritten the same way. Exposed for tests.
struct InlinedModules {
    std::string importMapJson;
    std::string script;
    int moduleCount = 0;
};
Result<InlinedModules> inlineThreeModules(const std::string& script, const std::filesystem::path& threeRoot);

}  // namespace softtouch::io
