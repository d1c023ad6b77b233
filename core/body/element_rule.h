#pragma once
/// The solid element's quadrature (core/body/element_body.h): a tensor-product rule over the lattice box, and the
/// two maps between the nodes and its points, by sum factorisation. The deformation gradient at every point is
/// three one-axis contractions of the node positions: for a 4x4x4 Bezier lattice about a tenth of the work of
/// summing each point's 64 nodes, and a 64th for 8x8x8. The node forces of the points' stresses are the same
/// contractions transposed.
///
/// Each contraction runs over the outermost axis of its input and over whole rows of what is left (the other two
/// axes and the components, contiguous), held in registers a block at a time, so the loops vectorise and each
/// output is written once; between contractions the next axis is brought outermost by a copy. Coefficients
/// outside a point's or a node's span (a B-spline's) are skipped.

#include "core/base/types.h"

#include <Eigen/Core>

#include <array>
#include <span>
#include <vector>

namespace softtouch {

/// One axis of a tensor-product quadrature rule: the basis and its slope (per metre) at each point, one row per
/// point, one column per node along the axis, and where they are not zero.
struct ElementAxisRule {
    Eigen::MatrixXd value;
    Eigen::MatrixXd slope;
    /// Per point, the nodes [first, end) outside which its value and slope are zero (a B-spline's span; every
    /// node on a Bezier axis). Filled by finishAxis().
    std::vector<std::array<int, 2>> pointNodes;
    /// Per node, the points [first, end) outside which its value and slope are zero. Filled by finishAxis().
    std::vector<std::array<int, 2>> nodePoints;

    /// Fills pointNodes and nodePoints from `value` and `slope`.
    void finishAxis();
};

/// A tensor-product quadrature rule over the lattice box: per axis its points, and per point its weight × volume
/// × the painted modulus and viscosity there. Points are numbered u fastest: the point of the u, v and w axes'
/// points p, q and r is p + P_u (q + P_v r) (elementRulePoint()).
struct ElementRule {
    std::array<ElementAxisRule, 3> axes;
    std::vector<double> stiffness;  ///< Pa·m³ per point.
    std::vector<double> viscosity;  ///< Pa·s·m³ per point.
    std::size_t pointCount() const { return stiffness.size(); }
    int axisPoints(int axis) const { return int(axes[std::size_t(axis)].value.rows()); }
};

/// The index of the point (p, q, r) in a rule's point order.
inline std::size_t elementRulePoint(const ElementRule& rule, int p, int q, int r) {
    return std::size_t(p + rule.axisPoints(0) * (q + rule.axisPoints(1) * r));
}

/// The deformation gradient's columns ∂x/∂X_c (box frame) of one or more node fields (node index
/// i + n_u (j + n_v k), `counts` the nodes per axis) at every point of `rule`: `columns[c]` receives, point by
/// point, field by field, the three components: 3 × fields doubles a point. Its scratch is the calling thread's.
void elementGradients(const ElementRule& rule, const std::array<int, 3>& counts,
                      std::span<const std::span<const Vec3>> fields, std::array<std::vector<double>, 3>& columns);

/// The transpose of elementGradients(): for each field f, forces[f]_i −= Σ_q P_q ∇N_i(q), P_q the stress whose
/// columns are in `columns` laid out as elementGradients() writes them (weights included), on the nodes whose
/// `slot` is not negative (the free ones).
void elementScatter(const ElementRule& rule, const std::array<int, 3>& counts,
                    const std::array<std::vector<double>, 3>& columns, std::span<const int> slot,
                    std::span<const std::span<Vec3>> forces);

}  // namespace softtouch
