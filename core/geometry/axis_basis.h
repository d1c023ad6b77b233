#pragma once
/// One axis of a tensor-product lattice: a clamped, uniform B-spline basis on [0,1].
///
/// A Bezier axis of n nodes is the special case degree = n-1 with no interior knots, where the
/// basis functions are exactly the Bernstein polynomials B_i(t) = C(n-1,i) t^i (1-t)^(n-1-i).
/// One evaluation routine (de Boor's, Piegl & Tiller "The NURBS Book" A2.2/A2.3) serves both.

#include <array>
#include <vector>

namespace softtouch {

/// Highest supported degree + 1 (Bezier up to degree 7 = 8 nodes per axis).
constexpr int kMaxBasisOrder = 8;

/// Basis values (and first derivatives) of one axis at one parameter.
struct BasisSample {
    int first = 0;                                ///< Index of the first node with non-zero weight.
    int order = 0;                                ///< Number of non-zero weights (degree + 1).
    std::array<double, kMaxBasisOrder> value{};   ///< N_{first+r}(t), r < order.
    std::array<double, kMaxBasisOrder> slope{};   ///< dN_{first+r}/dt.
};

/// A clamped uniform B-spline basis with `count` nodes and the given degree.
class AxisBasis {
public:
    AxisBasis() = default;
    /// Bernstein basis: degree count-1. Precondition: 2 <= count <= kMaxBasisOrder.
    static AxisBasis bezier(int count);
    /// Clamped uniform B-spline: each parameter depends on degree+1 nodes only.
    /// Precondition: count >= 2, 1 <= degree <= min(count-1, kMaxBasisOrder-1).
    static AxisBasis bspline(int count, int degree);

    int count() const { return m_count; }   ///< Number of nodes along the axis.
    int degree() const { return m_degree; } ///< Polynomial degree.
    /// Number of knot spans (polynomial pieces): 1 for Bezier.
    int spanCount() const { return m_count - m_degree; }
    /// Span holding t; parameters outside [0,1] use the end spans (polynomial extrapolation).
    int spanOf(double t) const;
    /// Values and slopes of the non-zero basis functions at t.
    BasisSample sample(double t) const;
    /// Greville abscissa of node i: where the node sits at rest so that the map reproduces the
    /// identity (linear precision). For Bezier: i / degree.
    double greville(int i) const;

private:
    int m_count = 0;
    int m_degree = 0;
    std::vector<double> m_knots;
};

}  // namespace softtouch
