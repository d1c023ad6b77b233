#pragma once
/// The lattice pose that carries a bound mesh closest to given vertex positions: the goal pose of a body
/// that follows a base animation (core/animation/base_motion.h).
///
/// With B the binding's weights (vertex v's position is Σ_i B_vi x_i), the pose solves
///   min_X |B X − P|² + λ |X − Y|²,   (BᵀB + λ I) X = BᵀP + λ Y,
/// where Y is the rest lattice moved by the affine map that best fits P (least squares over the vertices,
/// [p_rest 1] → p). Nodes the mesh barely reaches (air around a fish) follow that affine motion instead of
/// drifting, and the control net does not overshoot a bend it cannot follow: λ is kGoalFitRidge times the
/// mean diagonal of BᵀB. On the rigged guppy's swim (docs/design/lattice.md, "Secondary motion on a base
/// animation") a millionth let nodes swing 6.5 m for a 7 cm RMS motion (180 m/s² of spurious inertia) with a
/// residual of 3.1 mm; a hundredth keeps them within 0.44 m (9.3 m/s², what the tail's 1 Hz swing of 0.2 m
/// has) for a residual of 4.2 mm. The basis
/// reproduces affine maps (Σ_i B_vi x_i = p_v for the rest nodes, and it is a partition of unity), so a mesh
/// moved rigidly or affinely gives exactly the lattice moved the same way. Both normal matrices are
/// factored once; a fit costs one pass over the binding's weights and two small solves.

#include "core/base/result.h"
#include "core/base/types.h"
#include "core/geometry/lattice.h"

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <memory>
#include <span>
#include <vector>

namespace softtouch {

/// λ as a fraction of the mean diagonal of BᵀB (see above).
inline constexpr double kGoalFitRidge = 1e-2;

class GoalFit {
public:
    /// Fits for `lattice`, whose binding of `restPositions` has the rest parameters `parameters` (one per
    /// vertex, Binding::parameters()). Fails on an empty mesh or one that is flat along every axis.
    static Result<GoalFit> create(const Lattice& lattice, std::span<const Vec3f> restPositions,
                                  std::span<const Vec3> parameters);

    /// The lattice pose for vertex positions `positions` (mesh order, same count) into `nodes`, and the
    /// rotation of the best affine fit (its polar part: how the whole mesh turned).
    void fit(std::span<const Vec3f> positions, std::vector<Vec3>& nodes, Mat3& rotation) const;

private:
    Eigen::SparseMatrix<double> m_weights;          ///< B, vertices × nodes.
    /// BᵀB + λ I, factored (Eigen's solvers cannot be copied or moved; the fit is immutable once made).
    std::shared_ptr<const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>> m_normal;
    Eigen::LDLT<Eigen::Matrix4d> m_affine;          ///< Σ [p 1][p 1]ᵀ over the rest vertices.
    Eigen::MatrixX4d m_restHomogeneous;             ///< [p_rest 1] per vertex.
    Eigen::MatrixX4d m_restNodes;                   ///< [x_rest 1] per node.
    double m_lambda = 0.0;
};

}  // namespace softtouch
