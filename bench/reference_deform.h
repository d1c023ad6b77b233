#pragma once
/// The plain scalar deformation kernel the Binding is measured against: the same tensor-product maths,
/// written the obvious way — basis values stored per vertex (array of structures), one vertex at a
/// time, no vectorisation (this file is compiled with -fno-tree-vectorize), one thread.

#include "core/base/types.h"
#include "core/geometry/lattice.h"

#include <span>
#include <vector>

namespace softtouch::bench {

/// Straightforward per-vertex FFD evaluation.
class ReferenceDeformer {
public:
    ReferenceDeformer(const Lattice& lattice, std::span<const Vec3f> restPositions, std::span<const Vec3f> restNormals);
    /// Positions (and normals when non-empty), like Binding::evaluate.
    void evaluate(std::span<const Vec3> nodes, std::span<Vec3f> positions, std::span<Vec3f> normals) const;

private:
    struct VertexBasis {
        int first[3];
        float value[3][kMaxBasisOrder];
        float slope[3][kMaxBasisOrder];
        float restNormal[3];  ///< cof(A) n_rest
    };
    std::array<int, 3> m_order{};
    std::array<int, 3> m_counts{};
    std::vector<VertexBasis> m_vertices;
};

}  // namespace softtouch::bench
