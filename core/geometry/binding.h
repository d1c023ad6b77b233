#pragma once
/// Binding of a mesh to a lattice: each vertex's (u,v,w) and basis values, computed once, then the
/// deformed positions and normals for any node positions.
///
/// Normals come from the Jacobian of the map, not from faces: with J = dQ/dx_rest the normal
/// transforms by the cofactor matrix, n' ~ cof(J) n = det(J) J^-T n. Writing J = [Qu Qv Qw] * A with
/// A = d(u,v,w)/dx (constant for a box), cof(J) n = cof([Qu Qv Qw]) * cof(A) n, and
///   cof([Qu Qv Qw]) m = (Qv x Qw) m_u + (Qw x Qu) m_v + (Qu x Qv) m_w,
/// so per vertex only m = cof(A) n_rest (stored once) and the three partial derivatives are needed.
///
/// Layout: vertices are sorted by knot cell so that all vertices of a cell share one block of
/// (degree+1)^3 nodes; basis values are stored per axis as structure-of-arrays, so the inner loops
/// run over vertices and vectorise. A Bezier lattice is a single cell.

#include "core/geometry/lattice.h"
#include "core/geometry/mesh.h"

#include <span>
#include <vector>

namespace softtouch {

/// Precomputed Bernstein/B-spline data for one mesh on one lattice.
class Binding {
public:
    /// Binds rest positions and unit rest normals (same count) to a lattice.
    static Binding create(const Lattice& lattice, std::span<const Vec3f> restPositions,
                          std::span<const Vec3f> restNormals);

    /// Number of bound vertices.
    std::size_t vertexCount() const { return m_sortedToVertex.size(); }
    /// Rest parameters (u,v,w) of each vertex, in mesh order.
    const std::vector<Vec3>& parameters() const { return m_parameters; }

    /// Deformed positions (and, when `normals` is non-empty, unit normals) in mesh order.
    /// `nodes` holds the lattice node positions; `threads` <= 0 uses every hardware thread.
    void evaluate(std::span<const Vec3> nodes, std::span<Vec3f> positions, std::span<Vec3f> normals,
                  int threads = 0) const;

private:
    struct Chunk {
        std::array<int, 3> firstNode; ///< Lowest (i,j,k) of the cell's node block.
        std::uint32_t begin = 0;      ///< Range in sorted order.
        std::uint32_t end = 0;
    };
    void evaluateChunk(const Chunk& chunk, std::span<const Vec3> nodes, const Vec3& centre,
                       std::span<Vec3f> positions, std::span<Vec3f> normals) const;
    const float* basisRow(int axis, int r, bool slope) const;

    std::array<int, 3> m_order{};       ///< Non-zero basis functions per axis (degree + 1).
    std::array<int, 3> m_counts{};      ///< Lattice nodes per axis.
    std::vector<Vec3> m_parameters;     ///< (u,v,w) per vertex, mesh order.
    std::vector<std::uint32_t> m_sortedToVertex; ///< Sorted position -> mesh vertex index.
    std::vector<Chunk> m_chunks;        ///< Work units (one cell, at most kChunk vertices).
    std::vector<float> m_values;        ///< [axis][r][sorted vertex] basis values.
    std::vector<float> m_slopes;        ///< [axis][r][sorted vertex] basis derivatives.
    std::array<std::vector<float>, 3> m_restNormal; ///< cof(A) n_rest per sorted vertex, per component.
};

}  // namespace softtouch
