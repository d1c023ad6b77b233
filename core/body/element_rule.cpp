#include "core/body/element_rule.h"

#include "core/base/vector_clones.h"

#include <algorithm>
#include <cassert>

namespace softtouch {

void ElementAxisRule::finishAxis() {
    const int points = int(value.rows()), nodes = int(value.cols());
    const auto nonZero = [&](int p, int i) { return value(p, i) != 0.0 || slope(p, i) != 0.0; };
    pointNodes.assign(std::size_t(points), {nodes, 0});
    nodePoints.assign(std::size_t(nodes), {points, 0});
    for (int p = 0; p < points; ++p)
        for (int i = 0; i < nodes; ++i)
            if (nonZero(p, i)) {
                auto& n = pointNodes[std::size_t(p)];
                n = {std::min(n[0], i), std::max(n[1], i + 1)};
                auto& q = nodePoints[std::size_t(i)];
                q = {std::min(q[0], p), std::max(q[1], p + 1)};
            }
    for (auto* spans : {&pointNodes, &nodePoints})
        for (auto& span : *spans)
            span[0] = std::min(span[0], span[1]);  // an all-zero row or column: an empty span
}

namespace {

/// Scratch of the contractions, the calling thread's (a body is stepped by one thread at a time, and several
/// bodies may step at once on different threads).
struct ContractionScratch {
    std::vector<double> nodes;                   ///< The fields, [i][j][k][component].
    std::array<std::vector<double>, 3> first;    ///< After the first contraction.
    std::array<std::vector<double>, 3> turned;   ///< The same with the next axis outermost.
    std::array<std::vector<double>, 3> second;   ///< After the second contraction.
};
ContractionScratch& contractionScratch() {
    thread_local ContractionScratch s;
    return s;
}

void fit(std::vector<double>& v, std::size_t size) {
    if (v.size() < size)
        v.resize(size);
}

/// One sum of a contraction: Σ_t c_t × row_t over the terms t in [begin, end), c_t at coefficients[t × step] and
/// row_t at rows + t × rowStride.
struct Terms {
    const double* coefficients = nullptr;
    int step = 0;
    const double* rows = nullptr;
    int rowStride = 0;
    int begin = 0, end = 0;
};

/// The sum over an axis's nodes at point `p` (a row of the column-major matrix m), the rows `rowStride` apart.
Terms atPoint(const ElementAxisRule& axis, const Eigen::MatrixXd& m, int p, const double* rows, int rowStride) {
    const auto& span = axis.pointNodes[std::size_t(p)];
    return {m.data() + p, int(m.rows()), rows, rowStride, span[0], span[1]};
}

/// The sum over an axis's points at node `i` (a column of m).
Terms atNode(const ElementAxisRule& axis, const Eigen::MatrixXd& m, int i, const double* rows, int rowStride) {
    const auto& span = axis.nodePoints[std::size_t(i)];
    return {m.data() + i * m.rows(), 1, rows, rowStride, span[0], span[1]};
}

template <int W>
[[gnu::always_inline]] inline void addTerms(double (&acc)[W], const Terms& t, int e) {
    for (int i = t.begin; i < t.end; ++i) {
        const double c = t.coefficients[i * t.step];
        const double* row = t.rows + i * t.rowStride + e;
        for (int k = 0; k < W; ++k)
            acc[k] += c * row[k];
    }
}

template <int W>
[[gnu::always_inline]] inline void combineBlock(double* out, int e, const Terms& a, const Terms& b) {
    double acc[W] = {};
    addTerms<W>(acc, a, e);
    addTerms<W>(acc, b, e);
    for (int k = 0; k < W; ++k)
        out[e + k] = acc[k];
}

/// out[e] = the sum `a` plus the sum `b` (b may be empty) at e, for e < count: a block of the row at a time,
/// held in registers across the terms, so each output is written once.
[[gnu::always_inline]] inline void combine(double* out, int count, const Terms& a, const Terms& b = {}) {
    int e = 0;
    for (; e + 8 <= count; e += 8)
        combineBlock<8>(out, e, a, b);
    if (e + 4 <= count) {
        combineBlock<4>(out, e, a, b);
        e += 4;
    }
    if (e + 2 <= count) {
        combineBlock<2>(out, e, a, b);
        e += 2;
    }
    if (e < count)
        combineBlock<1>(out, e, a, b);
}

/// out[b][a][rest] = in[a][b][rest]: the second index brought outermost, `rest` doubles moving together.
template <int Rest>
void swapOuterFixed(const double* in, double* out, int na, int nb) {
    for (int a = 0; a < na; ++a)
        for (int b = 0; b < nb; ++b)
            for (int e = 0; e < Rest; ++e)
                out[(b * na + a) * Rest + e] = in[(a * nb + b) * Rest + e];
}
void swapOuter(const double* in, double* out, int na, int nb, int rest) {
    // One field's or two fields' components (3 or 6) are too short for a library copy's call.
    if (rest == 3)
        return swapOuterFixed<3>(in, out, na, nb);
    if (rest == 6)
        return swapOuterFixed<6>(in, out, na, nb);
    for (int a = 0; a < na; ++a)
        for (int b = 0; b < nb; ++b)
            std::copy_n(in + (a * nb + b) * rest, rest, out + (b * na + a) * rest);
}

struct Sizes {
    int nu, nv, nw, pu, pv, pw, width;
};

/// The gradient's columns [r][q][p][c] of the fields x[i][j][k][c], through [p][j][k][c] and [q][p][k][c], each
/// brought to its next axis outermost.
SOFTTOUCH_VECTOR_CLONES
void contractToPoints(const ElementRule& rule, const Sizes& s, const double* x, ContractionScratch& t, double* cu,
                      double* cv, double* cw) {
    const ElementAxisRule& u = rule.axes[0];
    const ElementAxisRule& v = rule.axes[1];
    const ElementAxisRule& w = rule.axes[2];
    // Along u: A_V[p][j k c] = Σ_i V_u(p, i) x[i][j k c], A_S likewise with the slope.
    const int rowA = s.nv * s.nw * s.width;
    double *aV = t.first[0].data(), *aS = t.first[1].data();
    for (int p = 0; p < s.pu; ++p) {
        combine(aV + p * rowA, rowA, atPoint(u, u.value, p, x, rowA));
        combine(aS + p * rowA, rowA, atPoint(u, u.slope, p, x, rowA));
    }
    // [p][j] to [j][p], then along v: B_VV = V_v A_V, B_VS = S_v A_V, B_SV = V_v A_S, at [q][p k c].
    const int kc = s.nw * s.width, rowB = s.pu * kc;
    swapOuter(aV, t.turned[0].data(), s.pu, s.nv, kc);
    swapOuter(aS, t.turned[1].data(), s.pu, s.nv, kc);
    double *bVV = t.second[0].data(), *bVS = t.second[1].data(), *bSV = t.second[2].data();
    for (int q = 0; q < s.pv; ++q) {
        combine(bVV + q * rowB, rowB, atPoint(v, v.value, q, t.turned[0].data(), rowB));
        combine(bVS + q * rowB, rowB, atPoint(v, v.slope, q, t.turned[0].data(), rowB));
        combine(bSV + q * rowB, rowB, atPoint(v, v.value, q, t.turned[1].data(), rowB));
    }
    // [q][p][k] to [k][q][p], then along w: the u column from B_SV, the v column from B_VS, the w column from
    // B_VV with the slope, at [r][q p c].
    const int qp = s.pv * s.pu, rowC = qp * s.width;
    for (int e = 0; e < 3; ++e)
        swapOuter(t.second[std::size_t(e)].data(), t.turned[std::size_t(e)].data(), qp, s.nw, s.width);
    for (int r = 0; r < s.pw; ++r) {
        combine(cu + r * rowC, rowC, atPoint(w, w.value, r, t.turned[2].data(), rowC));
        combine(cv + r * rowC, rowC, atPoint(w, w.value, r, t.turned[1].data(), rowC));
        combine(cw + r * rowC, rowC, atPoint(w, w.slope, r, t.turned[0].data(), rowC));
    }
}

/// The transpose of contractToPoints(): the stresses' columns at [r][q][p][c] to node forces f[i][j][k][c],
/// through [k][q][p][c] and [j][p][k][c].
SOFTTOUCH_VECTOR_CLONES
void contractToNodes(const ElementRule& rule, const Sizes& s, const double* pu, const double* pv, const double* pw,
                     ContractionScratch& t, double* f) {
    const ElementAxisRule& u = rule.axes[0];
    const ElementAxisRule& v = rule.axes[1];
    const ElementAxisRule& w = rule.axes[2];
    // Along w: C_SV = V_wᵀ P_u, C_VS = V_wᵀ P_v, C_VV = S_wᵀ P_w, at [k][q p c].
    const int qp = s.pv * s.pu, rowC = qp * s.width;
    double *cSV = t.first[0].data(), *cVS = t.first[1].data(), *cVV = t.first[2].data();
    for (int k = 0; k < s.nw; ++k) {
        combine(cSV + k * rowC, rowC, atNode(w, w.value, k, pu, rowC));
        combine(cVS + k * rowC, rowC, atNode(w, w.value, k, pv, rowC));
        combine(cVV + k * rowC, rowC, atNode(w, w.slope, k, pw, rowC));
    }
    // [k][q p] to [q p][k], then along v: D_S = V_vᵀ C_SV (still to meet the u slope), D_V = S_vᵀ C_VS + V_vᵀ C_VV,
    // at [j][p k c].
    const int kc = s.nw * s.width, rowB = s.pu * kc;
    for (int e = 0; e < 3; ++e)
        swapOuter(t.first[std::size_t(e)].data(), t.turned[std::size_t(e)].data(), s.nw, qp, s.width);
    double *dS = t.second[0].data(), *dV = t.second[1].data();
    for (int j = 0; j < s.nv; ++j) {
        combine(dS + j * rowB, rowB, atNode(v, v.value, j, t.turned[0].data(), rowB));
        combine(dV + j * rowB, rowB, atNode(v, v.slope, j, t.turned[1].data(), rowB),
                atNode(v, v.value, j, t.turned[2].data(), rowB));
    }
    // [j][p] to [p][j], then along u: f[i][j k c] = Σ_p S_u(p, i) D_S[p] + V_u(p, i) D_V[p].
    const int rowA = s.nv * kc;
    swapOuter(dS, t.turned[0].data(), s.nv, s.pu, kc);
    swapOuter(dV, t.turned[1].data(), s.nv, s.pu, kc);
    for (int i = 0; i < s.nu; ++i)
        combine(f + i * rowA, rowA, atNode(u, u.slope, i, t.turned[0].data(), rowA),
                atNode(u, u.value, i, t.turned[1].data(), rowA));
}

Sizes sizesOf(const ElementRule& rule, const std::array<int, 3>& counts, std::size_t fields) {
    return {counts[0], counts[1], counts[2], rule.axisPoints(0), rule.axisPoints(1), rule.axisPoints(2), int(3 * fields)};
}

/// Room in the scratch for either direction: every intermediate holds at most the larger of the node and point
/// counts along each axis.
void fitScratch(ContractionScratch& t, const Sizes& s) {
    const std::size_t size =
        std::size_t(std::max(s.nu, s.pu) * std::max(s.nv, s.pv) * std::max(s.nw, s.pw) * s.width);
    fit(t.nodes, std::size_t(s.nu * s.nv * s.nw * s.width));
    for (auto* group : {&t.first, &t.turned, &t.second})
        for (auto& v : *group)
            fit(v, size);
}

}  // namespace

void elementGradients(const ElementRule& rule, const std::array<int, 3>& counts,
                      std::span<const std::span<const Vec3>> fields, std::array<std::vector<double>, 3>& columns) {
    const Sizes s = sizesOf(rule, counts, fields.size());
    assert(rule.pointCount() == std::size_t(s.pu * s.pv * s.pw));
    ContractionScratch& t = contractionScratch();
    fitScratch(t, s);
    // The fields in [i][j][k][component] order, so the contraction along u runs over whole rows.
    for (int k = 0; k < s.nw; ++k)
        for (int j = 0; j < s.nv; ++j)
            for (int i = 0; i < s.nu; ++i) {
                const std::size_t node = std::size_t(i + s.nu * (j + s.nv * k));
                double* to = t.nodes.data() + ((i * s.nv + j) * s.nw + k) * s.width;
                for (std::size_t f = 0; f < fields.size(); ++f)
                    for (int a = 0; a < 3; ++a)
                        to[3 * f + std::size_t(a)] = fields[f][node][a];
            }
    for (auto& c : columns)
        fit(c, rule.pointCount() * std::size_t(s.width));
    contractToPoints(rule, s, t.nodes.data(), t, columns[0].data(), columns[1].data(), columns[2].data());
}

void elementScatter(const ElementRule& rule, const std::array<int, 3>& counts,
                    const std::array<std::vector<double>, 3>& columns, std::span<const int> slot,
                    std::span<const std::span<Vec3>> forces) {
    const Sizes s = sizesOf(rule, counts, forces.size());
    ContractionScratch& t = contractionScratch();
    fitScratch(t, s);
    contractToNodes(rule, s, columns[0].data(), columns[1].data(), columns[2].data(), t, t.nodes.data());
    for (int k = 0; k < s.nw; ++k)
        for (int j = 0; j < s.nv; ++j)
            for (int i = 0; i < s.nu; ++i) {
                const std::size_t node = std::size_t(i + s.nu * (j + s.nv * k));
                if (slot[node] < 0)
                    continue;
                const double* from = t.nodes.data() + ((i * s.nv + j) * s.nw + k) * s.width;
                for (std::size_t f = 0; f < forces.size(); ++f)
                    forces[f][node] -= Vec3(from[3 * f], from[3 * f + 1], from[3 * f + 2]);
            }
}

}  // namespace softtouch
