#include "io/mesh_import.h"

#include "io/input_file.h"
#include "io/mesh_file_check.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <system_error>

namespace softtouch::io {

Result<Mesh> importMesh(const std::filesystem::path& path) {
    const std::string name = "'" + path.string() + "'";
    if (Status s = checkInputFile(path, kMaxMeshFileBytes); !s)
        return Status::error("mesh file " + name + " " + s.message());
    std::error_code ec;
    if (std::filesystem::file_size(path, ec) == 0)
        return Status::error("mesh file " + name + " is empty (0 bytes)");
    if (Status s = checkMeshFileIsWhole(path); !s)
        return Status::error("mesh file " + name + ": " + s.message());

    Assimp::Importer importer;
    // Points and lines are of no use to a deformer: drop them instead of failing on them.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices |
                           aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    const aiScene* scene = importer.ReadFile(path.string(), flags);
    if (!scene)
        return Status::error("cannot read mesh " + name + ": " + importer.GetErrorString());

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

}  // namespace softtouch::io
