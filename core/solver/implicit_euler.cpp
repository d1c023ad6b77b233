// Linearised backward Euler: matrix-free conjugate gradients preconditioned by the factorised
// rest-state matrix.
#include "core/solver/element_implicit_euler.h"
#include "core/solver/integrator.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>

namespace softtouch {
namespace {

/// Implicit Euler, linearised once per step (Baraff & Witkin 1998):
///   (M − h ∂f/∂v − h² ∂f/∂x) Δv = h (f + h ∂f/∂x v),   v += Δv,   x += h v.
/// Spring blocks use ∂f_a/∂x_a = −k [n nᵀ + t (I − n nᵀ)] with t = max(0, 1 − L/l) (the transverse
/// term is dropped under compression so the matrix stays positive definite), so a spring's block of
/// the system matrix is
///   S = h²k [n nᵀ + t (I − n nᵀ)] + h c n nᵀ = α I + β n nᵀ,   α = h²k t,   β = h²k (1 − t) + h c,
/// four numbers per spring instead of a 3x3 matrix. Pinned and void nodes are not unknowns at all
/// (Δv = 0 is a constraint, not a huge mass): the system is over the free nodes only, and a spring to
/// a pinned node adds to its free end's diagonal block. A drag spring couples every node of its
/// support (a dense block); instead of densifying the pattern its rank-3 term enters the solve as a
/// low-rank product U Uᵀ (Woodbury identity in the preconditioner).
class ImplicitEuler final : public Integrator {
public:
    IntegratorKind kind() const override { return IntegratorKind::ImplicitEuler; }
    bool isExplicit() const override { return false; }
    LinearSolveStats lastSolve() const override { return m_element ? m_element->lastSolve() : m_stats; }

    void step(const BodyModel& model, const ExternalForces& external, BodyState& state, double h) override {
        if (model.element) {  // the consistent mass couples every node: its own system
            if (!m_element)
                m_element = std::make_unique<ElementImplicitEuler>();
            m_element->step(model, external, state, h);
            return;
        }
        m_element.reset();
        if (&model != m_model || m_springCount != model.springs.size())
            analyse(model);
        if (h != m_restStep)
            factorRestMatrix(model, h);
        linearise(model, external, state, h);
        const Eigen::VectorXd& dv = solve();
        for (std::size_t f = 0; f < m_freeNodes.size(); ++f) {
            const std::uint32_t i = m_freeNodes[f];
            state.velocity[i] += dv.segment<3>(Eigen::Index(3 * f));
            state.position[i] += h * state.velocity[i];
        }
    }

private:
    /// The system for one state: each spring's (α, β, n), the diagonal M + h d, m_rhs and the drags' U.
    void linearise(const BodyModel& model, const ExternalForces& external, const BodyState& state, double h) {
        const std::size_t n = model.nodeCount();
        m_force.resize(n);
        accumulateForces(model, external, state.position, state.velocity, m_force, m_scratch);

        const std::size_t free = m_freeNodes.size();
        m_rhs.resize(Eigen::Index(3 * free));
        m_diagonal.resize(free);
        auto rhs = [&](std::uint32_t node) { return m_rhs.segment<3>(Eigen::Index(3 * m_dof[node])); };
        for (std::size_t f = 0; f < free; ++f) {
            const std::uint32_t i = m_freeNodes[f];
            m_diagonal[f] = model.mass[i] + h * model.nodeDamping[i];
            rhs(i) = h * m_force[i];
        }
        const SpringTable& t = model.springTable;  // springs with a free end
        for (std::size_t k = 0; k < t.size(); ++k) {
            const Vec3 r = state.position[t.b[k]] - state.position[t.a[k]];
            const double length = r.norm();
            if (length <= 0.0) {  // no direction: the spring drops out of this step's system
                m_alpha[k] = m_beta[k] = 0.0;
                m_direction[k].setZero();
                continue;
            }
            const Vec3 dir = r * (1.0 / length);  // one division, not three
            const double transverse = std::max(0.0, 1.0 - t.restLength[k] / length);
            m_alpha[k] = h * h * t.stiffness[k] * transverse;
            m_beta[k] = h * h * t.stiffness[k] * (1.0 - transverse) + h * t.damping[k];
            m_direction[k] = dir;
            // h² (∂f/∂x) v for this spring: node a gets h² k J (v_b − v_a), node b the opposite.
            const Vec3 dv = state.velocity[t.b[k]] - state.velocity[t.a[k]];
            const Vec3 kv = (h * h * t.stiffness[k]) * (transverse * dv + (1.0 - transverse) * dir.dot(dv) * dir);
            if (m_dofA[k] != m_padding)
                rhs(t.a[k]) += kv;
            if (m_dofB[k] != m_padding)
                rhs(t.b[k]) -= kv;
        }
        // Drags: rhs part of h² ∂f/∂x v, and the Woodbury factors U (3 columns per drag).
        const std::size_t drags = external.drags.size();
        m_U.setZero(m_rhs.size(), Eigen::Index(3 * drags));
        for (std::size_t d = 0; d < drags; ++d) {
            const DragSpring& drag = external.drags[d];
            Vec3 meanVelocity = Vec3::Zero();
            forEachDragShare(model, drag, [&](std::uint32_t node, double share) { meanVelocity += share * state.velocity[node]; });
            const double alpha = std::sqrt(h * h * drag.stiffness + h * drag.damping);
            forEachDragShare(model, drag, [&](std::uint32_t node, double share) {
                rhs(node) -= h * h * drag.stiffness * share * meanVelocity;
                for (int c = 0; c < 3; ++c)
                    m_U(Eigen::Index(3 * m_dof[node] + std::uint32_t(c)), Eigen::Index(3 * d + std::size_t(c))) = alpha * share;
            });
        }
    }

    /// y = A p without forming A: y_i = (M + h d)_i p_i + Σ_springs ±S (p_a − p_b), then the drags'
    /// U Uᵀ p. Springs are done first (each S (p_a − p_b) once, with a pinned end's p taken as 0 from
    /// a padding slot), then every node sums its own springs from the spring table's lists.
    void applyMatrix(const BodyModel& model, const Eigen::VectorXd& p, Eigen::VectorXd& y) {
        const SpringTable& t = model.springTable;
        const std::size_t free = m_freeNodes.size();
        m_padded.head(Eigen::Index(3 * free)) = p;  // the last three entries stay zero
        const double* pp = m_padded.data();
        const std::uint32_t* dofA = m_dofA.data();
        const std::uint32_t* dofB = m_dofB.data();
        const double* alpha = m_alpha.data();
        const double* beta = m_beta.data();
        const Vec3* direction = m_direction.data();
        Vec3* springProduct = m_springProduct.data();
        for (std::size_t k = 0; k < t.size(); ++k) {
            const double* pa = pp + 3 * dofA[k];
            const double* pb = pp + 3 * dofB[k];
            const Vec3 d(pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]);
            springProduct[k] = alpha[k] * d + (beta[k] * direction[k].dot(d)) * direction[k];
        }
        y.resize(Eigen::Index(3 * free));
        for (std::size_t f = 0; f < free; ++f) {
            const std::uint32_t i = m_freeNodes[f];
            Vec3 sum = m_diagonal[f] * p.segment<3>(Eigen::Index(3 * f));
            for (std::uint32_t e = t.startOffset[i]; e < t.startOffset[i + 1]; ++e)
                sum += springProduct[t.startSpring[e]];
            for (std::uint32_t e = t.endOffset[i]; e < t.endOffset[i + 1]; ++e)
                sum -= springProduct[t.endSpring[e]];
            y.segment<3>(Eigen::Index(3 * f)) = sum;
        }
        if (m_U.cols() > 0) {
            m_lowRank.noalias() = m_U.transpose() * p;
            y.noalias() += m_U * m_lowRank;
        }
    }

    /// Writes the linearised system into m_matrix (for factorisations only: CG runs matrix-free).
    void assembleMatrix(const BodyModel& model) {
        double* values = m_matrix.valuePtr();
        std::fill(values, values + m_matrix.nonZeros(), 0.0);
        auto addBlock = [&](const BlockOffsets& block, const Mat3& m, double sign) {
            for (int c = 0; c < 3; ++c)
                for (int r = 0; r < 3; ++r)
                    values[block[std::size_t(c)] + r] += sign * m(r, c);
        };
        for (std::size_t f = 0; f < m_freeNodes.size(); ++f)
            addBlock(m_nodeBlock[f], Mat3::Identity() * m_diagonal[f], 1.0);
        for (std::size_t k = 0; k < model.springTable.size(); ++k) {
            const Mat3 S = m_alpha[k] * Mat3::Identity() + m_beta[k] * (m_direction[k] * m_direction[k].transpose());
            const SpringBlocks& blocks = m_springBlocks[k];
            if (blocks.freeA)
                addBlock(blocks.aa, S, 1.0);
            if (blocks.freeB)
                addBlock(blocks.bb, S, 1.0);
            if (blocks.freeA && blocks.freeB) {
                addBlock(blocks.ab, S, -1.0);
                addBlock(blocks.ba, S, -1.0);
            }
        }
    }

    /// A factorisation: dense Cholesky for small systems, sparse LDLT (pattern analysed once) beyond.
    /// A dense factor used as a preconditioner keeps its explicit inverse in single precision: one
    /// matrix-vector product per application instead of two triangular solves, at half the memory
    /// traffic and twice the vector width. Its rounding only changes how fast CG converges, never what
    /// it converges to (CG's own products and residuals stay in double).
    struct Factor {
        bool dense = false;
        bool keepInverse = false;
        Eigen::LLT<Eigen::MatrixXd> llt;
        Eigen::MatrixXf inverse;
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
        Eigen::VectorXf bFloat, yFloat;  ///< Work vectors of solveInto().
        bool compute(const Eigen::SparseMatrix<double>& A) {
            if (dense) {
                llt.compute(Eigen::MatrixXd(A));
                if (keepInverse && llt.info() == Eigen::Success) {
                    const Eigen::MatrixXd full = llt.solve(Eigen::MatrixXd::Identity(A.rows(), A.cols()));
                    inverse = (0.5 * (full + full.transpose())).cast<float>();  // exactly symmetric, as CG needs
                }
                return llt.info() == Eigen::Success;
            }
            ldlt.factorize(A);
            return ldlt.info() == Eigen::Success;
        }
        template <typename Rhs>
        Eigen::MatrixXd solve(const Rhs& b) const {
            if (dense && keepInverse)
                return (inverse * b.template cast<float>()).template cast<double>();
            if (dense)
                return llt.solve(b);
            return ldlt.solve(b);
        }
        /// y = A⁻¹ b for one vector, allocating nothing once the work vectors have their size.
        void solveInto(const Eigen::VectorXd& b, Eigen::VectorXd& y) {
            if (dense && keepInverse) {
                bFloat = b.cast<float>();
                yFloat.noalias() = inverse * bFloat;
                y = yFloat.cast<double>();
            } else {
                y = solve(b);
            }
        }
    };

    /// The preconditioner: the factorised matrix of the body at rest for this step size. It depends on
    /// the model and h only — never on the history of the run — so every step's answer is a function
    /// of its state and inputs alone, and saveState/restoreState replays bit for bit.
    void factorRestMatrix(const BodyModel& model, double h) {
        linearise(model, ExternalForces{}, restState(model), h);
        assembleMatrix(model);
        m_restReady = m_rest.compute(m_matrix);
        m_restStep = h;
        m_restU.resize(0, 0);
    }

    /// Solves (A + U Uᵀ) Δv = rhs by conjugate gradients preconditioned with (A_rest + U Uᵀ)⁻¹ (Woodbury
    /// for the drags' low-rank term), converged to a relative residual of 1e-10. Deformation rotates the
    /// springs away from rest; when CG has not converged after kMaxIterations the current matrix itself
    /// is assembled, factorised and solved directly (exact, and again a function of the state alone).
    const Eigen::VectorXd& solve() {
        m_stats = {};
        const double bNorm = m_rhs.norm();
        if (bNorm == 0.0) {
            m_x.setZero(m_rhs.size());
            return m_x;
        }
        if (m_restReady && conjugateGradients(1e-10 * bNorm))
            return m_x;
        // Direct fallback: factorise A, add the drags through Woodbury.
        m_stats.direct = true;
        assembleMatrix(*m_model);
        const bool ok = m_step.compute(m_matrix);
        m_x = m_step.solve(m_rhs);
        if (m_U.cols() > 0) {
            const Eigen::MatrixXd Z = m_step.solve(m_U);
            const Eigen::MatrixXd small = Eigen::MatrixXd::Identity(m_U.cols(), m_U.cols()) + m_U.transpose() * Z;
            m_x -= Z * small.ldlt().solve(m_U.transpose() * m_x);
        }
        if (!ok || !m_x.allFinite())
            m_x.setConstant(std::numeric_limits<double>::quiet_NaN());  // the simulator rolls back and reports
        return m_x;
    }

    bool conjugateGradients(double tolerance) {
        // Woodbury data for this U; recomputed only when the drags' terms change (same U, same numbers).
        if (m_U.rows() != m_restU.rows() || m_U.cols() != m_restU.cols() || m_U != m_restU) {
            m_restU = m_U;
            if (m_U.cols() > 0) {
                m_Z = m_rest.solve(m_U);
                m_small = (Eigen::MatrixXd::Identity(m_U.cols(), m_U.cols()) + m_U.transpose() * m_Z).ldlt();
            }
        }
        auto precondition = [&](const Eigen::VectorXd& r, Eigen::VectorXd& y) {
            m_rest.solveInto(r, y);
            if (m_U.cols() > 0) {
                m_lowRank.noalias() = m_U.transpose() * y;
                m_small.solveInPlace(m_lowRank);
                y.noalias() -= m_Z * m_lowRank;
            }
        };
        m_x.setZero(m_rhs.size());
        m_r = m_rhs;
        precondition(m_r, m_z);
        m_p = m_z;
        double rz = m_r.dot(m_z);
        for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
            m_stats.iterations = iteration + 1;
            applyMatrix(*m_model, m_p, m_Ap);
            const double alpha = rz / m_p.dot(m_Ap);
            m_x += alpha * m_p;
            m_r -= alpha * m_Ap;
            if (m_r.norm() <= tolerance)
                return m_x.allFinite();
            precondition(m_r, m_z);
            const double rzNext = m_r.dot(m_z);
            m_p = m_z + (rzNext / rz) * m_p;
            rz = rzNext;
        }
        return false;
    }

    static constexpr int kMaxIterations = 30;
    /// Up to this many unknowns (4x4x4: 192, 8x4x4: 384, fewer with anchors) factors are dense: the
    /// sparse factor is nearly dense anyway, and dense kernels vectorise. Beyond it O(n³) loses to the
    /// sparse LDLT.
    static constexpr std::size_t kDenseUnknowns = 600;

    /// Offsets into the value array of column 3c..3c+2 at row 3r (rows 3r+1, 3r+2 follow).
    using BlockOffsets = std::array<Eigen::Index, 3>;
    /// Where a table spring's 3x3 blocks sit in m_matrix's values (only the free ends' blocks exist).
    struct SpringBlocks {
        BlockOffsets aa{}, bb{}, ab{}, ba{};
        bool freeA = false, freeB = false;
    };

    /// Numbers the free nodes, lays out the sparse pattern (for factorisations) and sizes the work arrays.
    void analyse(const BodyModel& model) {
        const std::size_t n = model.nodeCount();
        constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
        m_dof.assign(n, none);
        m_freeNodes.clear();
        for (std::size_t i = 0; i < n; ++i) {
            if (model.inverseMass[i] > 0.0) {
                m_dof[i] = std::uint32_t(m_freeNodes.size());
                m_freeNodes.push_back(std::uint32_t(i));
            }
        }
        const std::uint32_t free = std::uint32_t(m_freeNodes.size());
        m_padding = free;  // the zero slot a pinned end reads in applyMatrix()
        const SpringTable& t = model.springTable;
        m_dofA.resize(t.size());
        m_dofB.resize(t.size());
        for (std::size_t k = 0; k < t.size(); ++k) {
            m_dofA[k] = m_dof[t.a[k]] == none ? m_padding : m_dof[t.a[k]];
            m_dofB[k] = m_dof[t.b[k]] == none ? m_padding : m_dof[t.b[k]];
        }
        m_alpha.assign(t.size(), 0.0);
        m_beta.assign(t.size(), 0.0);
        m_direction.assign(t.size(), Vec3::Zero());
        m_springProduct.assign(t.size(), Vec3::Zero());
        m_padded.setZero(Eigen::Index(3 * (free + 1)));

        std::vector<Eigen::Triplet<double>> pattern;
        auto addPattern = [&](std::uint32_t r, std::uint32_t c) {
            for (std::uint32_t i = 0; i < 3; ++i)
                for (std::uint32_t j = 0; j < 3; ++j)
                    pattern.emplace_back(Eigen::Index(3 * r + i), Eigen::Index(3 * c + j), 1.0);
        };
        for (std::uint32_t f = 0; f < free; ++f)
            addPattern(f, f);
        for (std::size_t k = 0; k < t.size(); ++k) {
            if (m_dofA[k] != m_padding && m_dofB[k] != m_padding) {
                addPattern(m_dofA[k], m_dofB[k]);
                addPattern(m_dofB[k], m_dofA[k]);
            }
        }
        const Eigen::Index unknowns = Eigen::Index(3 * free);
        m_matrix.resize(unknowns, unknowns);
        m_matrix.setFromTriplets(pattern.begin(), pattern.end());
        m_matrix.makeCompressed();
        auto offsets = [&](std::uint32_t r, std::uint32_t c) {
            BlockOffsets block{};
            for (std::uint32_t j = 0; j < 3; ++j) {
                const Eigen::Index column = Eigen::Index(3 * c + j);
                const auto* begin = m_matrix.innerIndexPtr() + m_matrix.outerIndexPtr()[column];
                const auto* end = m_matrix.innerIndexPtr() + m_matrix.outerIndexPtr()[column + 1];
                block[j] = std::lower_bound(begin, end, Eigen::Index(3 * r)) - m_matrix.innerIndexPtr();
            }
            return block;
        };
        m_nodeBlock.resize(free);
        for (std::uint32_t f = 0; f < free; ++f)
            m_nodeBlock[f] = offsets(f, f);
        m_springBlocks.assign(t.size(), SpringBlocks{});
        for (std::size_t k = 0; k < t.size(); ++k) {
            const std::uint32_t a = m_dofA[k], b = m_dofB[k];
            SpringBlocks& blocks = m_springBlocks[k];
            blocks.freeA = a != m_padding;
            blocks.freeB = b != m_padding;
            if (blocks.freeA)
                blocks.aa = offsets(a, a);
            if (blocks.freeB)
                blocks.bb = offsets(b, b);
            if (blocks.freeA && blocks.freeB) {
                blocks.ab = offsets(a, b);
                blocks.ba = offsets(b, a);
            }
        }
        m_rest.dense = m_step.dense = std::size_t(unknowns) <= kDenseUnknowns;
        m_rest.keepInverse = true;
        if (!m_rest.dense) {
            m_rest.ldlt.analyzePattern(m_matrix);
            m_step.ldlt.analyzePattern(m_matrix);
        }
        m_restStep = -1.0;  // the rest factor is made on the first step, when h is known
        m_model = &model;
        m_springCount = model.springs.size();
    }

    std::unique_ptr<ElementImplicitEuler> m_element;  ///< For a solid element body.
    const BodyModel* m_model = nullptr;
    std::size_t m_springCount = 0;
    LinearSolveStats m_stats;
    // Unknowns.
    std::vector<std::uint32_t> m_dof;        ///< Per node: its index among the free nodes (unknowns / 3).
    std::vector<std::uint32_t> m_freeNodes;  ///< Per free node: the body's node.
    std::uint32_t m_padding = 0;             ///< Free-node index of the zero slot (= free node count).
    std::vector<std::uint32_t> m_dofA, m_dofB; ///< Per table spring: its ends' free indices, or m_padding.
    // This step's system.
    std::vector<double> m_alpha, m_beta;     ///< Per table spring: S = α I + β n nᵀ.
    std::vector<Vec3> m_direction;           ///< Per table spring: n.
    std::vector<double> m_diagonal;          ///< Per free node: m + h d.
    Eigen::MatrixXd m_U;                     ///< Drag terms (3 columns per drag).
    Eigen::VectorXd m_rhs;
    std::vector<Vec3> m_force;
    SpringScratch m_scratch;
    // Factorisations (rest preconditioner and direct fallback) and their assembled matrix.
    Eigen::SparseMatrix<double> m_matrix;
    std::vector<BlockOffsets> m_nodeBlock;    ///< Per free node: its diagonal block.
    std::vector<SpringBlocks> m_springBlocks; ///< Per table spring.
    Factor m_rest;                   ///< Factorised rest matrix for step m_restStep: the preconditioner.
    Factor m_step;                   ///< Scratch for the direct fallback.
    bool m_restReady = false;
    double m_restStep = -1.0;
    Eigen::MatrixXd m_restU;         ///< The U that m_Z and m_small belong to.
    Eigen::MatrixXd m_Z;             ///< A_rest⁻¹ U.
    Eigen::LDLT<Eigen::MatrixXd> m_small;
    // Conjugate gradients (kept: no allocation per step).
    Eigen::VectorXd m_x, m_r, m_z, m_p, m_Ap;
    Eigen::VectorXd m_padded;                ///< p with a zero node appended (applyMatrix()).
    Eigen::VectorXd m_lowRank;               ///< Uᵀ times a vector (3 per drag).
    std::vector<Vec3> m_springProduct;       ///< Per table spring: S (p_a − p_b).
};

}  // namespace

std::unique_ptr<Integrator> makeImplicitEuler() { return std::make_unique<ImplicitEuler>(); }

}  // namespace softtouch
