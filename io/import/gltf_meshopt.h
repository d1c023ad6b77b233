#pragma once
/// GLB compression for shipping, the way game pipelines pack glTF (gltfpack): every buffer view through
/// EXT_meshopt_compression (meshoptimizer's byte codecs: lossless, decoded by three.js, Babylon.js and Unity's
/// glTFast). Two steps are lossy: the mesh's normals become 16-bit octahedral vectors (the extension's
/// OCTAHEDRAL filter on KHR_mesh_quantization's normalized shorts: under 1e-4 rad), and morph-target deltas
/// keep 16-bit mantissas (the EXPONENTIAL filter: each value within 2^-15 of itself). Nothing is reordered:
/// positions, weights, joints and animation keys decode to the bytes that went in (the triangle codec may
/// start a triangle at another corner), so the vertices stay bit-compatible with the other exports.
/// docs/formats.md, "Compressed GLB".

#include "core/base/result.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace softtouch::io {

/// What compressGlb() made, and what its export's note says of the lossy steps.
struct GlbCompression {
    std::string glb;                 ///< The compressed file.
    int octahedralNormals = 0;       ///< NORMAL attributes stored as 16-bit octahedral vectors.
    double largestChange = 0.0;      ///< Largest change of a morph-target delta component, in its units (metres).
};

/// Compresses a GLB whose data lies in its binary chunk (as SoftTouch's exports write them). `name` names
/// the file in errors.
Result<GlbCompression> compressGlb(std::string_view glb, const std::string& name);

/// True when the GLB's JSON lists EXT_meshopt_compression as used (false for anything else, GLB or not).
bool usesMeshoptCompression(std::string_view glb);
/// The same for a file, from its header and JSON chunk only (a large plain GLB is not read whole to tell).
bool fileUsesMeshoptCompression(const std::filesystem::path& path);

/// The reverse, for readers without the extensions (assimp, tinygltf, the preview's inspection): a core
/// glTF 2.0 GLB with every view decoded into the binary chunk, and normals and skin weights stored as
/// normalized integers back as floats (the only form assimp 5.2 reads right). Corrupt or truncated input
/// gets an error naming the file, the view and the problem.
Result<std::string> expandGlb(std::string_view glb, const std::string& name);

}  // namespace softtouch::io
