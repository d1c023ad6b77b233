#pragma once
/// The free-form deformation lattice: a trivariate tensor-product volume over an oriented box.
///
///   Q(u,v,w) = sum_ijk P_ijk N_i(u) N_j(v) N_k(w)
///
/// Bezier (the paper's; N = Bernstein, every node moves every vertex) or clamped uniform cubic
/// B-spline (N local: a vertex depends on 4x4x4 nodes only, for finer grids such as 8x4x4 along a fish).
///
/// Node numbering, i fastest:     k
///   index = i + nx*(j + ny*k)    |  j
///                                | /
///                                |/____ i   (i along box axis u, j along v, k along w)

#include "core/base/result.h"
#include "core/base/types.h"
#include "core/geometry/axis_basis.h"
#include "core/geometry/oriented_box.h"

#include <array>
#include <span>
#include <vector>

namespace softtouch {

/// Which basis the lattice uses.
enum class LatticeKind : std::uint8_t {
    Bezier,  ///< Bernstein basis, degree = nodes - 1 per axis (2..8 nodes).
    BSpline, ///< Clamped uniform cubic B-spline (degree min(3, nodes-1)), any node count >= 2.
};

/// Resolution and kind of a lattice.
struct LatticeShape {
    LatticeKind kind = LatticeKind::Bezier; ///< Basis kind.
    std::array<int, 3> nodes{4, 4, 4};      ///< Nodes per axis. Bezier: 2..8; B-spline: 2..64.
    /// Checks node counts against the kind's range.
    Status validate() const;
    bool operator==(const LatticeShape&) const = default;
};

/// One node's share of a material point.
struct NodeWeight {
    std::uint32_t node = 0; ///< Node index.
    double weight = 0.0;    ///< Basis product N_i N_j N_k at the point.
};

/// Lattice topology and rest geometry (immutable once created).
class Lattice {
public:
    /// Creates a lattice of the given shape over a box; errors on a bad shape or a degenerate box.
    static Result<Lattice> create(const LatticeShape& shape, const OrientedBox& box);

    const LatticeShape& shape() const { return m_shape; }
    const OrientedBox& box() const { return m_box; }
    const AxisBasis& axis(int a) const { return m_axes[std::size_t(a)]; }
    /// Nodes per axis.
    int count(int a) const { return m_shape.nodes[std::size_t(a)]; }
    /// Total node count.
    int nodeCount() const { return count(0) * count(1) * count(2); }
    /// Linear index of node (i,j,k).
    int index(int i, int j, int k) const { return i + count(0) * (j + count(1) * k); }
    /// (i,j,k) of a linear index.
    std::array<int, 3> coords(int index) const;
    /// Rest parameters (u,v,w) of a node (its Greville point).
    Vec3 restNodeParameters(int index) const;
    /// Rest world positions of all nodes: with these the map is the identity.
    std::vector<Vec3> restNodes() const;
    /// Non-zero node weights of a material point (u,v,w); they sum to 1.
    std::vector<NodeWeight> weights(const Vec3& uvw) const;
    /// Deformed world position of a material point for the given node positions.
    Vec3 evaluate(const Vec3& uvw, std::span<const Vec3> nodes) const;

private:
    LatticeShape m_shape;
    OrientedBox m_box;
    std::array<AxisBasis, 3> m_axes;
};

}  // namespace softtouch
