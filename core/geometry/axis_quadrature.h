#pragma once
/// Gauss-Legendre quadrature along one axis of a tensor-product basis, span by span: what the solid
/// reference (core/modes/solid_modes.h) and the simulated solid element (core/body/element_body.h) integrate with, so
/// the element a body runs is the element the mode study measures.

#include "core/geometry/axis_basis.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace softtouch {

/// Gauss-Legendre points and weights of `n` points on [0,1] (exact for polynomials of degree 2n-1).
void gaussLegendre(int n, std::vector<double>& points, std::vector<double>& weights);

/// `perSpan` Gauss points on every knot span of `basis`, with the basis sampled at each.
struct AxisQuadrature {
    std::vector<double> point;        ///< Parameters in [0,1].
    std::vector<double> weight;       ///< Sum to 1 over the axis.
    std::vector<BasisSample> sample;  ///< The basis at each point.
};
AxisQuadrature axisQuadrature(const AxisBasis& basis, int perSpan);

/// Aᵀ diag(w) B as a dense matrix: through dense products where the basis is dense (a Bezier element's points
/// see every node), sparse ones where it is not. A and B hold one row per quadrature point, one column per node.
Eigen::MatrixXd weightedProduct(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& w, const Eigen::SparseMatrix<double>& b);

}  // namespace softtouch
