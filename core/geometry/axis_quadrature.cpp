#include "core/geometry/axis_quadrature.h"

#include <cmath>
#include <numbers>

namespace softtouch {

// Newton's iteration on P_n from the Chebyshev-like first guess converges in a few steps for n <= 16.
void gaussLegendre(int n, std::vector<double>& points, std::vector<double>& weights) {
    points.assign(std::size_t(n), 0.0);
    weights.assign(std::size_t(n), 0.0);
    for (int i = 0; i < n; ++i) {
        double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
        double slope = 1.0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p0 = 1.0, p1 = x;  // P_0, P_1; the recurrence climbs to P_n and P_{n-1}
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            slope = n * (x * p1 - p0) / (x * x - 1.0);
            const double step = p1 / slope;
            x -= step;
            if (std::abs(step) < 1e-15)
                break;
        }
        // On [-1,1]: w = 2 / ((1 - x²) P_n'(x)²); mapped to [0,1] both halve.
        points[std::size_t(i)] = 0.5 * (1.0 - x);
        weights[std::size_t(i)] = 1.0 / ((1.0 - x * x) * slope * slope);
    }
}

AxisQuadrature axisQuadrature(const AxisBasis& basis, int perSpan) {
    std::vector<double> x, w;
    gaussLegendre(perSpan, x, w);
    AxisQuadrature q;
    const int spans = basis.spanCount();
    for (int s = 0; s < spans; ++s) {
        for (std::size_t p = 0; p < x.size(); ++p) {
            q.point.push_back((s + x[p]) / spans);
            q.weight.push_back(w[p] / spans);
            q.sample.push_back(basis.sample(q.point.back()));
        }
    }
    return q;
}

Eigen::MatrixXd weightedProduct(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& w, const Eigen::SparseMatrix<double>& b) {
    if (4 * a.nonZeros() > a.rows() * a.cols())
        return Eigen::MatrixXd(a).transpose() * w.asDiagonal() * Eigen::MatrixXd(b);
    return Eigen::MatrixXd(Eigen::SparseMatrix<double>(a.transpose() * w.asDiagonal() * b));
}

}  // namespace softtouch
