#include "io/assimp_read.h"

#include "io/gltf_meshopt.h"
#include "io/input_file.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string_view>

namespace softtouch::io {

namespace {

/// True when `path` is binary glTF whose JSON chunk contains the extension's name (a cheap first look:
/// usesMeshoptCompression() decides on the whole file).
bool mentionsMeshopt(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    char header[20] = {};
    in.read(header, sizeof header);
    if (in.gcount() < 20 || std::string_view(header, 4) != "glTF")
        return false;
    const std::uint32_t jsonLength = std::uint32_t(std::uint8_t(header[12])) | std::uint32_t(std::uint8_t(header[13])) << 8 |
                                     std::uint32_t(std::uint8_t(header[14])) << 16 | std::uint32_t(std::uint8_t(header[15])) << 24;
    std::string json(std::min<std::uint32_t>(jsonLength, kMaxJsonFileBytes), '\0');
    in.read(json.data(), std::streamsize(json.size()));
    json.resize(std::size_t(in.gcount()));
    return json.find("EXT_meshopt_compression") != std::string::npos;
}

}  // namespace

const aiScene* readAssimpScene(Assimp::Importer& importer, const std::filesystem::path& path, unsigned flags,
                              std::string& problem) {
    // By content, as assimp itself picks its readers (io/mesh_file_check.cpp): binary glTF whatever the name.
    // Only a JSON chunk that names the extension makes the whole file worth reading here (a large plain GLB
    // goes to assimp without a copy in memory first).
    if (mentionsMeshopt(path)) {
        auto bytes = readInputFile(path, kMaxMeshFileBytes);
        if (bytes && usesMeshoptCompression(bytes.value())) {
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
