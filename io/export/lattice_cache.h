#pragma once
/// The lattice cache: a clip stored as what drives it. The mesh is linear in the lattice nodes,
///   x(u,v,w) = sum_ijk P_ijk(t) N_i(u) N_j(v) N_k(w),
/// so a clip is the rest mesh with each vertex's (u,v,w) (<base>.lattice.glb) plus the node
/// positions per frame (<base>.lattice.bin: a JSON header, then float32 nodes). A vertex shader
/// (io/shaders/lattice_deform.glsl, .hlsl) reproduces the deformation from these alone.
/// Layout: docs/formats.md, "Lattice cache".

#include "core/base/result.h"
#include "core/base/types.h"
#include "core/geometry/lattice.h"

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace softtouch::io {

/// Signature at offset 0 of a .lattice.bin file.
inline constexpr char kLatticeCacheSignature[8] = {'S', 'T', 'L', 'A', 'T', 'C', '\r', '\n'};

/// One object's lattice as stored in the header.
struct LatticeCacheObject {
    std::string name;                       ///< Object name.
    std::uint32_t firstVertex = 0;          ///< First vertex in the cache's vertex order.
    std::uint32_t vertexCount = 0;          ///< Vertices of the object.
    LatticeKind kind = LatticeKind::Bezier; ///< Basis kind.
    std::array<int, 3> nodes{};             ///< Nodes per axis, >= 2.
    std::array<int, 3> degrees{};           ///< Polynomial degree per axis, 1..7.
    std::array<std::vector<double>, 3> knots; ///< Clamped knot vector per axis (nodes + degree + 1 values in [0,1]).
    OrientedBox box;                        ///< Rest box: (u,v,w) = box.toParameters(rest position).
    /// Nodes of this object in one frame.
    int nodeCount() const { return nodes[0] * nodes[1] * nodes[2]; }
};

/// A lattice cache read back (tests, tools).
struct LatticeCache {
    double fps = 0.0;                         ///< Frames per second, > 0.
    std::size_t frameCount = 0;               ///< Frames.
    std::string mesh;                         ///< File name of the mesh (beside the .bin).
    std::size_t nodeDataOffset = 0;           ///< Byte where the frames' nodes start (12 + headerBytes).
    std::vector<LatticeCacheObject> objects;  ///< Objects in vertex order.
    /// frames[f] holds every object's nodes in order (object 0's nodes first; within an object
    /// index = i + nx*(j + ny*k)), metres.
    std::vector<std::vector<Vec3f>> frames;
};

/// Reads a .lattice.bin; errors name the file and the field (JSON pointer) or byte range at fault.
Result<LatticeCache> readLatticeCache(const std::filesystem::path& path);

}  // namespace softtouch::io
