#include "core/fitting/morph_basis.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace softtouch {

namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The frames' mean row and the centred rows.
RowMatrix centred(std::span<const float> deltas, std::size_t frames, std::size_t values, std::vector<float>& mean) {
    const Eigen::Map<const RowMatrix> d(deltas.data(), Eigen::Index(frames), Eigen::Index(values));
    const Eigen::RowVectorXd m = d.cast<double>().colwise().mean();
    mean.assign(values, 0.0f);
    for (std::size_t j = 0; j < values; ++j)
        mean[j] = float(m[Eigen::Index(j)]);
    return d.rowwise() - m.cast<float>();
}

}  // namespace

MorphBasis fitMorphBasis(std::span<const float> deltas, std::size_t frames, std::size_t values, double rmsTarget,
                         std::size_t maxComponents) {
    MorphBasis basis;
    if (frames == 0 || values == 0 || deltas.size() != frames * values)
        return basis;
    const RowMatrix c = centred(deltas, frames, values, basis.mean);
    const std::size_t vertices = std::max<std::size_t>(1, values / 3);

    // The SVD of the centred frames through their Gram matrix G = C Cᵀ (frames x frames, small): G = U Σ² Uᵀ,
    // components T_k = Cᵀ u_k / σ_k (orthonormal), weights w_fk = σ_k u_fk. Row f of the residual after K
    // components has squared norm |c_f|² − Σ_{k<K} w_fk², so every K's error is known before any is built.
    const Eigen::MatrixXd gram = (c * c.transpose()).cast<double>();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
    const Eigen::Index n = gram.rows();
    std::vector<double> residual(frames);
    for (std::size_t f = 0; f < frames; ++f)
        residual[f] = gram(Eigen::Index(f), Eigen::Index(f));
    auto worstRms = [&] {
        double worst = 0.0;
        for (double r : residual)
            worst = std::max(worst, std::sqrt(std::max(0.0, r) / double(vertices)));
        return worst;
    };
    const std::size_t limit = std::min(maxComponents, frames > 1 ? frames - 1 : 0);
    std::vector<Eigen::Index> chosen;
    basis.worstFrameRms = worstRms();
    for (Eigen::Index k = n - 1; k >= 0 && chosen.size() < limit && basis.worstFrameRms > rmsTarget; --k) {
        const double lambda = eigen.eigenvalues()[k];
        if (!(lambda > 1e-30))
            break;  // nothing left to explain
        const Eigen::VectorXd u = eigen.eigenvectors().col(k);
        for (std::size_t f = 0; f < frames; ++f) {
            const double w = std::sqrt(lambda) * u[Eigen::Index(f)];
            residual[f] -= w * w;
        }
        chosen.push_back(k);
        basis.worstFrameRms = worstRms();
    }

    basis.weights.assign(frames, std::vector<float>(chosen.size()));
    for (std::size_t i = 0; i < chosen.size(); ++i) {
        const double sigma = std::sqrt(eigen.eigenvalues()[chosen[i]]);
        const Eigen::VectorXd u = eigen.eigenvectors().col(chosen[i]);
        const Eigen::VectorXf t = (c.transpose() * (u / sigma).cast<float>());
        basis.components.emplace_back(t.data(), t.data() + t.size());
        for (std::size_t f = 0; f < frames; ++f)
            basis.weights[f][i] = float(sigma * u[Eigen::Index(f)]);
    }
    // The largest vertex error, from the reconstruction itself (what a player will show).
    double worstVertex = 0.0;
    std::vector<float> row(values);
    for (std::size_t f = 0; f < frames; ++f) {
        for (std::size_t j = 0; j < values; ++j)
            row[j] = basis.mean[j];
        for (std::size_t i = 0; i < chosen.size(); ++i)
            for (std::size_t j = 0; j < values; ++j)
                row[j] += basis.weights[f][i] * basis.components[i][j];
        for (std::size_t v = 0; v + 2 < values; v += 3) {
            double e2 = 0.0;
            for (std::size_t a = 0; a < 3; ++a) {
                const double e = double(row[v + a]) - double(deltas[f * values + v + a]);
                e2 += e * e;
            }
            worstVertex = std::max(worstVertex, std::sqrt(e2));
        }
    }
    basis.worstVertexError = worstVertex;
    return basis;
}

MorphBasis fitMorphComponentsFor(const MorphBasis& basis, std::span<const float> deltas, std::size_t frames,
                                 std::size_t values) {
    MorphBasis fitted;
    if (frames == 0 || values == 0 || deltas.size() != frames * values || basis.weights.size() != frames)
        return fitted;
    const RowMatrix c = centred(deltas, frames, values, fitted.mean);
    fitted.weights = basis.weights;
    const std::size_t k = basis.components.size();
    for (std::size_t i = 0; i < k; ++i) {
        // Least squares with orthogonal weight columns: T_i = Cᵀ w_i / |w_i|².
        Eigen::VectorXf w(static_cast<Eigen::Index>(frames));
        for (std::size_t f = 0; f < frames; ++f)
            w[Eigen::Index(f)] = basis.weights[f][i];
        const float norm2 = w.squaredNorm();
        const Eigen::VectorXf t = norm2 > 0.0f ? Eigen::VectorXf(c.transpose() * w / norm2) : Eigen::VectorXf::Zero(Eigen::Index(values));
        fitted.components.emplace_back(t.data(), t.data() + t.size());
    }
    return fitted;
}

}  // namespace softtouch
