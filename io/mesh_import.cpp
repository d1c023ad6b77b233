#include "io/mesh_import.h"
#include "io/isolated_import.h"

#include "io/assimp_read.h"

#include "io/input_file.h"
#include "io/mesh_file_check.h"
#include "io/scene_units.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <functional>
#include <optional>
#include <system_error>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

namespace softtouch::io {

namespace {

/// The import itself: assimp, then SoftTouch's clean-up of what it gives.
Result<Mesh> readWithAssimp(const std::filesystem::path& path, const std::string& name) {
    Assimp::Importer importer;
    // Points and lines are of no use to a deformer: drop them instead of failing on them.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices |
                           aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    std::string problem;
    const aiScene* scene = readAssimpScene(importer, path, flags, problem);
    if (!scene)
        return Status::error("cannot read mesh " + name + ": " + problem);

    Mesh mesh;
    bool allHaveNormals = true;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* src = scene->mMeshes[m];
        if (!(src->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || src->mNumFaces == 0)
            continue;
        const auto base = std::uint32_t(mesh.positions.size());
        MeshPart part;
        part.name = src->mName.C_Str();
        part.firstVertex = base;
        part.vertexCount = src->mNumVertices;
        allHaveNormals = allHaveNormals && src->HasNormals();
        for (unsigned v = 0; v < src->mNumVertices; ++v) {
            const aiVector3D& p = src->mVertices[v];
            mesh.positions.emplace_back(p.x, p.y, p.z);
            if (src->HasNormals()) {
                const aiVector3D& n = src->mNormals[v];
                mesh.normals.emplace_back(n.x, n.y, n.z);
            }
        }
        for (unsigned f = 0; f < src->mNumFaces; ++f) {
            const aiFace& face = src->mFaces[f];
            if (face.mNumIndices != 3)
                continue;
            mesh.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
        }
        mesh.parts.push_back(part);
    }
    if (mesh.triangles.empty())
        return Status::error("mesh file " + name + " has no triangles");
    // In metres, whatever unit the file is in (an FBX in centimetres would otherwise come in 100x too large).
    const SceneUnit unit = sceneUnit(*scene, path.string());
    if (unit.metresPerUnit != 1.0)
        for (Vec3f& p : mesh.positions)
            p *= float(unit.metresPerUnit);
    if (!allHaveNormals)
        mesh.computeNormals();
    else {
        // Normalise imported normals; a zero normal (degenerate) is replaced from the faces.
        bool zero = false;
        for (Vec3f& n : mesh.normals) {
            const float len = n.norm();
            if (!(len > 0.0f) || !std::isfinite(len))
                zero = true;
            else
                n /= len;
        }
        if (zero)
            mesh.computeNormals();
    }
    if (Status s = mesh.validate(); !s)
        return Status::error("mesh file " + name + ": " + s.message());
    return mesh;
}


}  // namespace

Result<std::string> runIsolated(const std::filesystem::path& path, const std::string& name,
                                const std::function<std::string()>& produce) {
    int fds[2], errs[2];
    if (::pipe2(fds, O_CLOEXEC) != 0)
        return produce();  // no pipe: read in this process rather than not at all
    if (::pipe2(errs, O_CLOEXEC) != 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        return produce();
    }
    std::fflush(nullptr);
    const pid_t child = ::fork();
    if (child < 0) {
        for (int fd : {fds[0], fds[1], errs[0], errs[1]})
            ::close(fd);
        return produce();
    }
    if (child == 0) {
        // A crash in the child must end the child and nothing else: handlers inherited from the parent
        // (a crash reporter; under the fuzzer, libFuzzer's, which would file the child's crash as the
        // parent's finding) are put back to the default, so the parent sees the signal and reports it.
        for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT})
            ::signal(sig, SIG_DFL);
        // What assimp prints before it aborts ("ai_assert failure in …") goes to the parent's message.
        ::dup2(errs[1], STDERR_FILENO);
        ::close(fds[0]);
        ::close(errs[0]);
        const std::string bytes = produce();
        for (std::size_t done = 0; done < bytes.size();) {
            const ssize_t n = ::write(fds[1], bytes.data() + done, bytes.size() - done);
            if (n <= 0)
                ::_exit(3);
            done += std::size_t(n);
        }
        ::_exit(0);
    }
    ::close(fds[1]);
    ::close(errs[1]);
    // Both pipes at once: a child that fills one while the parent waits on the other would hang. And a
    // deadline: a child that never finishes (forking a threaded process can, in principle, leave a lock
    // held in the child) is killed, so an import never hangs: 10 s, plus 0.1 s per MiB of file.
    std::error_code sizeError;
    const auto megabytes = std::filesystem::file_size(path, sizeError) >> 20;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(10000 + 100 * megabytes);
    std::string bytes, errors;
    char chunk[1 << 16];
    pollfd open[2] = {{fds[0], POLLIN, 0}, {errs[0], POLLIN, 0}};
    bool late = false;
    while (open[0].fd >= 0 || open[1].fd >= 0) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        const int ready = left.count() > 0 ? ::poll(open, 2, int(left.count())) : 0;
        if (ready == 0) {
            late = true;
            ::kill(child, SIGKILL);
            break;
        }
        if (ready < 0) {
            if (errno == EINTR)
                continue;
            break;
        }
        for (int i = 0; i < 2; ++i) {
            if (open[i].fd < 0 || open[i].revents == 0)
                continue;
            const ssize_t n = ::read(open[i].fd, chunk, sizeof chunk);
            if (n > 0)
                (i == 0 ? bytes : errors).append(chunk, std::size_t(n));
            else if (n == 0 || errno != EINTR)
                open[i].fd = -1;
        }
    }
    ::close(fds[0]);
    ::close(errs[0]);
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    if (late)
        return Status::error("cannot read mesh " + name + ": the importer (assimp) did not finish within " +
                             std::to_string(10 + megabytes / 10) + " s and was stopped");
    const std::string said = errors.substr(0, std::min(errors.find('\n'), std::size_t(200)));
    if (WIFSIGNALED(status))
        return Status::error("cannot read mesh " + name + ": the importer (assimp) crashed on it (signal " +
                             std::to_string(WTERMSIG(status)) + (said.empty() ? "" : ": " + said) +
                             "); the file is corrupt or in a form assimp cannot read");
    if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0))
        return Status::error("cannot read mesh " + name + ": the importer (assimp) failed on it (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                             "); the file is corrupt or in a form assimp cannot read");
    return bytes;
}

Status checkMeshFile(const std::filesystem::path& path, const std::string& name) {
    if (Status s = checkInputFile(path, kMaxMeshFileBytes); !s)
        return Status::error("mesh file " + name + " " + s.message());
    std::error_code ec;
    if (std::filesystem::file_size(path, ec) == 0)
        return Status::error("mesh file " + name + " is empty (0 bytes)");
    if (Status s = checkMeshFileIsWhole(path); !s)
        return Status::error("mesh file " + name + ": " + s.message());
    return Status::success();
}

Result<Mesh> importMesh(const std::filesystem::path& path) {
    return importIsolated<Mesh>(
        path, [&](const std::string& name) { return readWithAssimp(path, name); }, putMesh, getMesh);
}

}  // namespace softtouch::io
