#include "core/animation/goal_fit.h"

#include <Eigen/SVD>

#include <algorithm>
#include <array>

namespace softtouch {

namespace {

/// (BᵀB + λ I)⁻¹ rhs for the three columns together: SimplicialLDLT::solve's steps (P, L, D⁻¹, Lᵀ, P⁻¹) with, in each
/// column, the same operations in the same order as Eigen's sparse triangular solves make them, so the result is bit
/// for bit solve()'s. Eigen solves one column at a time, each pass over the factor a chain of dependent updates; on
/// the guppy's 512-node Bezier net the factor is dense and the two solves were a third of a step.
Eigen::MatrixX3d solveNormal(const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& normal, const Eigen::MatrixX3d& rhs) {
    Eigen::MatrixX3d x = normal.permutationP().size() > 0 ? Eigen::MatrixX3d(normal.permutationP() * rhs) : rhs;
    const Eigen::SparseMatrix<double>& l = normal.matrixL().nestedExpression();  // strictly lower, unit diagonal
    const int* starts = l.outerIndexPtr();
    const int* rows = l.innerIndexPtr();
    const double* value = l.valuePtr();
    const Eigen::Index n = x.rows();
    // Column i's first entry below the diagonal, as Eigen's iterators reach it (past any above it and the diagonal).
    const auto belowDiagonal = [&](Eigen::Index i) {
        int k = starts[i];
        while (k < starts[i + 1] && rows[k] < i)
            ++k;
        if (k < starts[i + 1] && rows[k] == i)
            ++k;
        return k;
    };
    // L y = P rhs, column-oriented (Eigen's Lower/ColMajor solve): entry i, once final, is scattered down its column,
    // in each column of x only where it is not 0.
    for (Eigen::Index i = 0; i < n; ++i) {
        const double t0 = x(i, 0), t1 = x(i, 1), t2 = x(i, 2);
        for (int k = belowDiagonal(i), end = starts[i + 1]; k < end; ++k) {
            const Eigen::Index r = rows[k];
            if (t0 != 0.0)
                x(r, 0) -= t0 * value[k];
            if (t1 != 0.0)
                x(r, 1) -= t1 * value[k];
            if (t2 != 0.0)
                x(r, 2) -= t2 * value[k];
        }
    }
    // D⁻¹ as Eigen applies it: the inverse diagonal times each entry.
    const Eigen::VectorXd& d = normal.vectorD();
    for (Eigen::Index i = 0; i < n; ++i) {
        const double inverse = 1.0 / d(i);
        x.row(i) = (inverse * x.row(i).array()).matrix();
    }
    // Lᵀ z = y, row-oriented (Eigen's Upper/RowMajor solve on the transposed factor): from the last row up, each
    // entry's sum of the rows below it, in the factor's stored order.
    for (Eigen::Index i = n - 1; i >= 0; --i) {
        double t0 = x(i, 0), t1 = x(i, 1), t2 = x(i, 2);
        for (int k = belowDiagonal(i), end = starts[i + 1]; k < end; ++k) {
            const Eigen::Index r = rows[k];
            t0 -= value[k] * x(r, 0);
            t1 -= value[k] * x(r, 1);
            t2 -= value[k] * x(r, 2);
        }
        x(i, 0) = t0;
        x(i, 1) = t1;
        x(i, 2) = t2;
    }
    return normal.permutationPinv().size() > 0 ? Eigen::MatrixX3d(normal.permutationPinv() * x) : x;
}

}  // namespace

Result<GoalFit> GoalFit::create(const Lattice& lattice, std::span<const Vec3f> restPositions,
                                std::span<const Vec3> parameters) {
    const auto vertices = Eigen::Index(restPositions.size());
    const auto n = Eigen::Index(lattice.nodeCount());
    if (vertices == 0 || std::size_t(vertices) != parameters.size())
        return Status::error("goal fit: the mesh has no vertices bound to the lattice");
    GoalFit g;
    std::vector<Eigen::Triplet<double>> entries;
    for (Eigen::Index v = 0; v < vertices; ++v) {
        const Vec3& u = parameters[std::size_t(v)];
        const BasisSample a = lattice.axis(0).sample(u.x()), b = lattice.axis(1).sample(u.y()), c = lattice.axis(2).sample(u.z());
        for (int k = 0; k < c.order; ++k)
            for (int j = 0; j < b.order; ++j)
                for (int i = 0; i < a.order; ++i) {
                    const double w = a.value[std::size_t(i)] * b.value[std::size_t(j)] * c.value[std::size_t(k)];
                    if (w != 0.0)
                        entries.emplace_back(v, lattice.index(a.first + i, b.first + j, c.first + k), w);
                }
    }
    g.m_weights.resize(vertices, n);
    g.m_weights.setFromTriplets(entries.begin(), entries.end());  // compressed: fit() reads its arrays
    Eigen::SparseMatrix<double> normal = Eigen::SparseMatrix<double>(g.m_weights.transpose()) * g.m_weights;
    g.m_lambda = kGoalFitRidge * normal.diagonal().sum() / double(n);
    Eigen::SparseMatrix<double> identity(n, n);
    identity.setIdentity();
    normal += g.m_lambda * identity;
    auto factored = std::make_shared<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(normal);
    if (factored->info() != Eigen::Success)
        return Status::error("goal fit: the lattice's normal matrix could not be factored");
    g.m_normal = std::move(factored);
    g.m_restHomogeneous.resize(vertices, 4);
    for (Eigen::Index v = 0; v < vertices; ++v)
        g.m_restHomogeneous.row(v) << restPositions[std::size_t(v)].cast<double>().transpose(), 1.0;
    const Eigen::Matrix4d affine = g.m_restHomogeneous.transpose() * g.m_restHomogeneous;
    g.m_affine.compute(affine);
    // A mesh flat along some axis has no unique affine fit: its volume is what says so.
    if (g.m_affine.info() != Eigen::Success || !(std::abs(g.m_affine.vectorD().minCoeff()) > 1e-12 * affine.trace()))
        return Status::error("goal fit: the mesh is flat, so no motion of it fixes the lattice around it");
    g.m_restNodes.resize(n, 4);
    for (Eigen::Index i = 0; i < n; ++i)
        g.m_restNodes.row(i) << lattice.restNodes()[std::size_t(i)].transpose(), 1.0;
    return g;
}

void GoalFit::fit(std::span<const Vec3f> positions, std::vector<Vec3>& nodes, Mat3& rotation) const {
    const Eigen::Index vertices = m_weights.rows();
    Eigen::MatrixX3d p(vertices, 3);
    for (Eigen::Index v = 0; v < vertices; ++v)
        p.row(v) = positions[std::size_t(v)].cast<double>().transpose();
    // The affine fit T (4×3): p ≈ [p_rest 1] T.
    const Eigen::Matrix<double, 4, 3> t = m_affine.solve(m_restHomogeneous.transpose() * p);
    const Eigen::MatrixX3d prior = m_restNodes * t;
    // Bᵀp in one pass over B, a node's three sums together, four nodes at a time. Eigen's product makes the same
    // sums in the same order (bit for bit) but one column of p at a time, reading B three times, and each sum waits
    // on its previous add: on a Bezier 8x8x8 net every vertex weighs every node, so B is 3,198 × 512 dense on the
    // guppy and those sums were most of a step. Four nodes' sums are twelve chains that do not wait on each other.
    const int* starts = m_weights.outerIndexPtr();
    const int* vertexOf = m_weights.innerIndexPtr();
    const double* weight = m_weights.valuePtr();
    const Eigen::Index n = m_weights.cols();
    Eigen::MatrixX3d weighted(n, 3);
    Eigen::Index node = 0;
    for (; node + 4 <= n; node += 4) {
        std::array<int, 4> at{}, end{};
        std::array<double, 4> x{}, y{}, z{};
        for (int k = 0; k < 4; ++k) {
            at[std::size_t(k)] = starts[node + k];
            end[std::size_t(k)] = starts[node + k + 1];
        }
        const int common = std::min({end[0] - at[0], end[1] - at[1], end[2] - at[2], end[3] - at[3]});
        for (int e = 0; e < common; ++e)
            for (std::size_t k = 0; k < 4; ++k) {
                const int i = at[k] + e;
                const Vec3f& q = positions[std::size_t(vertexOf[i])];
                x[k] += weight[i] * double(q.x());
                y[k] += weight[i] * double(q.y());
                z[k] += weight[i] * double(q.z());
            }
        for (std::size_t k = 0; k < 4; ++k) {
            for (int i = at[k] + common; i < end[k]; ++i) {
                const Vec3f& q = positions[std::size_t(vertexOf[i])];
                x[k] += weight[i] * double(q.x());
                y[k] += weight[i] * double(q.y());
                z[k] += weight[i] * double(q.z());
            }
            weighted.row(node + Eigen::Index(k)) << x[k], y[k], z[k];
        }
    }
    for (; node < n; ++node) {
        double x = 0.0, y = 0.0, z = 0.0;
        for (int i = starts[node]; i < starts[node + 1]; ++i) {
            const Vec3f& q = positions[std::size_t(vertexOf[i])];
            x += weight[i] * double(q.x());
            y += weight[i] * double(q.y());
            z += weight[i] * double(q.z());
        }
        weighted.row(node) << x, y, z;
    }
    const Eigen::MatrixX3d x = solveNormal(*m_normal, weighted + m_lambda * prior);
    nodes.resize(std::size_t(x.rows()));
    for (Eigen::Index i = 0; i < x.rows(); ++i)
        nodes[std::size_t(i)] = x.row(i).transpose();
    // Rows of T's linear part map row vectors: the column-vector map is its transpose.
    const Mat3 linear = t.topRows<3>().transpose();
    const Eigen::JacobiSVD<Mat3> svd(linear, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 u = svd.matrixU();
    if ((u * svd.matrixV().transpose()).determinant() < 0.0)
        u.col(2) = -u.col(2);
    rotation = u * svd.matrixV().transpose();
}

}  // namespace softtouch
