// Linearised backward Euler: sparse LDLT (pattern analysed once per model) preconditioning a CG solve.
#include "core/integrator.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

namespace softtouch {
namespace {

/// Implicit Euler, linearised once per step (Baraff & Witkin 1998):
///   (M − h ∂f/∂v − h² ∂f/∂x) Δv = h (f + h ∂f/∂x v),   v += Δv,   x += h v.
/// Spring blocks use ∂f_a/∂x_a = −k [n nᵀ + max(0, 1 − L/l)(I − n nᵀ)] (the transverse term is
/// dropped under compression so the matrix stays positive definite). Pinned nodes are constraints:
/// their rows are the identity with Δv = 0, not a huge mass. A drag spring couples every node of its
/// support (a dense block); instead of densifying the pattern its rank-3 term α (ŵŵᵀ ⊗ I) enters the
/// solve as a low-rank term (Woodbury identity in the preconditioner).
class ImplicitEuler final : public Integrator {
public:
    IntegratorKind kind() const override { return IntegratorKind::ImplicitEuler; }
    bool isExplicit() const override { return false; }

    void step(const BodyModel& model, const ExternalForces& external, BodyState& state, double h) override {
        if (&model != m_model || m_springCount != model.springs.size())
            analyse(model);
        const std::size_t n = model.nodeCount();
        m_force.resize(n);
        accumulateForces(model, external, state.position, state.velocity, m_force);

        double* values = m_matrix.valuePtr();
        std::fill(values, values + m_matrix.nonZeros(), 0.0);
        m_rhs.setZero(Eigen::Index(3 * n));
        auto addBlock = [&](const BlockOffsets& block, const Mat3& m, double sign) {
            for (int c = 0; c < 3; ++c)
                for (int r = 0; r < 3; ++r)
                    values[block[std::size_t(c)] + r] += sign * m(r, c);
        };
        auto isFree = [&](std::size_t i) { return model.inverseMass[i] > 0.0; };
        for (std::size_t i = 0; i < n; ++i) {
            const double diagonal = isFree(i) ? model.mass[i] + h * model.airDamping : 1.0;
            addBlock(m_nodeBlock[i], Mat3::Identity() * diagonal, 1.0);
            if (isFree(i))
                m_rhs.segment<3>(Eigen::Index(3 * i)) = h * m_force[i];
        }
        for (std::size_t k = 0; k < model.springs.size(); ++k) {
            const Spring& s = model.springs[k];
            const Vec3 r = state.position[s.b] - state.position[s.a];
            const double length = r.norm();
            if (length <= 0.0)
                continue;
            const Vec3 dir = r * (1.0 / length);  // one division, not three
            const Mat3 nnT = dir * dir.transpose();
            const double transverse = std::max(0.0, 1.0 - s.restLength / length);
            const Mat3 J = nnT + transverse * (Mat3::Identity() - nnT);
            const Mat3 S = (h * h * s.stiffness) * J + (h * s.damping) * nnT;
            const bool a = isFree(s.a), b = isFree(s.b);
            // h² (∂f/∂x) v for this spring: node a gets k J (v_b − v_a), node b the opposite.
            const Vec3 kv = s.stiffness * (J * (state.velocity[s.b] - state.velocity[s.a]));
            if (a) {
                addBlock(m_nodeBlock[s.a], S, 1.0);
                m_rhs.segment<3>(Eigen::Index(3 * s.a)) += h * h * kv;
            }
            if (b) {
                addBlock(m_nodeBlock[s.b], S, 1.0);
                m_rhs.segment<3>(Eigen::Index(3 * s.b)) -= h * h * kv;
            }
            if (a && b) {
                addBlock(m_springBlock[k][0], S, -1.0);
                addBlock(m_springBlock[k][1], S, -1.0);
            }
        }
        // Drags: rhs part of h² ∂f/∂x v, and the Woodbury factors U (3n x 3 per drag).
        const std::size_t drags = external.drags.size();
        m_U.setZero(Eigen::Index(3 * n), Eigen::Index(3 * drags));
        for (std::size_t d = 0; d < drags; ++d) {
            const DragSpring& drag = external.drags[d];
            const std::vector<NodeWeight> weights = dragDistribution(model, drag);
            Vec3 meanVelocity = Vec3::Zero();
            for (const NodeWeight& w : weights)
                meanVelocity += w.weight * state.velocity[w.node];
            const double alpha = std::sqrt(h * h * drag.stiffness + h * drag.damping);
            for (const NodeWeight& w : weights) {
                m_rhs.segment<3>(Eigen::Index(3 * w.node)) -= h * h * drag.stiffness * w.weight * meanVelocity;
                for (int c = 0; c < 3; ++c)
                    m_U(Eigen::Index(3 * w.node + std::size_t(c)), Eigen::Index(3 * d + std::size_t(c))) = alpha * w.weight;
            }
        }

        const Eigen::VectorXd& dv = solve();
        for (std::size_t i = 0; i < n; ++i) {
            if (!isFree(i))
                continue;
            state.velocity[i] += dv.segment<3>(Eigen::Index(3 * i));
            state.position[i] += h * state.velocity[i];
        }
    }

private:
    /// Solves (A + U Uᵀ) Δv = rhs. The matrix changes little from one step to the next, so the LDLT
    /// factorisation of a recent A (with Uᵀ folded in through Woodbury) preconditions a conjugate
    /// gradient solve of the current one: a few cheap iterations instead of a new factorisation. When
    /// the old factorisation stops being a good preconditioner (more than kRefactorAfter iterations),
    /// the matrix is factorised again. The solution is converged to a relative residual of 1e-10
    /// either way, so reuse changes the cost, not the answer's accuracy.
    const Eigen::VectorXd& solve() {
        const bool sameU = m_U.rows() == m_factorU.rows() && m_U.cols() == m_factorU.cols() && m_U == m_factorU;
        if (!m_factorized) {
            refactor();
        } else if (!sameU) {
            m_factorU = m_U;
            updateWoodbury();
        }
        auto apply = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
            y.noalias() = m_matrix * x;
            if (m_U.cols() > 0)
                y.noalias() += m_U * (m_U.transpose() * x);
        };
        const double bNorm = m_rhs.norm();
        if (bNorm == 0.0) {
            m_x.setZero(m_rhs.size());
            return m_x;
        }
        const double tolerance = 1e-10 * bNorm;
        for (int attempt = 0; attempt < 2; ++attempt) {
            // Start from zero: the first preconditioned step then is the old factorisation's answer.
            m_x.setZero(m_rhs.size());
            m_r = m_rhs;
            precondition(m_r, m_z);
            m_p = m_z;
            double rz = m_r.dot(m_z);
            int iterations = 0;
            while (iterations < kMaxIterations) {
                apply(m_p, m_Ap);
                const double alpha = rz / m_p.dot(m_Ap);
                m_x += alpha * m_p;
                m_r -= alpha * m_Ap;
                ++iterations;
                if (!(m_r.norm() > tolerance))
                    break;  // converged (or NaN: reported below)
                precondition(m_r, m_z);
                const double rzNext = m_r.dot(m_z);
                m_p = m_z + (rzNext / rz) * m_p;
                rz = rzNext;
            }
            Eigen::VectorXd& x = m_x;
            Eigen::VectorXd& r = m_r;
            if (!(r.norm() <= tolerance) && attempt == 0) {
                refactor();  // the preconditioner is too stale: factorise this matrix and solve again
                continue;
            }
            if (iterations > kRefactorAfter)
                m_factorized = false;  // solved, but refresh the factorisation for the next step
            if (m_solver.info() != Eigen::Success || !x.allFinite())
                x.setConstant(std::numeric_limits<double>::quiet_NaN());  // the simulator rolls back and reports
            return x;
        }
        m_x.setConstant(m_rhs.size(), std::numeric_limits<double>::quiet_NaN());
        return m_x;
    }

    void refactor() {
        m_solver.factorize(m_matrix);
        m_factorized = true;
        m_factorU = m_U;
        updateWoodbury();
    }

    /// Z = A_f⁻¹ U and the small Woodbury matrix (I + Uᵀ Z), for the current U.
    void updateWoodbury() {
        if (m_factorU.cols() == 0)
            return;
        m_Z = m_solver.solve(m_factorU);
        m_small = (Eigen::MatrixXd::Identity(m_factorU.cols(), m_factorU.cols()) + m_factorU.transpose() * m_Z).ldlt();
    }

    /// y = (A_f + U Uᵀ)⁻¹ r by Woodbury.
    void precondition(const Eigen::VectorXd& r, Eigen::VectorXd& y) const {
        y = m_solver.solve(r);
        if (m_factorU.cols() > 0)
            y.noalias() -= m_Z * m_small.solve(m_factorU.transpose() * y);
    }

    static constexpr int kMaxIterations = 25;
    static constexpr int kRefactorAfter = 4;

    /// Offsets into the value array of column 3c..3c+2 at row 3r (rows 3r+1, 3r+2 follow).
    using BlockOffsets = std::array<Eigen::Index, 3>;

    void analyse(const BodyModel& model) {
        const std::size_t n = model.nodeCount();
        std::vector<Eigen::Triplet<double>> pattern;
        auto addPattern = [&](std::size_t r, std::size_t c) {
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    pattern.emplace_back(Eigen::Index(3 * r + std::size_t(i)), Eigen::Index(3 * c + std::size_t(j)), 1.0);
        };
        for (std::size_t i = 0; i < n; ++i)
            addPattern(i, i);
        for (const Spring& s : model.springs) {
            addPattern(s.a, s.b);
            addPattern(s.b, s.a);
        }
        m_matrix.resize(Eigen::Index(3 * n), Eigen::Index(3 * n));
        m_matrix.setFromTriplets(pattern.begin(), pattern.end());
        m_matrix.makeCompressed();
        auto offsets = [&](std::size_t r, std::size_t c) {
            BlockOffsets block{};
            for (int j = 0; j < 3; ++j) {
                const Eigen::Index column = Eigen::Index(3 * c + std::size_t(j));
                const auto* begin = m_matrix.innerIndexPtr() + m_matrix.outerIndexPtr()[column];
                const auto* end = m_matrix.innerIndexPtr() + m_matrix.outerIndexPtr()[column + 1];
                block[std::size_t(j)] = std::lower_bound(begin, end, Eigen::Index(3 * r)) - m_matrix.innerIndexPtr();
            }
            return block;
        };
        m_nodeBlock.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            m_nodeBlock[i] = offsets(i, i);
        m_springBlock.resize(model.springs.size());
        for (std::size_t k = 0; k < model.springs.size(); ++k)
            m_springBlock[k] = {offsets(model.springs[k].a, model.springs[k].b),
                                offsets(model.springs[k].b, model.springs[k].a)};
        m_solver.analyzePattern(m_matrix);
        m_factorized = false;
        m_model = &model;
        m_springCount = model.springs.size();
    }

    const BodyModel* m_model = nullptr;
    std::size_t m_springCount = 0;
    Eigen::SparseMatrix<double> m_matrix;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> m_solver;
    bool m_factorized = false;       ///< m_solver holds a factorisation of a recent matrix.
    Eigen::MatrixXd m_U;             ///< Drag terms of this step (3n x 3 per drag).
    Eigen::MatrixXd m_factorU;       ///< The U that m_Z and m_small were computed for.
    Eigen::MatrixXd m_Z;             ///< A_f⁻¹ U.
    Eigen::LDLT<Eigen::MatrixXd> m_small;
    Eigen::VectorXd m_x, m_r, m_z, m_p, m_Ap;  ///< Conjugate gradient work vectors (kept: no allocation per step).
    std::vector<BlockOffsets> m_nodeBlock;
    std::vector<std::array<BlockOffsets, 2>> m_springBlock;
    std::vector<Vec3> m_force;
    Eigen::VectorXd m_rhs;
};

}  // namespace

std::unique_ptr<Integrator> makeImplicitEuler() { return std::make_unique<ImplicitEuler>(); }

}  // namespace softtouch
