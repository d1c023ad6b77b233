#include "io/import/isolated_import.h"
#include "io/import/mesh_import.h"

#include "io/import/assimp_read.h"

#include "io/files/input_file.h"
#include "io/import/mesh_file_check.h"
#include "io/import/scene_units.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
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


/// The child's end of its progress pipe (reportImportProgress); -1 in any process that is not an importer child.
int progressFd = -1;

/// How an importer child exits when it could not send its answer, and when `produce` threw.
constexpr int kChildCouldNotSend = 3;
constexpr int kChildThrew = 4;

/// In the child: says why `produce` threw, on the error pipe (its stderr), and exits. Only write(2): after a
/// std::bad_alloc, building a message could throw again.
[[noreturn]] void childThrew(const char* cause) {
    (void)!::write(STDERR_FILENO, "\n", 1);
    (void)!::write(STDERR_FILENO, cause, std::strlen(cause));
    (void)!::write(STDERR_FILENO, "\n", 1);
    ::_exit(kChildThrew);
}

/// Keeps what the child printed to its first and last 64 KiB: the first line says why assimp aborted, the last
/// why `produce` threw, and a child that prints without end must not fill this process's memory.
void keepEnds(std::string& text) {
    constexpr std::size_t kEnd = 64 << 10;
    if (text.size() > 3 * kEnd)
        text.erase(kEnd, text.size() - 2 * kEnd);
}

/// The first line of what the child printed (assimp's ai_assert before an abort), or its last (the cause
/// childThrew() printed after whatever came before), at most 200 characters.
std::string childSaid(const std::string& errors, bool last) {
    std::string text = errors;
    while (!text.empty() && text.back() == '\n')
        text.pop_back();
    const std::size_t from = last ? (text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1) : 0;
    const std::size_t to = std::min(text.find('\n', from), text.size());
    return text.substr(from, std::min<std::size_t>(to - from, 200));
}

}  // namespace

void reportImportProgress() {
    if (progressFd < 0)
        return;
    // At most ten a second: the parent only needs a sign of life well within its idle window.
    static std::chrono::steady_clock::time_point last;
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::milliseconds(100))
        return;
    last = now;
    const char beat = 1;
    (void)!::write(progressFd, &beat, 1);
}

Result<std::string> runIsolated(const std::filesystem::path& path, const std::string& name,
                                const std::function<std::string()>& produce, double idleSeconds) {
    int fds[2], errs[2], beats[2];
    if (::pipe2(fds, O_CLOEXEC) != 0)
        return produce();  // no pipe: read in this process rather than not at all
    if (::pipe2(errs, O_CLOEXEC) != 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        return produce();
    }
    if (::pipe2(beats, O_CLOEXEC) != 0) {
        for (int fd : {fds[0], fds[1], errs[0], errs[1]})
            ::close(fd);
        return produce();
    }
    std::fflush(nullptr);
    const pid_t child = ::fork();
    if (child < 0) {
        for (int fd : {fds[0], fds[1], errs[0], errs[1], beats[0], beats[1]})
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
        ::close(beats[0]);
        progressFd = beats[1];
        // An exception (std::bad_alloc, std::length_error, …) would end the child in std::terminate, which
        // the parent could only report as a crash: its cause goes back instead.
        std::string bytes;
        try {
            bytes = produce();
        } catch (const std::exception& e) {
            childThrew(e.what());
        } catch (...) {
            childThrew("an exception that is not a std::exception");
        }
        for (std::size_t done = 0; done < bytes.size();) {
            const ssize_t n = ::write(fds[1], bytes.data() + done, bytes.size() - done);
            if (n <= 0)
                ::_exit(kChildCouldNotSend);
            done += std::size_t(n);
        }
        ::_exit(0);
    }
    ::close(fds[1]);
    ::close(errs[1]);
    ::close(beats[1]);
    // Every pipe at once: a child that fills one while the parent waits on another would hang. And a
    // watchdog: a child that shows no sign of life (its answer's bytes, its progress beats) for the idle
    // window is taken for hung and killed (forking a threaded process can, in principle, leave a lock held in
    // the child; assimp has looped on malformed headers), and none runs past the overall bound. A long import
    // that keeps reporting progress (an animation's samples) is not stopped for being long: before, every
    // import was stopped 10 s after it started, and 3,601 samples of the rigged guppy, 6 s under ASan here,
    // were stopped on a slower machine.
    std::error_code sizeError;
    const auto megabytes = std::filesystem::file_size(path, sizeError) >> 20;
    const auto perFile = std::chrono::milliseconds(100 * megabytes);
    const auto idle = std::chrono::milliseconds(std::int64_t(idleSeconds * 1000)) + perFile;
    const auto started = std::chrono::steady_clock::now();
    const auto mostUntil = started + std::chrono::milliseconds(std::int64_t(kImportMostSeconds * 1000)) + perFile;
    auto quietUntil = started + idle;
    std::string bytes, errors;
    char chunk[1 << 16];
    pollfd open[3] = {{fds[0], POLLIN, 0}, {errs[0], POLLIN, 0}, {beats[0], POLLIN, 0}};
    enum class Stopped { No, Idle, TooLong } stopped = Stopped::No;
    while (open[0].fd >= 0 || open[1].fd >= 0 || open[2].fd >= 0) {
        const auto until = std::min(quietUntil, mostUntil);
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
        const int ready = left.count() > 0 ? ::poll(open, 3, int(left.count())) : 0;
        if (ready == 0) {
            stopped = until == mostUntil ? Stopped::TooLong : Stopped::Idle;
            ::kill(child, SIGKILL);
            break;
        }
        if (ready < 0) {
            if (errno == EINTR)
                continue;
            break;
        }
        for (int i = 0; i < 3; ++i) {
            if (open[i].fd < 0 || open[i].revents == 0)
                continue;
            const ssize_t n = ::read(open[i].fd, chunk, sizeof chunk);
            if (n > 0) {
                if (i == 0)
                    bytes.append(chunk, std::size_t(n));
                if (i == 1) {
                    errors.append(chunk, std::size_t(n));
                    keepEnds(errors);
                }
                // Its answer and its beats are progress; what it prints is not (assimp looping on a malformed
                // file may warn each time round).
                if (i != 1)
                    quietUntil = std::chrono::steady_clock::now() + idle;
            } else if (n == 0 || errno != EINTR) {
                open[i].fd = -1;
            }
        }
    }
    for (int fd : {fds[0], errs[0], beats[0]})
        ::close(fd);
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    auto seconds = [](std::chrono::milliseconds ms) { return std::to_string((ms.count() + 500) / 1000); };
    if (stopped == Stopped::Idle)
        return Status::error("cannot read mesh " + name + ": the importer (assimp) showed no progress for " +
                             seconds(idle) + " s and was stopped");
    if (stopped == Stopped::TooLong)
        return Status::error("cannot read mesh " + name + ": the importer (assimp) did not finish within " +
                             seconds(std::chrono::duration_cast<std::chrono::milliseconds>(mostUntil - started)) +
                             " s and was stopped");
    if (WIFSIGNALED(status)) {
        const std::string said = childSaid(errors, false);
        return Status::error("cannot read mesh " + name + ": the importer (assimp) crashed on it (signal " +
                             std::to_string(WTERMSIG(status)) + (said.empty() ? "" : ": " + said) +
                             "); the file is corrupt or in a form assimp cannot read");
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == kChildThrew)
        return Status::error("cannot read mesh " + name + ": the importer failed: " + childSaid(errors, true));
    if (WIFEXITED(status) && WEXITSTATUS(status) == kChildCouldNotSend)
        return Status::error("cannot read mesh " + name + ": the importer could not send back what it read (" +
                             std::to_string(bytes.size()) + " bytes arrived)");
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

Status checkMeshesImport(const std::vector<std::filesystem::path>& paths) {
    constexpr std::size_t kFilesPerChild = 256;  // each file restarts the idle watchdog; the cap stays far off
    for (const std::filesystem::path& path : paths)
        if (Status s = checkMeshFile(path, "'" + path.string() + "'"); !s)
            return s;
    for (std::size_t first = 0; first < paths.size(); first += kFilesPerChild) {
        const std::size_t last = std::min(paths.size(), first + kFilesPerChild);
        const std::string name = "'" + paths[first].string() + "'" + (last - first > 1 ? " and the next files" : "");
        auto bytes = runIsolated(paths[first], name, [&] {
            for (std::size_t i = first; i < last; ++i) {
                auto mesh = readWithAssimp(paths[i], "'" + paths[i].string() + "'");
                if (!mesh)
                    return encodeResult(Result<std::uint8_t>(mesh.status()), [](std::string&, std::uint8_t) {});
                reportImportProgress();
            }
            return encodeResult(Result<std::uint8_t>(std::uint8_t(1)), [](std::string& out, std::uint8_t v) { put(out, v); });
        });
        if (!bytes)
            return bytes.status();
        const auto decoded =
            decodeResult<std::uint8_t>(bytes.value(), [](Decoder& in, std::uint8_t& v) { return in.get(v); });
        if (!decoded)
            return Status::error("cannot read mesh " + name + ": the importer (assimp) failed (its answer was cut short)");
        if (!decoded->ok())
            return decoded->status();
    }
    return Status::success();
}

}  // namespace softtouch::io
