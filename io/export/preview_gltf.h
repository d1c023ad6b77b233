#pragma once
/// The preview's glTF reader (`softtouch-cli preview`, io/pipeline/clip_preview.h). A clip given to the preview may
/// come from anyone, and the page it makes is shared, so the reader holds the glTF to two rules
/// (docs/design/reliability.md, "The preview page"):
///  - every file the glTF names (a buffer's or an image's URI) is a regular file inside the glTF's own folder
///    or a folder below it; nothing else is read, and so nothing else is embedded in the page;
///  - the glTF is one three.js's GLTFLoader plays: what it indexes exists, its data lies inside its buffers,
///    its nodes form trees and it requires no extension the page cannot decode.
/// Internal to io: it hands out tinygltf's model.

#include "core/base/result.h"
#include "io/files/input_file.h"

#include <tiny_gltf.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace softtouch::io {

/// The most the page embeds of one file, and of all the files a glTF names together: a page of this size is
/// already slow to open in a browser.
inline constexpr std::uintmax_t kMaxPreviewFileBytes = 512 * kMiB;

/// A URI as tinygltf reads it: '%' and two hex digits become that byte (a digit that is not hex counts as 0),
/// '+' a space.
std::string decodeGltfUri(std::string_view uri);

/// The folder of a clip's file (`path`), as `std::filesystem::weakly_canonical` gives it: where the
/// files it names must lie (resolveClipFile).
Result<std::filesystem::path> clipFolder(const std::filesystem::path& path);

/// A file a clip names (a glTF's buffer or image, a VAT's texture or mesh, a lattice cache's mesh):
/// `relative` (for a glTF, its URI through decodeGltfUri) in `folder`, the clipFolder of the file that
/// names it. Accepted only when it is a relative path that, links and ".." resolved, stays inside `folder`
/// or a folder below it and names a regular file of at most kMaxPreviewFileBytes. The path returned is
/// its folder, canonical, and its own name as `relative` gives it (a link keeps its name: the page finds
/// files by name). Errors follow the name: "leads outside the clip's folder …", "is an absolute path …",
/// "is not a regular file (a FIFO)", "does not exist".
Result<std::filesystem::path> resolveClipFile(const std::filesystem::path& folder, const std::string& relative);

/// Reads a .gltf or .glb (by its extension; a packed GLB is decoded first, io/import/gltf_meshopt.h) for the preview:
/// its JSON at most kMaxJsonDepth deep and without repeated keys, every buffer and image URI through
/// resolveClipFile (tinygltf reads only through it, and decodes no image), then checkPlayableGltf.
/// Errors name the file, the JSON pointer ("/buffers/0/uri") and the reason.
Result<tinygltf::Model> readPreviewGltf(const std::filesystem::path& path);

/// Ok when three.js's GLTFLoader (web/node_modules/three, r187) can play `model`; else the first problem,
/// after `path` and a JSON pointer:
///  - every index (a view's buffer, an accessor's view, a primitive's accessors and material, a node's
///    mesh, skin, camera and children, a skin's joints, an animation's accessors, sampler and node, a
///    scene's nodes, a texture's image and sampler, a material's textures) names something that exists;
///  - every bufferView lies inside its buffer (tinygltf already holds each buffer's data to its byteLength),
///    and every accessor's count elements (each its type's size, byteStride apart) from its byteOffset inside
///    its view, sparse indices and values too; an accessor without a view (three.js fills it with zeros) is
///    at most kMaxPreviewFileBytes;
///  - the nodes form a forest: no node is the child of two nodes or its own ancestor, and a scene's nodes
///    are roots;
///  - extensionsRequired lists only extensions the page plays: GLTFLoader's own, less Draco and KTX2/Basis
///    (the page loads no decoder for them). EXT_meshopt_compression and KHR_mesh_quantization, which
///    `bake --compress` requires, are among them.
Status checkPlayableGltf(const tinygltf::Model& model, const std::filesystem::path& path);

}  // namespace softtouch::io
