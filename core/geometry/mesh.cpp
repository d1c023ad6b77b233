#include "core/geometry/mesh.h"

#include <cmath>
#include <utility>

namespace softtouch {

Status Mesh::validate() const {
    if (positions.empty())
        return Status::error("the mesh has no vertices");
    if (triangles.empty())
        return Status::error("the mesh has no triangles");
    for (std::size_t i = 0; i < positions.size(); ++i) {
        if (!isFinite(positions[i]))
            return Status::error("vertex " + std::to_string(i) + " has a non-finite coordinate");
    }
    if (!normals.empty() && normals.size() != positions.size())
        return Status::error("the mesh has " + std::to_string(normals.size()) + " normals for " +
                             std::to_string(positions.size()) + " vertices");
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        for (std::uint32_t index : triangles[t]) {
            if (index >= positions.size())
                return Status::error("triangle " + std::to_string(t) + " uses vertex " + std::to_string(index) +
                                     " of " + std::to_string(positions.size()));
        }
    }
    return Status::success();
}

void areaWeightedNormals(std::span<const Vec3f> positions, std::span<const std::array<std::uint32_t, 3>> triangles,
                         std::span<Vec3f> normals) {
    std::vector<Eigen::Vector3d> sum(positions.size(), Eigen::Vector3d::Zero());
    for (const auto& tri : triangles) {
        const Eigen::Vector3d a = positions[tri[0]].cast<double>();
        const Eigen::Vector3d b = positions[tri[1]].cast<double>();
        const Eigen::Vector3d c = positions[tri[2]].cast<double>();
        // The cross product's length is twice the area: area weighting comes for free.
        const Eigen::Vector3d n = (b - a).cross(c - a);
        for (std::uint32_t index : tri)
            sum[index] += n;
    }
    for (std::size_t i = 0; i < positions.size() && i < normals.size(); ++i) {
        const double length = sum[i].norm();
        normals[i] = length > 0.0 ? Vec3f((sum[i] / length).cast<float>()) : Vec3f(Vec3f::UnitZ());
    }
}

void Mesh::computeNormals() {
    normals.resize(positions.size());
    areaWeightedNormals(positions, triangles, normals);
}

Bounds boundsOf(std::span<const Vec3> points) {
    if (points.empty())
        return {};
    Bounds b{points.front(), points.front()};
    for (const Vec3& p : points) {
        b.min = b.min.cwiseMin(p);
        b.max = b.max.cwiseMax(p);
    }
    return b;
}

Bounds Mesh::bounds() const {
    Bounds b;
    if (positions.empty())
        return b;
    b.min = b.max = positions[0].cast<double>();
    for (const Vec3f& p : positions) {
        b.min = b.min.cwiseMin(p.cast<double>());
        b.max = b.max.cwiseMax(p.cast<double>());
    }
    return b;
}

SharedMesh::SharedMesh() {
    static const auto empty = std::make_shared<const Mesh>();
    m_mesh = empty;
}

SharedMesh::SharedMesh(Mesh mesh) : m_mesh(std::make_shared<const Mesh>(std::move(mesh))) {}

}  // namespace softtouch
