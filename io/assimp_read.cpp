#include "io/assimp_read.h"

#include "io/gltf_meshopt.h"
#include "io/input_file.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

namespace softtouch::io {

const aiScene* readAssimpScene(Assimp::Importer& importer, const std::filesystem::path& path, unsigned flags,
                              std::string& problem) {
    // By content, as assimp itself picks its readers (io/mesh_file_check.cpp): binary glTF whatever the name.
    // Only a packed one is read whole here; a large plain GLB goes to assimp without a copy in memory first.
    if (fileUsesMeshoptCompression(path)) {
        auto bytes = readInputFile(path, kMaxMeshFileBytes);
        if (bytes) {
            auto expanded = expandGlb(bytes.value(), path.string());
            if (!expanded) {
                problem = expanded.message();
                return nullptr;
            }
            // assimp keeps what it needs: the buffer may go once the scene is read.
            const aiScene* scene = importer.ReadFileFromMemory(expanded.value().data(), expanded.value().size(), flags, "glb");
            if (!scene)
                problem = importer.GetErrorString();
            return scene;
        }
    }
    const aiScene* scene = importer.ReadFile(path.string(), flags);
    if (!scene)
        problem = importer.GetErrorString();
    return scene;
}

}  // namespace softtouch::io
