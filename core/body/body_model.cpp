#include "core/body/body_model.h"

#include "core/base/ranges.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace softtouch {

using ranges::finiteIn;

namespace {

/// The largest eigenvalue of the symmetric tridiagonal matrix T with diagonal `alpha` and off-diagonal
/// `beta`, known to lie in [low, high], by bisection on Sturm counts (the signs of the pivots of T − x I
/// count the eigenvalues below x) to 1e-13 of itself: O(n) a halving, where a full eigenvalue solve of
/// T is O(n²) and the Lanczos loop below asks after every step. (Newton's step on the determinant from
/// above was tried: the top Ritz values cluster as the lattice's stiffest modes do, and it crawled.)
double largestTridiagonalEigenvalue(const std::vector<double>& alpha, const std::vector<double>& beta, double low, double high) {
    const std::size_t n = alpha.size();
    const auto below = [&](double x) {  // eigenvalues of T smaller than x
        std::size_t count = 0;
        double pivot = 1.0;
        for (std::size_t i = 0; i < n; ++i) {
            pivot = (alpha[i] - x) - (i > 0 ? beta[i - 1] * beta[i - 1] / pivot : 0.0);
            if (pivot == 0.0)
                pivot = -1e-300;  // x is an eigenvalue of the leading block: count it below, go on
            count += pivot < 0.0 ? 1 : 0;
        }
        return count;
    };
    // Widen by round-off until the bracket holds: `low` may be the last estimate, a hair above the truth.
    const double tolerance = 1e-13 * std::max(std::abs(low), std::abs(high)) + 1e-300;
    while (below(low) == n)
        low -= 10 * tolerance;
    while (below(high) < n)
        high += 10 * tolerance;
    while (high - low > tolerance) {
        const double mid = 0.5 * (low + high);
        if (mid <= low || mid >= high)
            break;
        (below(mid) == n ? high : low) = mid;
    }
    return 0.5 * (low + high);
}

/// Largest eigenvalue of M^-1 K (K the rest stiffness matrix of the springs, free nodes only), by Lanczos
/// on the symmetric form A = M^-1/2 K M^-1/2. The largest Ritz value rises to the largest eigenvalue from
/// below; it is looked at every fourth step and taken once it moved by less than 1e-9 of itself since.
/// Power iteration, used before, needed all of its 200 rounds on every body of a swimming fish (the
/// stiffest modes of a lattice lie close together, and power iteration converges as their ratio) and
/// still stopped short; Lanczos settles in a few dozen products with A.
template <typename Apply>
double lanczosLargest(Eigen::VectorXd q, Apply&& apply);

double largestStiffnessOverMass(const BodyModel& m) {
    const std::size_t n = m.nodeCount();
    if (m.element) {
        // A = L⁻¹ K L⁻ᵀ over the free nodes, M = L Lᵀ the element's consistent mass (each component alike).
        const ElementBody& e = *m.element;
        const Eigen::MatrixXd k = elementRestStiffness(e);
        const Eigen::Index free = Eigen::Index(e.freeNodes.size());
        const auto lower = e.massFactor.matrixL();
        Eigen::MatrixXd block(free, 3);
        const auto apply = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
            for (Eigen::Index s = 0; s < free; ++s)
                block.row(s) = x.segment<3>(3 * s).transpose();
            lower.transpose().solveInPlace(block);  // L⁻ᵀ x
            Eigen::VectorXd z(3 * free);
            for (Eigen::Index s = 0; s < free; ++s)
                z.segment<3>(3 * s) = block.row(s).transpose();
            z = k * z;
            for (Eigen::Index s = 0; s < free; ++s)
                block.row(s) = z.segment<3>(3 * s).transpose();
            lower.solveInPlace(block);  // L⁻¹ K L⁻ᵀ x
            y.resize(3 * free);
            for (Eigen::Index s = 0; s < free; ++s)
                y.segment<3>(3 * s) = block.row(s).transpose();
        };
        Eigen::VectorXd q(3 * free);
        for (Eigen::Index s = 0; s < free; ++s)
            q.segment<3>(3 * s) = Vec3(1.0 + 0.37 * double(s % 7), -0.5 + 0.11 * double(s % 5), 0.3 + 0.05 * double(s % 11));
        return lanczosLargest(std::move(q), apply);
    }
    // Each spring's direction and mass scales, once (the same values every product would compute).
    struct Term {
        std::uint32_t a, b;
        Vec3 d;
        double sa, sb, k;
    };
    std::vector<Term> terms;
    terms.reserve(m.springs.size());
    for (const Spring& s : m.springs)
        terms.push_back({s.a, s.b, (m.restPositions[s.b] - m.restPositions[s.a]).normalized(), std::sqrt(m.inverseMass[s.a]),
                         std::sqrt(m.inverseMass[s.b]), s.stiffness});
    const auto apply = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
        y.setZero();
        for (const Term& t : terms) {
            const double rel = t.d.dot(t.sa * x.segment<3>(3 * t.a) - t.sb * x.segment<3>(3 * t.b));
            y.segment<3>(3 * t.a) += t.k * t.sa * rel * t.d;
            y.segment<3>(3 * t.b) -= t.k * t.sb * rel * t.d;
        }
    };
    // A deterministic, non-symmetric start so that no mode is missed by symmetry; zero on pinned nodes.
    Eigen::VectorXd q(3 * n);
    for (std::size_t i = 0; i < n; ++i)
        q.segment<3>(3 * i) = m.inverseMass[i] > 0.0
                                  ? Vec3(1.0 + 0.37 * double(i % 7), -0.5 + 0.11 * double(i % 5), 0.3 + 0.05 * double(i % 11))
                                  : Vec3::Zero();
    return lanczosLargest(std::move(q), apply);
}

/// The largest eigenvalue of the symmetric operator `apply` (y = A x), by Lanczos from `q`.
template <typename Apply>
double lanczosLargest(Eigen::VectorXd q, Apply&& apply) {
    const std::size_t n = std::size_t(q.size()) / 3;
    if (q.norm() == 0.0)
        return 0.0;
    // The three-term recurrence only: two vectors, whatever the lattice's size (a basis kept for
    // reorthogonalisation would take 3n x its length). Lost orthogonality adds copies of converged Ritz
    // values, never one above the spectrum, so the largest still rises to λ_max from below.
    const int most = int(std::min<std::size_t>(3 * n, 120));
    std::vector<double> alpha, beta;
    Eigen::VectorXd previous = Eigen::VectorXd::Zero(3 * n), current = q / q.norm(), w(3 * n);
    double largest = 0.0;  // the largest Ritz value at the last look
    bool looked = false;
    for (int j = 0; j < most; ++j) {
        apply(current, w);
        alpha.push_back(current.dot(w));
        w -= alpha.back() * current;
        if (!beta.empty())
            w -= beta.back() * previous;
        const double b = w.norm();
        // The largest Ritz value, every fourth step and at the end (a look costs a bisection; a step, a
        // product with A): it never falls (interlacing), so the last look bounds it from below, and
        // Gershgorin's discs bound it from above.
        double upper = 0.0;
        for (std::size_t i = 0; i < alpha.size(); ++i)
            upper = std::max(upper, alpha[i] + (i > 0 ? std::abs(beta[i - 1]) : 0.0) + (i < beta.size() ? std::abs(beta[i]) : 0.0));
        const bool end = j + 1 == most || b <= 1e-12 * std::max(upper, 1e-300);
        if (j % 4 == 3 || end) {
            const double next = largestTridiagonalEigenvalue(alpha, beta, largest, upper);
            const bool settled = looked && next - largest <= 1e-9 * std::abs(next);
            largest = next;
            looked = true;
            if (settled || end)
                break;
        }
        beta.push_back(b);
        previous.swap(current);
        current = w / b;
    }
    return largest;
}

}  // namespace

double BodyModel::maxStiffnessOverMass() const {
    std::call_once(m_stepBoundOnce, [this] { m_maxStiffnessOverMass = largestStiffnessOverMass(*this); });
    return m_maxStiffnessOverMass;
}

const ElementViscosityModes& BodyModel::elementViscosityModes() const {
    std::call_once(m_viscosityModesOnce, [this] {
        if (element)
            m_elementViscosityModes = softtouch::elementViscosityModes(*element);
    });
    return m_elementViscosityModes;
}

Result<std::shared_ptr<const BodyModel>> buildBodyModel(const BodyDescription& d) {
    const std::size_t n = d.restPositions.size();
    if (n == 0)
        return Status::error("the body has no nodes");
    if (d.mass.size() != n)
        return Status::error("mass has " + std::to_string(d.mass.size()) + " values for " + std::to_string(n) + " nodes");
    if (!d.anchor.empty() && d.anchor.size() != n)
        return Status::error("anchor has " + std::to_string(d.anchor.size()) + " values for " + std::to_string(n) + " nodes");
    if (!d.isVoid.empty() && d.isVoid.size() != n)
        return Status::error("void has " + std::to_string(d.isVoid.size()) + " values for " + std::to_string(n) + " nodes");
    if (std::string p = kHeavyAnchorRatio.problem(d.heavyAnchorRatio); !p.empty())
        return Status::error(p);
    if (!d.nodeDamping.empty() && d.nodeDamping.size() != n)
        return Status::error("node damping has " + std::to_string(d.nodeDamping.size()) + " values for " +
                             std::to_string(n) + " nodes");

    if (Status s = validateStrainLimits(d.strainLimits); !s)
        return s;
    if (d.element) {
        if (!d.springs.empty() || !d.nodeDamping.empty())
            return Status::error("a body that runs the solid element has no springs or node damping of its own");
        if (d.element->nodeCount() != n)
            return Status::error("the solid element has " + std::to_string(d.element->nodeCount()) + " nodes for " +
                                 std::to_string(n));
        for (std::size_t i = 0; i < n; ++i) {
            const bool held = !d.anchor.empty() && d.anchor[i] != AnchorMode::Free;
            if (held != (d.element->slot[i] < 0) || (!d.anchor.empty() && d.anchor[i] == AnchorMode::Heavy))
                return Status::error("node " + std::to_string(i) + " is held differently by the body and its solid element");
        }
    }

    auto model = std::make_shared<BodyModel>();
    model->restPositions = d.restPositions;
    model->strainLimits = d.strainLimits;
    model->volume = d.volume;
    model->contactPoints = d.contactPoints;
    model->mass.assign(n, 0.0);
    model->inverseMass.assign(n, 0.0);
    model->simulated.assign(n, 1);
    model->pinned.assign(n, 0);
    model->nodeDamping.assign(n, 0.0);
    bool anySimulated = false;
    for (std::size_t i = 0; i < n; ++i) {
        const auto node = [i] { return "node " + std::to_string(i); };  // for a message only: a build names no node
        if (!isFinite(d.restPositions[i]))
            return Status::error(node() + " has a non-finite rest position");
        const bool isVoid = !d.isVoid.empty() && d.isVoid[i] != 0;
        if (isVoid) {
            model->simulated[i] = 0;
            continue;
        }
        if (!finiteIn(d.mass[i], 1e-12, 1e12))
            return Status::error(node() + " has mass " + std::to_string(d.mass[i]) +
                                 " kg; a mass must be finite and in [1e-12, 1e12] kg");
        const AnchorMode mode = d.anchor.empty() ? AnchorMode::Free : d.anchor[i];
        model->mass[i] = mode == AnchorMode::Heavy ? d.mass[i] * d.heavyAnchorRatio : d.mass[i];
        model->pinned[i] = mode == AnchorMode::Pinned;
        model->inverseMass[i] = mode == AnchorMode::Pinned ? 0.0 : 1.0 / model->mass[i];
        const double damping = d.nodeDamping.empty() ? 0.0 : d.nodeDamping[i];
        if (!finiteIn(damping, 0.0, 1e6))
            return Status::error(node() + " has node damping " + std::to_string(damping) +
                                 " N·s/m; it must be finite and in [0, 1e6] N·s/m");
        model->nodeDamping[i] = damping;
        model->anyNodeDamping = model->anyNodeDamping || damping > 0.0;
        model->maxNodeDampingRate = std::max(model->maxNodeDampingRate, damping * model->inverseMass[i]);
        anySimulated = true;
    }
    if (!anySimulated)
        return Status::error("every node is void: nothing is left to simulate");
    for (std::size_t k = 0; k < d.springs.size(); ++k) {
        const Spring& s = d.springs[k];
        const auto spring = [k] { return "spring " + std::to_string(k); };
        if (s.a >= n || s.b >= n || s.a == s.b)
            return Status::error(spring() + " joins invalid nodes " + std::to_string(s.a) + " and " + std::to_string(s.b));
        if (!finiteIn(s.stiffness, 0.0, 1e9))
            return Status::error(spring() + " has stiffness " + std::to_string(s.stiffness) +
                                 " N/m; it must be finite and in [0, 1e9] N/m");
        if (!finiteIn(s.damping, 0.0, 1e6))
            return Status::error(spring() + " has damping " + std::to_string(s.damping) +
                                 " N·s/m; it must be finite and in [0, 1e6] N·s/m");
        if (!finiteIn(s.restLength, 1e-12, 1e12))
            return Status::error(spring() + " has a zero or invalid rest length; its nodes coincide");
        if (!model->simulated[s.a] || !model->simulated[s.b])
            continue;  // a void node takes its springs with it
        model->springs.push_back(s);
        model->anySpringDamping = model->anySpringDamping || s.damping > 0.0;
        if (s.stiffness > 0.0)
            model->maxDampingRatio = std::max(model->maxDampingRatio, s.damping / s.stiffness);
    }
    if (d.element) {
        model->element = d.element;
        model->maxNodeDampingRate = d.element->maxNodeDampingRate;
        // Its viscosity does not bound the explicit step: the step takes it implicitly (ElementBody::viscosityBound).
        model->maxDampingRatio = 0.0;
    }
    model->voidFollowers = d.voidFollowers;
    model->springTable = SpringTable::build(model->springs, model->inverseMass);
    for (double w : model->inverseMass)
        model->maxInverseMass = std::max(model->maxInverseMass, w);
    return std::shared_ptr<const BodyModel>(std::move(model));
}

}  // namespace softtouch
