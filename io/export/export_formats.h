#pragma once
/// The export registry: every way a clip can be exported, as people name it, with its writer. `bake
/// --format`, batch manifests, the editor's Export Clip dialog and the CLI usage text all read this one
/// table, so a new export is its writer's file and one entry (with its factory's declaration) in
/// export_formats.cpp. Several entries may share a writer: pca and skin are GLB (or glTF) files written
/// with their own options.

#include "core/base/result.h"
#include "io/export/clip_writer.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace softtouch::io {

/// What a bake must hand an export's writer each frame besides the deformed positions.
enum class ExportNeeds {
    Positions,     ///< Positions only (vertex caches).
    Normals,       ///< Positions and unit normals (glTF morphs, skins, VAT).
    LatticeNodes,  ///< Each object's lattice nodes: the mesh is rebuilt from them, so an object moved by a
                   ///< rig of its own cannot be exported this way.
};

/// Settings an export takes beside its path (bake's --error, --targets, --bones, --compress). Unset: the default.
struct ExportSettings {
    std::optional<double> error;  ///< Compression target, a fraction of the rest mesh's diagonal, (0, 0.1].
    std::optional<double> targets;  ///< Compressed morphs: most targets, the mean included, a whole number in [2, 256].
    std::optional<double> bones;    ///< Skinning: exactly this many bones, a whole number in [1, 256].
    bool compress = false;          ///< GLB for shipping: EXT_meshopt_compression, octahedral normals, 8-bit weights.
    std::optional<ClipExportOptions::SkinRig> rig = std::nullopt;  ///< Skinning: the source rig or fitted bones (default: auto).
};

/// The skin rig a name gives ("auto", "source", "fitted"); nullopt for any other.
std::optional<ClipExportOptions::SkinRig> skinRigNamed(std::string_view name);

/// Where an export's rest mesh goes (the OBJ whose vertex order the files follow; bake writes it).
enum class RestMeshPlace {
    ReplaceExtension,  ///< out/fish.pc2 -> out/fish.obj.
    AfterBasePath,     ///< A base path keeps all of its name: out/fish.v2 -> out/fish.v2.obj.
    AtPath,            ///< The path itself (an OBJ sequence: its frames go beside it).
};

/// Makes an export's writer for `path` (an export of several extensions writes what the path's names).
using MakeExportWriter = std::unique_ptr<ClipWriter> (*)(const std::filesystem::path& path, const ClipExportOptions& options);
/// Every file an export of `frames` frames to `path` publishes, the cache first.
using ExportFiles = std::vector<std::filesystem::path> (*)(const std::filesystem::path& path, std::size_t frames);

/// One export.
struct ExportFormat {
    std::string_view name;        ///< What people type: "pc2", "pca", … (case-insensitive when parsed).
    std::string_view label;       ///< For a file dialog: "Point cache".
    std::string_view extensions;  ///< Space-separated, first is the default: ".glb .gltf". Empty for a base
                                  ///< path, whose files get suffixes (vat, lattice; docs/formats.md).
    ExportNeeds needs;            ///< What the bake supplies per frame.
    bool takesError;              ///< Accepts ExportSettings::error.
    bool takesTargets;            ///< Accepts ExportSettings::targets.
    bool takesBones;              ///< Accepts ExportSettings::bones.
    bool takesCompress;           ///< Accepts ExportSettings::compress (writes GLB).
    std::string_view help;        ///< A sentence for usage texts (wrapped by the caller).
    MakeExportWriter makeWriter;  ///< Its writer.
    ExportFiles files;            ///< The files it publishes; nullptr: the one file at the path.
    RestMeshPlace restMesh;       ///< Where bake puts the rest mesh.
};

/// The extensions of `format`, first the default (".glb", ".gltf"); none for a base path.
std::vector<std::string_view> extensionsOf(const ExportFormat& format);

/// Every export, in the order usage texts and the editor list them.
std::span<const ExportFormat> exportFormats();

/// The export called `name` (case-insensitive); nullptr when there is none.
const ExportFormat* findExportFormat(std::string_view name);

/// The export a path's extension names (the first entry listing it: ".glb" is glb, not pca); nullptr
/// for an unknown or missing extension.
const ExportFormat* exportFormatForPath(const std::filesystem::path& path);

/// "pc2, mdd, …, vat or lattice": every name, for messages and usage lines (`separator` between names,
/// `last` before the final one).
std::string exportFormatNames(std::string_view separator = ", ", std::string_view last = " or ");

/// ".pc2, .mdd, .obj, .gltf, .glb": every extension that names an export, once each, in registry order.
std::string exportExtensions();

/// Every file an export of `format` with `frames` frames to `path` publishes, the cache first (for an OBJ
/// sequence every frame; for vat and lattice `path` is a base path and the names get suffixes, see
/// docs/formats.md). The rest mesh is not among them: restMeshPath().
std::vector<std::filesystem::path> exportFiles(const ExportFormat& format, const std::filesystem::path& path,
                                               std::size_t frames = 1);

/// Where the rest mesh of an export of `format` to `path` goes (RestMeshPlace).
std::filesystem::path restMeshPath(const std::filesystem::path& path, const ExportFormat& format);

/// Whether an export of several extensions writes glTF JSON to `path` (it ends in .gltf) rather than GLB.
bool writesGltfJson(const std::filesystem::path& path);

/// The writer options an export of `format` uses with `settings`. Refuses a setting the format does
/// not take, a value out of range, or --bones with --error, with a message naming the option
/// ("--targets: is for --format pca").
Result<ClipExportOptions> exportOptions(const ExportFormat& format, const ExportSettings& settings = {});

}  // namespace softtouch::io
