#include "core/body/element_stress.h"

#include "core/base/vector_clones.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softtouch {

namespace {

constexpr int L = kStressLanes;

/// The Voigt slot of a symmetric tensor's entry (i, j).
constexpr int kVoigt[3][3] = {{0, 5, 4}, {5, 1, 3}, {4, 3, 2}};

/// Column-major slot of a 3x3 matrix's entry (row, column).
constexpr int at(int row, int column) { return 3 * column + row; }

/// One Jacobi rotation in the (P, Q) plane of the symmetric `a` (R the third axis), accumulated into the
/// columns P and Q of `v` (Numerical Recipes' jacobi, |θ| ≤ π/4). With d = a_QQ − a_PP, h = 2 a_PQ and
/// r = √(d² + h²): tan θ = sgn(d) h / (|d| + r), so c = (|d| + r) q and s = sgn(d) h q with q = 1/√(2r (|d| + r)),
/// and the block's new diagonal is its eigenvalues, (a_PP + a_QQ)/2 ∓ sgn(d) r/2: two square roots and one
/// division a rotation, no branch, and c = 1, s = 0 where the block is already diagonal and d = 0.
template <int P, int Q, int R>
[[gnu::always_inline]] inline void rotate(std::array<Lanes, 6>& a, std::array<Lanes, 9>& v) {
    constexpr int pp = kVoigt[P][P], qq = kVoigt[Q][Q], pq = kVoigt[P][Q], rp = kVoigt[R][P], rq = kVoigt[R][Q];
    for (int l = 0; l < L; ++l) {
        const double d = a[qq][l] - a[pp][l];
        const double h = 2.0 * a[pq][l];
        const double r = std::sqrt(d * d + h * h);
        const double sum = std::abs(d) + r;
        const double q = 1.0 / std::sqrt(std::max(2.0 * r * sum, std::numeric_limits<double>::min()));
        const double c = r > 0.0 ? sum * q : 1.0;
        const double s = r > 0.0 ? std::copysign(1.0, d) * h * q : 0.0;
        const double mean = 0.5 * (a[pp][l] + a[qq][l]), half = std::copysign(0.5 * r, d);
        a[pp][l] = mean - half;
        a[qq][l] = mean + half;
        a[pq][l] = 0.0;
        const double arp = a[rp][l], arq = a[rq][l];
        a[rp][l] = c * arp - s * arq;
        a[rq][l] = s * arp + c * arq;
        for (int k = 0; k < 3; ++k) {
            const double vkp = v[at(k, P)][l], vkq = v[at(k, Q)][l];
            v[at(k, P)][l] = c * vkp - s * vkq;
            v[at(k, Q)][l] = s * vkp + c * vkq;
        }
    }
}

/// Whether every lane's off-diagonal part is below round-off against the whole: |off|² ≤ 1e-32 |a|².
[[gnu::always_inline]] inline bool diagonal(const std::array<Lanes, 6>& a) {
    bool done = true;
    for (int l = 0; l < L; ++l) {
        const double off = a[3][l] * a[3][l] + a[4][l] * a[4][l] + a[5][l] * a[5][l];
        const double on = a[0][l] * a[0][l] + a[1][l] * a[1][l] + a[2][l] * a[2][l];
        done = done && off <= 1e-32 * (on + off);
    }
    return done;
}

/// Sweeps of cyclic Jacobi at most: it converges quadratically, and from any start a 3x3 matrix is diagonal to
/// round-off in three or four (tests/core/test_element_stress.cpp checks it on the hardest cases).
constexpr int kMaxSweeps = 8;

/// A symmetric tensor of Voigt entries (tensor shears) turned into V's frame and back: out = V diag(d) Vᵀ.
[[gnu::always_inline]] inline void spectral(const std::array<Lanes, 9>& v, const std::array<Lanes, 3>& d, std::array<Lanes, 6>& out) {
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            for (int l = 0; l < L; ++l)
                out[kVoigt[i][j]][l] = v[at(i, 0)][l] * d[0][l] * v[at(j, 0)][l] + v[at(i, 1)][l] * d[1][l] * v[at(j, 1)][l] +
                                       v[at(i, 2)][l] * d[2][l] * v[at(j, 2)][l];
}

/// σ = k C ε for strains with doubled shears.
[[gnu::always_inline]] inline void stressOf(const Eigen::Matrix<double, 6, 6>& elasticity, const Lanes& k, const std::array<Lanes, 6>& strain,
              std::array<Lanes, 6>& sigma) {
    for (int i = 0; i < 6; ++i) {
        Lanes sum{};
        for (int j = 0; j < 6; ++j) {
            const double c = elasticity(i, j);
            for (int l = 0; l < L; ++l)
                sum[l] += c * strain[j][l];
        }
        for (int l = 0; l < L; ++l)
            sigma[i][l] = k[l] * sum[l];
    }
}

}  // namespace

SOFTTOUCH_VECTOR_CLONES
void stretchLanes(const std::array<Lanes, 9>& f, StretchLanes& out) {
    // FᵀF − I, whose eigenvalues are the strains' own scale: at rest it is zero, not the identity.
    std::array<Lanes, 6> a;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            for (int l = 0; l < L; ++l)
                a[kVoigt[i][j]][l] = f[at(0, i)][l] * f[at(0, j)][l] + f[at(1, i)][l] * f[at(1, j)][l] +
                                     f[at(2, i)][l] * f[at(2, j)][l] - (i == j ? 1.0 : 0.0);
    std::array<Lanes, 9>& v = out.basis;
    for (int e = 0; e < 9; ++e)
        v[e].fill(e % 4 == 0 ? 1.0 : 0.0);
    for (int sweep = 0; sweep < kMaxSweeps && !diagonal(a); ++sweep) {
        rotate<0, 1, 2>(a, v);
        rotate<0, 2, 1>(a, v);
        rotate<1, 2, 0>(a, v);
    }
    std::array<Lanes, 3> change;
    for (int k = 0; k < 3; ++k)
        for (int l = 0; l < L; ++l) {
            const double g = std::max(a[k][l], -1.0 + 1e-12);  // a collapsed direction keeps a tiny length
            out.singular[k][l] = std::sqrt(1.0 + g);
            change[k][l] = g / (1.0 + out.singular[k][l]);
        }
    spectral(v, change, out.strain);
}

SOFTTOUCH_VECTOR_CLONES
void elasticStressLanes(const Eigen::Matrix<double, 6, 6>& elasticity, const Lanes& modulus, const std::array<Lanes, 9>& f,
                        const StretchLanes& stretch, std::array<Lanes, 9>& stress, Lanes* energy) {
    std::array<Lanes, 6> strain, sigma;
    for (int i = 0; i < 6; ++i)
        for (int l = 0; l < L; ++l)
            strain[i][l] = i < 3 ? stretch.strain[i][l] : 2.0 * stretch.strain[i][l];
    stressOf(elasticity, modulus, strain, sigma);
    if (energy)
        for (int l = 0; l < L; ++l) {
            double e = 0.0;
            for (int i = 0; i < 6; ++i)
                e += strain[i][l] * sigma[i][l];
            (*energy)[l] += 0.5 * e;
        }
    // Y' = Vᵀ σ V / (s_a + s_b) in S's eigenbasis, then Y = V Y' Vᵀ and P = 2 F Y.
    const std::array<Lanes, 9>& v = stretch.basis;
    std::array<Lanes, 9> sv;  // σ V
    for (int i = 0; i < 3; ++i)
        for (int b = 0; b < 3; ++b)
            for (int l = 0; l < L; ++l)
                sv[at(i, b)][l] = sigma[kVoigt[i][0]][l] * v[at(0, b)][l] + sigma[kVoigt[i][1]][l] * v[at(1, b)][l] +
                                  sigma[kVoigt[i][2]][l] * v[at(2, b)][l];
    std::array<Lanes, 6> y;  // Y', then Y
    for (int a = 0; a < 3; ++a)
        for (int b = a; b < 3; ++b)
            for (int l = 0; l < L; ++l)
                y[kVoigt[a][b]][l] = (v[at(0, a)][l] * sv[at(0, b)][l] + v[at(1, a)][l] * sv[at(1, b)][l] +
                                      v[at(2, a)][l] * sv[at(2, b)][l]) /
                                     (stretch.singular[a][l] + stretch.singular[b][l]);
    std::array<Lanes, 9> vy;  // V Y'
    for (int i = 0; i < 3; ++i)
        for (int b = 0; b < 3; ++b)
            for (int l = 0; l < L; ++l)
                vy[at(i, b)][l] = v[at(i, 0)][l] * y[kVoigt[0][b]][l] + v[at(i, 1)][l] * y[kVoigt[1][b]][l] +
                                  v[at(i, 2)][l] * y[kVoigt[2][b]][l];
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            for (int l = 0; l < L; ++l)
                y[kVoigt[i][j]][l] = vy[at(i, 0)][l] * v[at(j, 0)][l] + vy[at(i, 1)][l] * v[at(j, 1)][l] +
                                     vy[at(i, 2)][l] * v[at(j, 2)][l];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            for (int l = 0; l < L; ++l)
                stress[at(r, c)][l] = 2.0 * (f[at(r, 0)][l] * y[kVoigt[0][c]][l] + f[at(r, 1)][l] * y[kVoigt[1][c]][l] +
                                             f[at(r, 2)][l] * y[kVoigt[2][c]][l]);
}

SOFTTOUCH_VECTOR_CLONES
void rotationLanes(const std::array<Lanes, 9>& f, const StretchLanes& stretch, std::array<Lanes, 9>& rotation) {
    std::array<Lanes, 3> inverse;
    for (int k = 0; k < 3; ++k)
        for (int l = 0; l < L; ++l)
            inverse[k][l] = 1.0 / stretch.singular[k][l];
    std::array<Lanes, 6> s;  // S⁻¹
    spectral(stretch.basis, inverse, s);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            for (int l = 0; l < L; ++l)
                rotation[at(r, c)][l] = f[at(r, 0)][l] * s[kVoigt[0][c]][l] + f[at(r, 1)][l] * s[kVoigt[1][c]][l] +
                                        f[at(r, 2)][l] * s[kVoigt[2][c]][l];
}

SOFTTOUCH_VECTOR_CLONES
void corotatedStressLanes(const Eigen::Matrix<double, 6, 6>& elasticity, const Lanes& factor,
                          const std::array<Lanes, 9>& rotation, const std::array<Lanes, 9>& gradient,
                          std::array<Lanes, 9>& stress) {
    std::array<Lanes, 9> turned;  // Rᵀ G
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            for (int l = 0; l < L; ++l)
                turned[at(r, c)][l] = rotation[at(0, r)][l] * gradient[at(0, c)][l] +
                                      rotation[at(1, r)][l] * gradient[at(1, c)][l] +
                                      rotation[at(2, r)][l] * gradient[at(2, c)][l];
    std::array<Lanes, 6> strain, sigma;  // doubled shears: the symmetric part's 2ε_ij = t_ij + t_ji
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            for (int l = 0; l < L; ++l)
                strain[kVoigt[i][j]][l] = i == j ? turned[at(i, i)][l] : turned[at(i, j)][l] + turned[at(j, i)][l];
    stressOf(elasticity, factor, strain, sigma);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            for (int l = 0; l < L; ++l)
                stress[at(r, c)][l] = rotation[at(r, 0)][l] * sigma[kVoigt[0][c]][l] +
                                      rotation[at(r, 1)][l] * sigma[kVoigt[1][c]][l] +
                                      rotation[at(r, 2)][l] * sigma[kVoigt[2][c]][l];
}

}  // namespace softtouch
