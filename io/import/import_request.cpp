// An import request as the importer's child gets it (io/import/isolated_import.h): bytes for the importer
// program's stdin, and the dispatch to the reader that answers it.

#include "io/import/isolated_import.h"

namespace softtouch::io {

namespace {

/// Marks the bytes as a request of this build's layout: a program of another build refuses them.
constexpr std::uint32_t kRequestMagic = 0x53544931;  // "STI1"

}  // namespace

std::string encodeImportRequest(const ImportRequest& request) {
    std::string out;
    put(out, kRequestMagic);
    put(out, request.kind);
    put(out, std::uint64_t(request.paths.size()));
    for (const std::filesystem::path& path : request.paths)
        putString(out, path.string());
    putString(out, request.animation.take);
    put(out, request.animation.start);
    put(out, request.animation.end);
    put(out, request.animation.rate);
    put(out, std::uint8_t(request.animation.loop));
    putString(out, request.take);
    putVector(out, request.takeSeconds);
    return out;
}

std::optional<ImportRequest> decodeImportRequest(const std::string& bytes) {
    Decoder in(bytes);
    ImportRequest request;
    std::uint32_t magic = 0;
    std::uint64_t paths = 0;
    std::uint8_t loop = 0;
    if (!in.get(magic) || magic != kRequestMagic || !in.get(request.kind) || !in.get(paths) || paths == 0 ||
        paths > bytes.size())
        return std::nullopt;
    for (std::uint64_t i = 0; i < paths; ++i) {
        std::string path;
        if (!in.getBytes(path))
            return std::nullopt;
        request.paths.emplace_back(path);
    }
    if (!in.getBytes(request.animation.take) || !in.get(request.animation.start) || !in.get(request.animation.end) ||
        !in.get(request.animation.rate) || !in.get(loop) || !in.getBytes(request.take) || !in.getVector(request.takeSeconds))
        return std::nullopt;
    request.animation.loop = loop != 0;
    using Kind = ImportRequest::Kind;
    if (request.kind < Kind::Mesh || request.kind > Kind::CheckMeshes)
        return std::nullopt;
    return request;
}

std::string answerImportRequest(const ImportRequest& request) {
    const std::filesystem::path& path = request.paths.front();
    const std::string name = "'" + path.string() + "'";
    switch (request.kind) {
    case ImportRequest::Kind::Mesh:
        return answerMesh(path, name);
    case ImportRequest::Kind::Animated:
        return answerAnimated(path, name, request.animation);
    case ImportRequest::Kind::Takes:
        return answerTakes(path, name);
    case ImportRequest::Kind::SourceRig:
        return answerSourceRig(path, name, request.take, request.takeSeconds);
    case ImportRequest::Kind::CheckMeshes:
        return answerMeshesCheck(request.paths);
    }
    return answerMesh(path, name);
}

}  // namespace softtouch::io
