#pragma once
/// GLB compression for shipping, the way game pipelines pack glTF (gltfpack): every buffer view through
/// EXT_meshopt_compression (meshoptimizer's byte codecs: lossless, decoded by three.js, Babylon.js and Unity's
/// glTFast). Two steps are lossy: the mesh's normals become 16-bit octahedral vectors (the extension's
/// OCTAHEDRAL filter on KHR_mesh_quantization's normalized shorts: under 1e-4 rad), and morph-target deltas
/// keep 16-bit mantissas (the EXPONENTIAL filter: each value within 2^-15 of itself). Nothing is reordered:
/// positions, weights, joints and animation keys decode to the bytes that went in (the triangle codec may
/// start a triangle at another corner), so the vertices stay bit-compatible with the other exports.
/// docs/formats.md, "Compressed GLB".

#include "core/result.h"

#include <cstddef>
#include <string>
#include <string_view>

namespace softtouch::io {

/// What compressGlb() did, for the export's note.
struct GlbCompression {
    std::string glb;                 ///< The compressed file.
    std::size_t viewBytes = 0;       ///< Binary data before (every buffer view), bytes.
    std::size_t packedBytes = 0;     ///< Binary data after, bytes.
    int views = 0;                   ///< Buffer views.
    int compressedViews = 0;         ///< Views stored through the extension (the rest are too small to gain).
    int octahedralNormals = 0;       ///< NORMAL attributes stored as 16-bit octahedral vectors.
    int exponentialViews = 0;        ///< Morph-target deltas stored with 16-bit mantissas.
    double largestChange = 0.0;      ///< Largest change of a morph-target delta component, in its units (metres).
};

/// Compresses a GLB whose data lies in its binary chunk (as SoftTouch's exports write them). `name` names
/// the file in errors.
Result<GlbCompression> compressGlb(std::string_view glb, const std::string& name);

/// True when the GLB's JSON lists EXT_meshopt_compression as used (false for anything else, GLB or not).
bool usesMeshoptCompression(std::string_view glb);

/// The reverse, for readers without the extensions (assimp, tinygltf, the preview's inspection): a core
/// glTF 2.0 GLB with every view decoded into the binary chunk and octahedral normals back as floats. Corrupt
/// or truncated input gets an error naming the file, the view and the problem.
Result<std::string> expandGlb(std::string_view glb, const std::string& name);

}  // namespace softtouch::io
