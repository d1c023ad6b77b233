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
#include <cstdio>
#include <cstring>
#include <optional>
#include <system_error>


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

std::string answerMesh(const std::filesystem::path& path, const std::string& name) {
    return encodeResult(readWithAssimp(path, name), putMesh);
}

std::string answerMeshesCheck(const std::vector<std::filesystem::path>& paths) {
    for (const std::filesystem::path& path : paths) {
        auto mesh = readWithAssimp(path, "'" + path.string() + "'");
        if (!mesh)
            return encodeResult(Result<std::uint8_t>(mesh.status()), [](std::string&, std::uint8_t) {});
        reportImportProgress();
    }
    return encodeResult(Result<std::uint8_t>(std::uint8_t(1)), [](std::string& out, std::uint8_t v) { put(out, v); });
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
    ImportRequest request;
    request.kind = ImportRequest::Kind::Mesh;
    request.paths = {path};
    return importIsolated<Mesh>(request, getMesh);
}

Status checkMeshesImport(const std::vector<std::filesystem::path>& paths) {
    constexpr std::size_t kFilesPerChild = 256;  // each file restarts the idle watchdog; the cap stays far off
    for (const std::filesystem::path& path : paths)
        if (Status s = checkMeshFile(path, "'" + path.string() + "'"); !s)
            return s;
    for (std::size_t first = 0; first < paths.size(); first += kFilesPerChild) {
        const std::size_t last = std::min(paths.size(), first + kFilesPerChild);
        const std::string name = "'" + paths[first].string() + "'" + (last - first > 1 ? " and the next files" : "");
        ImportRequest request;
        request.kind = ImportRequest::Kind::CheckMeshes;
        request.paths.assign(paths.begin() + std::ptrdiff_t(first), paths.begin() + std::ptrdiff_t(last));
        auto bytes = runImport(request, name);
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
