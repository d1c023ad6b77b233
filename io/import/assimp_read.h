#pragma once
/// How both assimp readers (io/import/mesh_import.cpp, io/import/animation_import.cpp) open a file: a packed GLB
/// (EXT_meshopt_compression: bake --compress and gltfpack write them), which assimp 5.2 cannot read, is
/// expanded in memory first (io/import/gltf_meshopt.h); anything else goes to assimp as it is.

#include <filesystem>
#include <string>

struct aiScene;
namespace Assimp {
class Importer;
}

namespace softtouch::io {

/// The scene `importer` read from `path` with post-processing `flags`, or null with `problem` set (assimp's
/// message, or what was wrong with a packed GLB).
const aiScene* readAssimpScene(Assimp::Importer& importer, const std::filesystem::path& path, unsigned flags,
                              std::string& problem);

}  // namespace softtouch::io
