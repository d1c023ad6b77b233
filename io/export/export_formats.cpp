#include "io/export/export_formats.h"

#include <algorithm>
#include <array>
#include <memory>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <vector>

namespace softtouch::io {

// Each export's writer, in its own file: a factory with the registry's signature and, for exports of
// several files, the files it publishes.
namespace detail {
std::unique_ptr<ClipWriter> makePc2Export(const std::filesystem::path& path, const ClipExportOptions& options);  // pc2.cpp
std::unique_ptr<ClipWriter> makeMddExport(const std::filesystem::path& path, const ClipExportOptions& options);  // mdd.cpp
std::unique_ptr<ClipWriter> makeObjSequenceExport(const std::filesystem::path& path,
                                                  const ClipExportOptions& options);  // obj_sequence.cpp
std::vector<std::filesystem::path> objSequenceFiles(const std::filesystem::path& path, std::size_t frames);
std::unique_ptr<ClipWriter> makeGltfExport(const std::filesystem::path& path, const ClipExportOptions& options);  // gltf_export.cpp
std::unique_ptr<ClipWriter> makeGlbExport(const std::filesystem::path& path, const ClipExportOptions& options);
std::unique_ptr<ClipWriter> makeCompressedMorphExport(const std::filesystem::path& path, const ClipExportOptions& options);
std::unique_ptr<ClipWriter> makeSkinExport(const std::filesystem::path& path,
                                           const ClipExportOptions& options);  // gltf_skin_export.cpp
std::unique_ptr<ClipWriter> makeVatExport(const std::filesystem::path& path, const ClipExportOptions& options);  // vat_export.cpp
std::vector<std::filesystem::path> vatFiles(const std::filesystem::path& path, std::size_t frames);
std::unique_ptr<ClipWriter> makeLatticeExport(const std::filesystem::path& path,
                                              const ClipExportOptions& options);  // lattice_cache.cpp
std::vector<std::filesystem::path> latticeFiles(const std::filesystem::path& path, std::size_t frames);
}  // namespace detail

namespace {

using enum ExportNeeds;
using enum RestMeshPlace;
using namespace detail;

const std::array kFormats = {
    ExportFormat{"pc2", "Point cache", ".pc2", Positions, false, false, false, false,
                 "3ds Max point cache: positions per frame", makePc2Export, nullptr, ReplaceExtension},
    ExportFormat{"mdd", "MDD", ".mdd", Positions, false, false, false, false,
                 "LightWave/Blender MDD: positions and frame times", makeMddExport, nullptr, ReplaceExtension},
    ExportFormat{"objseq", "OBJ sequence", ".obj", Positions, false, false, false, false,
                 "one OBJ per frame: NAME_0000.obj, NAME_0001.obj, ... beside FILE (the rest mesh)", makeObjSequenceExport,
                 objSequenceFiles, AtPath},
    ExportFormat{"gltf", "glTF, one morph target per frame", ".gltf", Normals, false, false, false, false,
                 "glTF 2.0 (JSON, embedded buffer): one morph target per frame and a weights animation", makeGltfExport,
                 nullptr, ReplaceExtension},
    ExportFormat{"glb", "glTF binary, one morph target per frame", ".glb", Normals, false, false, false, true,
                 "the same as binary glTF", makeGlbExport, nullptr, ReplaceExtension},
    ExportFormat{"pca", "glTF binary, compressed morph targets", ".glb .gltf", Normals, true, true, false, true,
                 "glTF/GLB (by the extension) with compressed morphs: the frames' mean plus the fewest principal "
                 "components that keep every frame's RMS vertex error within --error (at most --targets); prints "
                 "the targets, the errors and the size against PC2",
                 makeCompressedMorphExport, nullptr, ReplaceExtension},
    ExportFormat{"skin", "glTF binary, skinned: bones for game engines", ".glb .gltf", Positions, true, false, true, true,
                 "glTF/GLB (by the extension) as linear blend skinning: rigid bones fitted to the clip (Le & Deng "
                 "2012), at most 4 weights a vertex, a bone animation; the fewest of 8/16/32/64 bones within "
                 "--error, or --bones K; prints the errors",
                 makeSkinExport, nullptr, ReplaceExtension},
    ExportFormat{"vat", "Vertex animation textures", "", Normals, false, false, false, false,
                 "FILE is a base path: FILE.vat-position.exr, FILE.vat-normal.exr (half float), "
                 "FILE.vat-mesh.glb, FILE.vat.json",
                 makeVatExport, vatFiles, AfterBasePath},
    ExportFormat{"lattice", "Lattice cache", "", LatticeNodes, false, false, false, false,
                 "FILE is a base path: FILE.lattice.glb (mesh with lattice u,v,w), FILE.lattice.bin (node "
                 "positions per frame); shaders in io/shaders/",
                 makeLatticeExport, latticeFiles, AfterBasePath},
};

std::string lowercase(std::string_view text) {
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

/// True when `format` lists `extension` (lower case, with its dot).
bool listsExtension(const ExportFormat& format, std::string_view extension) {
    const std::vector<std::string_view> listed = extensionsOf(format);
    return std::find(listed.begin(), listed.end(), extension) != listed.end();
}

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

/// "--error: is for --format pca and --format skin": the formats whose `takes` flag is set.
std::string onlyFor(const char* option, bool ExportFormat::*takes) {
    std::string text = std::string(option) + ": is for";
    bool first = true;
    for (const ExportFormat& f : kFormats) {
        if (!(f.*takes))
            continue;
        text += (first ? " --format " : " and --format ") + std::string(f.name);
        first = false;
    }
    return text;
}

bool isWhole(double value) { return std::floor(value) == value; }

}  // namespace

std::vector<std::string_view> extensionsOf(const ExportFormat& format) {
    std::vector<std::string_view> out;
    for (std::string_view rest = format.extensions; !rest.empty();) {
        const std::size_t space = rest.find(' ');
        out.push_back(rest.substr(0, space));
        rest = space == std::string_view::npos ? std::string_view() : rest.substr(space + 1);
    }
    return out;
}

std::span<const ExportFormat> exportFormats() { return kFormats; }

const ExportFormat* findExportFormat(std::string_view name) {
    // Case-insensitive: the same names are typed on the command line, where "PC2" is natural.
    const std::string key = lowercase(name);
    for (const ExportFormat& f : kFormats)
        if (f.name == key)
            return &f;
    return nullptr;
}

const ExportFormat* exportFormatForPath(const std::filesystem::path& path) {
    const std::string extension = lowercase(path.extension().string());
    if (extension.empty())
        return nullptr;
    for (const ExportFormat& f : kFormats)
        if (listsExtension(f, extension))
            return &f;
    return nullptr;
}

std::string exportFormatNames(std::string_view separator, std::string_view last) {
    std::string text;
    for (std::size_t i = 0; i < kFormats.size(); ++i) {
        if (i > 0)
            text += i + 1 == kFormats.size() ? last : separator;
        text += kFormats[i].name;
    }
    return text;
}

std::string exportExtensions() {
    std::vector<std::string_view> seen;
    for (const ExportFormat& f : kFormats)
        for (std::string_view e : extensionsOf(f))
            if (std::find(seen.begin(), seen.end(), e) == seen.end())
                seen.push_back(e);
    std::string text;
    for (std::string_view e : seen)
        text += (text.empty() ? "" : ", ") + std::string(e);
    return text;
}

std::vector<std::filesystem::path> exportFiles(const ExportFormat& format, const std::filesystem::path& path, std::size_t frames) {
    return format.files ? format.files(path, frames) : std::vector<std::filesystem::path>{path};
}

std::filesystem::path restMeshPath(const std::filesystem::path& path, const ExportFormat& format) {
    std::filesystem::path rest = path;
    switch (format.restMesh) {
    case AtPath:
        return rest;
    case AfterBasePath:
        return rest += ".obj";  // a base path: "out/fish.v2" must not lose ".v2"
    case ReplaceExtension:
        break;
    }
    return rest.replace_extension(".obj");
}

bool writesGltfJson(const std::filesystem::path& path) { return lowercase(path.extension().string()) == ".gltf"; }

std::optional<ClipExportOptions::SkinRig> skinRigNamed(std::string_view name) {
    using SkinRig = ClipExportOptions::SkinRig;
    if (name == "auto")
        return SkinRig::Auto;
    if (name == "source")
        return SkinRig::Source;
    if (name == "fitted")
        return SkinRig::Fitted;
    return std::nullopt;
}

Result<ClipExportOptions> exportOptions(const ExportFormat& format, const ExportSettings& settings) {
    if (settings.error && !format.takesError)
        return Status::error(onlyFor("--error", &ExportFormat::takesError));
    if (settings.targets && !format.takesTargets)
        return Status::error(onlyFor("--targets", &ExportFormat::takesTargets));
    if (settings.bones && !format.takesBones)
        return Status::error(onlyFor("--bones", &ExportFormat::takesBones));
    if (settings.rig && !format.takesBones)
        return Status::error(onlyFor("--rig", &ExportFormat::takesBones));
    if (settings.compress && !format.takesCompress)
        return Status::error(onlyFor("--compress", &ExportFormat::takesCompress));
    if (settings.bones && settings.error)
        return Status::error("--bones: fixes the bone count, and --error chooses it: give one");
    if (settings.bones && !(*settings.bones >= 1 && *settings.bones <= 256 && isWhole(*settings.bones)))
        return Status::error("--bones: must be a whole number in [1, 256], got " + number(*settings.bones));
    if (settings.error && !(*settings.error > 0 && *settings.error <= 0.1))
        return Status::error("--error: must be a number in (0, 0.1] (a fraction of the diagonal), got " + number(*settings.error));
    if (settings.targets && !(*settings.targets >= 2 && *settings.targets <= 256 && isWhole(*settings.targets)))
        return Status::error("--targets: must be a whole number in [2, 256] (the mean and at least one component), got " +
                             number(*settings.targets));
    ClipExportOptions options;
    options.gltfCompress = settings.compress;
    const double error = settings.error.value_or(ClipExportOptions::kDefaultCompressionError);
    if (format.takesTargets) {  // compressed morphs: the mean plus at most targets - 1 components
        options.gltfMorphError = error;
        options.gltfMaxMorphs = settings.targets ? int(*settings.targets) - 1 : 32;
    }
    if (format.takesBones) {  // skinning: a bone count, or the fewest bones within the error
        options.skinBones = settings.bones ? int(*settings.bones) : 0;
        options.skinError = settings.bones ? 0.0 : error;
        options.skinRig = settings.rig.value_or(ClipExportOptions::SkinRig::Auto);
    }
    return options;
}

}  // namespace softtouch::io
