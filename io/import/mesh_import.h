#pragma once
/// Mesh import through assimp (OBJ, FBX, glTF/GLB, PLY, STL, DAE, …): every mesh of the file, node
/// transforms applied, triangulated, identical vertices joined, concatenated in file order into one
/// core Mesh (one MeshPart per source mesh). The vertex order of every cache is this order; the
/// rest OBJ written beside a cache records it (docs/formats.md).

#include "core/geometry/mesh.h"

#include <filesystem>
#include <vector>

namespace softtouch::io {

/// Imports a mesh file. Errors name the file: missing, unreadable, unsupported, no triangles,
/// non-finite coordinates.
Result<Mesh> importMesh(const std::filesystem::path& path);

/// Whether every file of `paths` imports as importMesh() would import it, read by assimp in as few child
/// processes as it takes (up to 256 files each, a progress beat after each file): a library check reads
/// back every frame of an OBJ sequence, and a child per file spent most of its ~30 ms starting. Ok, or
/// the first file's problem.
Status checkMeshesImport(const std::vector<std::filesystem::path>& paths);

}  // namespace softtouch::io
