#pragma once
/// Reading an outside file in a child process, and the bytes the child sends back. Debian's assimp 5.2
/// aborts, or reads past its buffers, on some corrupt files; in a child that crash becomes an error
/// message instead of taking the editor, and the user's unsaved work, with it (io/import/mesh_import.cpp).

#include "core/base/result.h"
#include "core/geometry/mesh.h"
#include "io/import/animation_import.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace softtouch::io {

/// Seconds an importer child may go without a sign of life (its answer's bytes, or reportImportProgress())
/// before it is taken for hung and stopped: assimp's read gives none, and reading a file takes longer the
/// larger it is, so this grows by 0.1 s per MiB of the file.
inline constexpr double kImportIdleSeconds = 10.0;
/// Seconds an importer child may run in all, however steadily it reports progress (plus 0.1 s per MiB of
/// the file). The importers' own limits keep what they accept well inside it: the largest animated imports
/// accepted (io/import/animation_import.h: 31 million positions of the rigged guppy; 256 million blend-shape
/// operations) took 2.1 s and 0.4 s in release, 8.1 s and 4.9 s under ASan + UBSan, on a busy 2-core machine.
inline constexpr double kImportMostSeconds = 120.0;

/// Runs `produce` in a forked child process and returns the bytes it made. The child is stopped when it shows no
/// sign of life for `idleSeconds` (an import hung in a lock or a loop), or runs past kImportMostSeconds.
/// A crash, a hang, an exception or another failure of the child is an error naming `name` and the cause
/// ("cannot read mesh NAME: …"). Where no child can be started, `produce` runs in this process. The imports go
/// through runImport(); this is for a test of the watchdog itself, which may give a shorter window.
Result<std::string> runIsolated(const std::filesystem::path& path, const std::string& name,
                                const std::function<std::string()>& produce, double idleSeconds = kImportIdleSeconds);

/// One import, as the importer's child is asked for it.
struct ImportRequest {
    enum class Kind : std::uint8_t {
        Mesh = 1,       ///< importMesh(paths[0]).
        Animated,       ///< importAnimatedMesh(paths[0], animation).
        Takes,          ///< animationTakes(paths[0]).
        SourceRig,      ///< importSourceRig(paths[0], take, takeSeconds).
        CheckMeshes,    ///< Whether every one of `paths` imports as a mesh.
    };
    Kind kind = Kind::Mesh;
    std::vector<std::filesystem::path> paths;  ///< At least one.
    AnimationRequest animation;                ///< Animated.
    std::string take;                          ///< SourceRig.
    std::vector<double> takeSeconds;           ///< SourceRig.
};

/// The importer program, started for each import where it is found beside the running program.
inline constexpr const char* kImporterProgramName = "softtouch-import";
/// Its path beside the running program; empty where it is not there (a fuzz build), and the import forks.
std::filesystem::path importerProgram();

/// Runs `request` in a child process, as runIsolated() describes: the importer program when there is one
/// (started with posix_spawn, so it begins with a single thread whatever this process runs), else a fork() of
/// this process. Returns the bytes of its answer (answerImportRequest()).
Result<std::string> runImport(const ImportRequest& request, const std::string& name);

/// What the child sends back for `request`: the import's result, encoded (encodeResult()). Runs in the child.
std::string answerImportRequest(const ImportRequest& request);
/// A request as bytes for the importer program's stdin, and back; nullopt when the bytes are not one.
std::string encodeImportRequest(const ImportRequest& request);
std::optional<ImportRequest> decodeImportRequest(const std::string& bytes);

/// The importer program's main: reads a request on stdin, beats on fd 3, answers on stdout, and exits as a
/// forked child would (app/softtouch_import.cpp).
int importerMain();

/// Tells the parent that the import running in this child is making progress (one sample of an animation
/// done), so a long, legitimate import is not taken for a hung one. Cheap enough to call often: it writes at
/// most one byte every 0.1 s. Does nothing outside an importer child.
void reportImportProgress();

/// Appends a value's bytes.
template <typename T>
void put(std::string& out, const T& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}
template <typename T>
void putVector(std::string& out, const std::vector<T>& values) {
    put(out, std::uint64_t(values.size()));
    out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

/// Reads back what put() and putVector() wrote; every read says whether the bytes held it.
class Decoder {
public:
    explicit Decoder(const std::string& bytes) : m_bytes(bytes) {}
    template <typename T>
    bool get(T& value) {
        if (m_bytes.size() - m_at < sizeof value)
            return false;
        std::memcpy(&value, m_bytes.data() + m_at, sizeof value);
        m_at += sizeof value;
        return true;
    }
    bool getBytes(std::string& out) {
        std::uint64_t n = 0;
        if (!get(n) || m_bytes.size() - m_at < n)
            return false;
        out.assign(m_bytes.data() + m_at, std::size_t(n));
        m_at += std::size_t(n);
        return true;
    }
    template <typename T>
    bool getVector(std::vector<T>& values) {
        std::uint64_t n = 0;
        if (!get(n) || (m_bytes.size() - m_at) / sizeof(T) < n)
            return false;
        values.resize(std::size_t(n));
        if (n != 0)  // an empty vector's data() may be null, which memcpy must not be given
            std::memcpy(static_cast<void*>(values.data()), m_bytes.data() + m_at, std::size_t(n) * sizeof(T));
        m_at += std::size_t(n) * sizeof(T);
        return true;
    }

private:
    const std::string& m_bytes;
    std::size_t m_at = 0;
};

/// A string, and a mesh (positions, normals, triangles, parts), as bytes; getMesh reads them back.
inline void putString(std::string& out, const std::string& text) {
    put(out, std::uint64_t(text.size()));
    out += text;
}
inline void putMesh(std::string& out, const Mesh& mesh) {
    putVector(out, mesh.positions);
    putVector(out, mesh.normals);
    putVector(out, mesh.triangles);
    put(out, std::uint64_t(mesh.parts.size()));
    for (const MeshPart& part : mesh.parts) {
        putString(out, part.name);
        put(out, part.firstVertex);
        put(out, part.vertexCount);
    }
}
inline bool getMesh(Decoder& in, Mesh& mesh) {
    std::uint64_t parts = 0;
    if (!in.getVector(mesh.positions) || !in.getVector(mesh.normals) || !in.getVector(mesh.triangles) || !in.get(parts))
        return false;
    for (std::uint64_t i = 0; i < parts; ++i) {
        MeshPart part;
        if (!in.getBytes(part.name) || !in.get(part.firstVertex) || !in.get(part.vertexCount))
            return false;
        mesh.parts.push_back(std::move(part));
    }
    return true;
}

/// What a child sends back: a failure's message, or what `putValue(out, value)` writes.
template <typename T, typename Put>
std::string encodeResult(const Result<T>& result, Put&& putValue) {
    std::string out;
    put(out, std::uint8_t(result.ok()));
    if (!result.ok())
        putString(out, result.message());
    else
        putValue(out, result.value());
    return out;
}
/// Reads what encodeResult wrote with `getValue(decoder, value)`; nullopt when the bytes are cut short.
template <typename T, typename Get>
std::optional<Result<T>> decodeResult(const std::string& bytes, Get&& getValue) {
    Decoder in(bytes);
    std::uint8_t ok = 0;
    if (!in.get(ok))
        return std::nullopt;
    if (!ok) {
        std::string message;
        if (!in.getBytes(message))
            return std::nullopt;
        return Result<T>(Status::error(message));
    }
    T value;
    if (!getValue(in, value))
        return std::nullopt;
    return Result<T>(std::move(value));
}

/// Checks `path` as a mesh file (a regular file within the size limit, not empty, its header against its
/// body), naming it `name` in errors.
Status checkMeshFile(const std::filesystem::path& path, const std::string& name);

/// Runs `request` in a child process (runImport()): its files checked first, its answer read with
/// `getValue`. Every error names the file.
template <typename T, typename Get>
Result<T> importIsolated(const ImportRequest& request, Get&& getValue) {
    const std::string name = "'" + request.paths.front().string() + "'";
    if (Status s = checkMeshFile(request.paths.front(), name); !s)
        return s;
    auto bytes = runImport(request, name);
    if (!bytes)
        return bytes.status();
    auto decoded = decodeResult<T>(bytes.value(), getValue);
    if (!decoded)
        return Status::error("cannot read mesh " + name + ": the importer (assimp) failed on it (its answer was cut "
                             "short); the file is corrupt or in a form assimp cannot read");
    return std::move(*decoded);
}

/// What each kind of request answers, in the child (the readers live beside their public functions).
std::string answerMesh(const std::filesystem::path& path, const std::string& name);
std::string answerMeshesCheck(const std::vector<std::filesystem::path>& paths);
std::string answerAnimated(const std::filesystem::path& path, const std::string& name, const AnimationRequest& request);
std::string answerTakes(const std::filesystem::path& path, const std::string& name);
std::string answerSourceRig(const std::filesystem::path& path, const std::string& name, const std::string& take,
                            const std::vector<double>& takeSeconds);
/// Reads what answerAnimated(), answerTakes() and answerSourceRig() send (animation_import.cpp).
bool getAnimated(Decoder& in, AnimatedMesh& a);
bool getTakes(Decoder& in, TakeList& takes);
bool getSourceRig(Decoder& in, SourceRig& rig);

}  // namespace softtouch::io
