#include "io/import/assimp_read.h"

#include "io/files/input_file.h"
#include "io/import/gltf_meshopt.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <string>
#include <system_error>
#include <vector>

namespace softtouch::io {

namespace {

namespace fs = std::filesystem;

/// assimp's file access, held to the mesh's own folder: the files a mesh names beside it (an OBJ's
/// mtllib, a glTF's buffers, whatever else its format lets it name) are read only from that folder and below, and
/// only when they are regular files. Otherwise a shared mesh could name ../../home/x/.ssh/id_rsa or
/// /dev/zero as a buffer, and its bytes would become geometry in a bake (docs/design/reliability.md,
/// "Confinement"). What is refused is kept, for the message when the read then fails.
class ConfinedIOSystem : public Assimp::DefaultIOSystem {
public:
    explicit ConfinedIOSystem(fs::path folder) : m_folder(std::move(folder)) {}

    bool Exists(const char* file) const override { return allowed(file) && DefaultIOSystem::Exists(file); }

    Assimp::IOStream* Open(const char* file, const char* mode = "rb") override {
        if (std::string(mode).find_first_of("wa+") != std::string::npos || !allowed(file)) {
            m_refused.push_back(file);
            return nullptr;
        }
        return DefaultIOSystem::Open(file, mode);
    }

    const std::vector<std::string>& refused() const { return m_refused; }

private:
    bool allowed(const char* file) const {
        std::error_code ec;
        const fs::path resolved = fs::weakly_canonical(fs::absolute(fs::path(file), ec), ec);
        if (ec)
            return false;
        if (!liesInside(resolved, m_folder))
            return false;
        const auto status = fs::status(resolved, ec);  // a missing file is assimp's to report
        return ec || !fs::exists(status) || fs::is_regular_file(status);
    }

    fs::path m_folder;
    mutable std::vector<std::string> m_refused;
};

}  // namespace

const aiScene* readAssimpScene(Assimp::Importer& importer, const std::filesystem::path& path, unsigned flags,
                              std::string& problem) {
    std::error_code ec;
    auto* io = new ConfinedIOSystem(fs::weakly_canonical(fs::absolute(path).parent_path(), ec));
    importer.SetIOHandler(io);  // the importer owns it
    const auto explain = [&] {
        problem = importer.GetErrorString();
        if (!io->refused().empty())
            problem += " (the file names '" + io->refused().front() +
                       "', which is not a regular file in the mesh's folder or below it; SoftTouch reads a mesh's "
                       "side files from there only)";
    };
    // By content, as assimp itself picks its readers (io/import/mesh_file_check.cpp): binary glTF whatever the name.
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
                explain();
            return scene;
        }
    }
    const aiScene* scene = importer.ReadFile(path.string(), flags);
    if (!scene)
        explain();
    return scene;
}

}  // namespace softtouch::io
