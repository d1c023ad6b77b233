#pragma once
/// Mesh import through assimp (OBJ, FBX, glTF/GLB, PLY, STL, DAE, …): every mesh of the file, node
/// transforms applied, triangulated, identical vertices joined, concatenated in file order into one
/// core Mesh (one MeshPart per source mesh). The vertex order of every cache is this order; the
/// rest OBJ written beside a cache records it (docs/formats.md).

#include "core/mesh.h"

#include <filesystem>

namespace softtouch::io {

/// Imports a mesh file. Errors name the file: missing, unreadable, unsupported, no triangles,
/// non-finite coordinates.
Result<Mesh> importMesh(const std::filesystem::path& path);

}  // namespace softtouch::io
