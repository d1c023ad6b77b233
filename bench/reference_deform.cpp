#include "bench/reference_deform.h"

namespace softtouch::bench {

ReferenceDeformer::ReferenceDeformer(const Lattice& lattice, std::span<const Vec3f> restPositions,
                                     std::span<const Vec3f> restNormals) {
    for (int a = 0; a < 3; ++a) {
        m_order[std::size_t(a)] = lattice.axis(a).degree() + 1;
        m_counts[std::size_t(a)] = lattice.count(a);
    }
    const Mat3 A = lattice.box().parameterJacobian();
    const Mat3 cofactor = A.determinant() * A.inverse().transpose();
    m_vertices.resize(restPositions.size());
    for (std::size_t v = 0; v < restPositions.size(); ++v) {
        const Vec3 uvw = lattice.box().toParameters(restPositions[v].cast<double>());
        VertexBasis& b = m_vertices[v];
        for (int a = 0; a < 3; ++a) {
            const BasisSample s = lattice.axis(a).sample(uvw[a]);
            b.first[a] = s.first;
            for (int r = 0; r < s.order; ++r) {
                b.value[a][r] = float(s.value[std::size_t(r)]);
                b.slope[a][r] = float(s.slope[std::size_t(r)]);
            }
        }
        const Vec3 m = (cofactor * restNormals[v].cast<double>()).normalized();
        for (int a = 0; a < 3; ++a)
            b.restNormal[a] = float(m[a]);
    }
}

void ReferenceDeformer::evaluate(std::span<const Vec3> nodes, std::span<Vec3f> positions, std::span<Vec3f> normals) const {
    const bool withNormals = !normals.empty();
    for (std::size_t v = 0; v < m_vertices.size(); ++v) {
        const VertexBasis& b = m_vertices[v];
        Vec3f p = Vec3f::Zero(), du = Vec3f::Zero(), dv = Vec3f::Zero(), dw = Vec3f::Zero();
        for (int k = 0; k < m_order[2]; ++k)
            for (int j = 0; j < m_order[1]; ++j)
                for (int i = 0; i < m_order[0]; ++i) {
                    const int node = (b.first[0] + i) + m_counts[0] * ((b.first[1] + j) + m_counts[1] * (b.first[2] + k));
                    const Vec3f P = nodes[std::size_t(node)].cast<float>();
                    p += (b.value[0][i] * b.value[1][j] * b.value[2][k]) * P;
                    if (withNormals) {
                        du += (b.slope[0][i] * b.value[1][j] * b.value[2][k]) * P;
                        dv += (b.value[0][i] * b.slope[1][j] * b.value[2][k]) * P;
                        dw += (b.value[0][i] * b.value[1][j] * b.slope[2][k]) * P;
                    }
                }
        positions[v] = p;
        if (withNormals)
            normals[v] = (dv.cross(dw) * b.restNormal[0] + dw.cross(du) * b.restNormal[1] + du.cross(dv) * b.restNormal[2])
                             .normalized();
    }
}

}  // namespace softtouch::bench
