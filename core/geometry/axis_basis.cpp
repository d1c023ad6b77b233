#include "core/geometry/axis_basis.h"

#include <algorithm>
#include <cassert>

namespace softtouch {

AxisBasis AxisBasis::bezier(int count) {
    assert(count >= 2 && count <= kMaxBasisOrder);
    return bspline(count, count - 1);
}

AxisBasis AxisBasis::bspline(int count, int degree) {
    assert(count >= 2 && degree >= 1 && degree <= count - 1 && degree < kMaxBasisOrder);
    AxisBasis basis;
    basis.m_count = count;
    basis.m_degree = degree;
    // Clamped knot vector: degree+1 zeros, uniform interior knots, degree+1 ones.
    const int spans = count - degree;
    basis.m_knots.assign(std::size_t(degree), 0.0);
    for (int s = 0; s <= spans; ++s)
        basis.m_knots.push_back(double(s) / double(spans));
    basis.m_knots.insert(basis.m_knots.end(), std::size_t(degree), 1.0);
    return basis;
}

int AxisBasis::spanOf(double t) const {
    const int spans = spanCount();
    const int s = int(t * spans);  // uniform interior knots: no search needed
    return std::clamp(s, 0, spans - 1);
}

BasisSample AxisBasis::sample(double t) const {
    // de Boor / Cox recursion in the triangular form of The NURBS Book, A2.3 (first derivative only).
    const int p = m_degree;
    const int span = spanOf(t) + p;  // index into the knot vector
    const double* U = m_knots.data();
    double ndu[kMaxBasisOrder][kMaxBasisOrder];
    double left[kMaxBasisOrder];
    double right[kMaxBasisOrder];
    ndu[0][0] = 1.0;
    for (int j = 1; j <= p; ++j) {
        left[j] = t - U[span + 1 - j];
        right[j] = U[span + j] - t;
        double saved = 0.0;
        for (int r = 0; r < j; ++r) {
            ndu[j][r] = right[r + 1] + left[j - r];  // lower triangle: knot differences
            const double temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;  // upper triangle: basis values
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    BasisSample out;
    out.first = span - p;
    out.order = p + 1;
    for (int r = 0; r <= p; ++r)
        out.value[std::size_t(r)] = ndu[r][p];
    // N'_{i,p} = p (N_{i,p-1} / (u_{i+p} - u_i) - N_{i+1,p-1} / (u_{i+p+1} - u_{i+1})).
    for (int r = 0; r <= p; ++r) {
        double d = 0.0;
        if (r >= 1)
            d += ndu[r - 1][p - 1] / ndu[p][r - 1];
        if (r <= p - 1)
            d -= ndu[r][p - 1] / ndu[p][r];
        out.slope[std::size_t(r)] = double(p) * d;
    }
    return out;
}

double AxisBasis::greville(int i) const {
    double sum = 0.0;
    for (int k = 1; k <= m_degree; ++k)
        sum += m_knots[std::size_t(i + k)];
    return sum / double(m_degree);
}

}  // namespace softtouch
