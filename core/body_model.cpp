#include "core/body_model.h"

#include "core/ranges.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace softtouch {

using ranges::finiteIn;

namespace {

/// Largest eigenvalue of M^-1 K (K the rest stiffness matrix of the springs, free nodes only) by
/// power iteration on the symmetric form M^-1/2 K M^-1/2. K's Rayleigh quotient is bounded by the
/// Gershgorin estimate, which seeds a fixed iteration count; 1% accuracy is plenty for a step bound
/// that then gets a safety factor.
double largestStiffnessOverMass(const BodyModel& m) {
    const std::size_t n = m.nodeCount();
    std::vector<Vec3> x(n), y(n);
    for (std::size_t i = 0; i < n; ++i) {
        // Deterministic, non-symmetric start vector so no mode is missed by symmetry.
        x[i] = m.inverseMass[i] > 0.0 ? Vec3(1.0 + 0.37 * double(i % 7), -0.5 + 0.11 * double(i % 5), 0.3 + 0.05 * double(i % 11))
                                       : Vec3::Zero();
    }
    // Each spring's direction and mass scales, once (the same values every iteration would compute).
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
    double lambda = 0.0;
    for (int iteration = 0; iteration < 200; ++iteration) {
        double norm = 0.0;
        for (const Vec3& v : x)
            norm += v.squaredNorm();
        norm = std::sqrt(norm);
        if (norm == 0.0)
            return 0.0;
        for (Vec3& v : x)
            v /= norm;
        for (Vec3& v : y)
            v.setZero();
        for (const Term& t : terms) {
            const double rel = t.d.dot(t.sa * x[t.a] - t.sb * x[t.b]);
            y[t.a] += t.k * t.sa * rel * t.d;
            y[t.b] -= t.k * t.sb * rel * t.d;
        }
        double next = 0.0;
        for (std::size_t i = 0; i < n; ++i)
            next += x[i].dot(y[i]);
        std::swap(x, y);
        if (iteration > 20 && std::abs(next - lambda) <= 1e-6 * next)
            return next;
        lambda = next;
    }
    return lambda;
}

}  // namespace

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
    if (!finiteIn(d.heavyAnchorRatio, 1.0, 1e9))
        return Status::error("heavy anchor ratio must be in [1, 1e9], got " + std::to_string(d.heavyAnchorRatio));
    if (!d.nodeDamping.empty() && d.nodeDamping.size() != n)
        return Status::error("node damping has " + std::to_string(d.nodeDamping.size()) + " values for " +
                             std::to_string(n) + " nodes");

    if (Status s = validateStrainLimits(d.strainLimits); !s)
        return s;

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
    model->voidFollowers = d.voidFollowers;
    model->springTable = SpringTable::build(model->springs, model->inverseMass);
    for (double w : model->inverseMass)
        model->maxInverseMass = std::max(model->maxInverseMass, w);
    model->maxStiffnessOverMass = largestStiffnessOverMass(*model);
    return std::shared_ptr<const BodyModel>(std::move(model));
}

}  // namespace softtouch
