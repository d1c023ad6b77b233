#include "bench/static_response.h"

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>

namespace softtouch::bench {
namespace {

constexpr int kMaxIterations = 40;
constexpr double kTolerance = 2e-4;  ///< Relative change of the displacement per iteration.

/// E, its gradient and its Hessian over the free nodes of one body.
class DragEquilibrium {
public:
    DragEquilibrium(const BodyModel& model, const std::vector<NodeWeight>& support, const Vec3& target, double ks)
        : m_model(model), m_support(support), m_target(target), m_ks(ks) {
        m_dof.assign(model.nodeCount(), -1);
        for (std::size_t i = 0; i < model.nodeCount(); ++i) {
            if (model.inverseMass[i] > 0.0) {
                m_dof[i] = int(m_free.size());
                m_free.push_back(i);
            }
        }
    }
    Eigen::Index unknowns() const { return Eigen::Index(3 * m_free.size()); }
    void gather(const std::vector<Vec3>& nodes, Eigen::VectorXd& x) const {
        x.resize(unknowns());
        for (std::size_t f = 0; f < m_free.size(); ++f)
            x.segment<3>(Eigen::Index(3 * f)) = nodes[m_free[f]];
    }
    void scatter(const Eigen::VectorXd& x, std::vector<Vec3>& nodes) const {
        for (std::size_t f = 0; f < m_free.size(); ++f)
            nodes[m_free[f]] = x.segment<3>(Eigen::Index(3 * f));
    }
    /// E at `nodes`, and its gradient over the free nodes.
    double energy(const std::vector<Vec3>& nodes, Eigen::VectorXd& gradient) const {
        gradient.setZero(unknowns());
        double e = 0.0;
        for (const Spring& s : m_model.springs) {
            const Vec3 r = nodes[s.b] - nodes[s.a];
            const double length = r.norm();
            const double stretch = length - s.restLength;
            e += 0.5 * s.stiffness * stretch * stretch;
            if (length <= 0.0)
                continue;
            const Vec3 pull = (s.stiffness * stretch / length) * r;  // ∂E/∂x_b
            add(gradient, s.b, pull);
            add(gradient, s.a, -pull);
        }
        const Vec3 miss = dragPoint(nodes) - m_target;
        e += 0.5 * m_ks * miss.squaredNorm();
        for (const NodeWeight& w : m_support)
            add(gradient, w.node, m_ks * w.weight * miss);
        return e;
    }
    /// The positive semi-definite Hessian at `nodes` (lower triangle, what SimplicialLDLT reads).
    void hessian(const std::vector<Vec3>& nodes, Eigen::SparseMatrix<double>& h) {
        m_triplets.clear();
        for (std::size_t f = 0; f < m_free.size(); ++f)
            block(int(f), int(f), Mat3::Identity() * kShift);
        for (const Spring& s : m_model.springs) {
            const Vec3 r = nodes[s.b] - nodes[s.a];
            const double length = r.norm();
            if (length <= 0.0)
                continue;
            const Vec3 n = r / length;
            const double t = std::max(0.0, 1.0 - s.restLength / length);
            const Mat3 k = s.stiffness * ((1.0 - t) * n * n.transpose() + t * Mat3::Identity());
            const int a = m_dof[s.a], b = m_dof[s.b];
            block(a, a, k);
            block(b, b, k);
            block(a, b, -k);
            block(b, a, -k);
        }
        for (const NodeWeight& i : m_support)
            for (const NodeWeight& j : m_support)
                block(m_dof[i.node], m_dof[j.node], Mat3::Identity() * (m_ks * i.weight * j.weight));
        h.resize(unknowns(), unknowns());
        h.setFromTriplets(m_triplets.begin(), m_triplets.end());
    }
    Vec3 dragPoint(const std::vector<Vec3>& nodes) const {
        Vec3 p = Vec3::Zero();
        for (const NodeWeight& w : m_support)
            p += w.weight * nodes[w.node];
        return p;
    }

private:
    /// Keeps the factorisation defined where a free node has no spring pulling it in some direction.
    static constexpr double kShift = 1e-9;

    void add(Eigen::VectorXd& g, std::uint32_t node, const Vec3& v) const {
        if (m_dof[node] >= 0)
            g.segment<3>(3 * m_dof[node]) += v;
    }
    /// Adds block (r, c) where it lies in the lower triangle (r ≥ c) and both nodes are free.
    void block(int r, int c, const Mat3& m) {
        if (r < c || c < 0)
            return;
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i)
                if (r > c || i >= j)
                    m_triplets.emplace_back(3 * r + i, 3 * c + j, m(i, j));
    }

    const BodyModel& m_model;
    const std::vector<NodeWeight>& m_support;
    Vec3 m_target;
    double m_ks;
    std::vector<int> m_dof;           ///< Per node: its index among the free nodes, or −1.
    std::vector<std::size_t> m_free;  ///< Per free node: the body's node.
    std::vector<Eigen::Triplet<double>> m_triplets;
};

}  // namespace

StaticResponse settleOurs(const InteractionScenario& s, const OurBody& body, std::vector<Vec3>* start) {
    const BodyModel& model = body.model();
    const Vec3 restPoint = body.gripRest();
    DragEquilibrium problem(model, body.gripSupport(), restPoint + s.dragOffset, s.dragStiffness);
    std::vector<Vec3> nodes = start && start->size() == model.nodeCount() ? *start : model.restPositions;

    Eigen::VectorXd x, gradient, trialGradient, trial;
    std::vector<Vec3> trialNodes = nodes;
    problem.gather(nodes, x);
    double e = problem.energy(nodes, gradient);
    Eigen::SparseMatrix<double> hessian;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
    bool analysed = false;

    StaticResponse result;
    double previous = (problem.dragPoint(nodes) - restPoint).norm();
    int quiet = 0;
    while (result.steps < kMaxIterations && quiet < 2) {
        ++result.steps;
        problem.hessian(nodes, hessian);
        if (!analysed) {
            solver.analyzePattern(hessian);
            analysed = true;
        }
        solver.factorize(hessian);
        Eigen::VectorXd direction = solver.info() == Eigen::Success ? Eigen::VectorXd(-solver.solve(gradient))
                                                                     : Eigen::VectorXd(-gradient);
        double slope = gradient.dot(direction);
        if (!(slope < 0.0)) {  // not a descent direction (a failed factorisation): fall back to the gradient
            direction = -gradient;
            slope = -gradient.squaredNorm();
        }
        // Backtracking (Armijo): halve the step until E falls by a fraction of what the slope promises.
        double step = 1.0, trialEnergy = e;
        bool decreased = false;
        for (int halving = 0; halving < 30 && !decreased; ++halving, step *= 0.5) {
            trial = x + step * direction;
            problem.scatter(trial, trialNodes);
            trialEnergy = problem.energy(trialNodes, trialGradient);
            decreased = trialEnergy <= e + 1e-4 * step * slope;
        }
        if (!decreased)
            break;  // E cannot fall any further in double precision: this is the equilibrium
        x.swap(trial);
        gradient.swap(trialGradient);
        nodes.swap(trialNodes);
        e = trialEnergy;
        result.displacement = (problem.dragPoint(nodes) - restPoint).norm();
        quiet = std::abs(result.displacement - previous) <= kTolerance * result.displacement ? quiet + 1 : 0;
        previous = result.displacement;
    }
    result.displacement = (problem.dragPoint(nodes) - restPoint).norm();
    result.converged = std::isfinite(result.displacement) && (quiet >= 2 || result.steps < kMaxIterations);
    if (start)
        *start = nodes;
    return result;
}

}  // namespace softtouch::bench
