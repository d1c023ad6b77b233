#include "core/simulator.h"

#include <cassert>

#include <cmath>
#include <sstream>

namespace softtouch {

Status SimulationSettings::validate() const {
    if (!(std::isfinite(dt) && dt > 0.0 && dt <= 0.1))
        return Status::error("time step dt must be in (0, 0.1] s, got " + std::to_string(dt));
    if (xpbdSubsteps < 1 || xpbdSubsteps > 10000)
        return Status::error("XPBD substeps must be in [1, 10000], got " + std::to_string(xpbdSubsteps));
    if (!(std::isfinite(stabilitySafety) && stabilitySafety > 0.0 && stabilitySafety <= 1.0))
        return Status::error("stability safety must be in (0, 1], got " + std::to_string(stabilitySafety));
    if (maxSubsteps < 1)
        return Status::error("max substeps must be at least 1");
    if (!(std::isfinite(sleepSpeed) && sleepSpeed >= 0.0))
        return Status::error("sleep speed must be finite and >= 0");
    return Status::success();
}

Simulator::Simulator(std::shared_ptr<const BodyModel> model, const SimulationSettings& settings)
    : m_model(std::move(model)), m_settings(settings), m_integrator(makeIntegrator(settings.integrator)) {
    m_state = restState(*m_model);
    m_lastGood = m_state;
}

void Simulator::restoreState(const BodyState& state) {
    m_state = state;
    m_lastGood = state;
    m_sleeping = false;
    m_quietSteps = 0;
}

void Simulator::restoreState(const BodyState& state, long long stepCount) {
    assert(stepCount >= 0);
    restoreState(state);
    m_stepCount = stepCount;
}

double Simulator::stableStep(const ExternalForces& external) const {
    const BodyModel& m = *m_model;
    double lambda = m.maxStiffnessOverMass;
    double dampingRate = m.maxNodeDampingRate;  // largest d/m-like rate from node damping and drags
    // A drag adds the rank-one term Ks M^-1/2 ŵŵᵀ M^-1/2, eigenvalue Ks Σ ŵ²/m (Weyl's bound).
    for (const DragSpring& drag : external.drags) {
        double sum = 0.0;
        forEachDragShare(m, drag, [&](std::uint32_t node, double share) { sum += share * share * m.inverseMass[node]; });
        lambda += drag.stiffness * sum;
        dampingRate = std::max(dampingRate, drag.damping * sum);
    }
    if (lambda <= 0.0 && dampingRate <= 0.0)
        return m_settings.dt;
    const double omega = std::sqrt(std::max(lambda, 1e-300));
    // Damping ratio of the stiffest mode: spring damping scales like K (c/k · ω/2), the rest like M.
    const double zeta = 0.5 * m.maxDampingRatio * omega + 0.5 * dampingRate / omega;
    const double bound = 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
    return m_settings.stabilitySafety * bound;
}

int Simulator::substepsFor(const ExternalForces& external) const {
    if (m_settings.integrator == IntegratorKind::Xpbd)
        return m_settings.xpbdSubsteps;
    if (!m_integrator->isExplicit())
        return 1;
    const double needed = std::ceil(m_settings.dt / stableStep(external) - 1e-9);
    if (!(needed < double(m_settings.maxSubsteps) + 1.0))
        return m_settings.maxSubsteps + 1;  // refused by step()
    return std::max(1, int(needed));
}

bool Simulator::forcesChanged(const ExternalForces& e) const {
    const ExternalForces& s = m_sleepForces;
    if (e.gravity != s.gravity || e.drags.size() != s.drags.size() || e.planes.size() != s.planes.size())
        return true;
    for (std::size_t i = 0; i < e.drags.size(); ++i) {
        const DragSpring& a = e.drags[i];
        const DragSpring& b = s.drags[i];
        if (a.target != b.target || a.targetVelocity != b.targetVelocity || a.stiffness != b.stiffness ||
            a.damping != b.damping || a.support.size() != b.support.size())
            return true;
        for (std::size_t k = 0; k < a.support.size(); ++k) {
            if (a.support[k].node != b.support[k].node || a.support[k].weight != b.support[k].weight)
                return true;
        }
    }
    for (std::size_t i = 0; i < e.planes.size(); ++i) {
        const CollisionPlane& a = e.planes[i];
        const CollisionPlane& b = s.planes[i];
        if (a.point != b.point || a.normal != b.normal || a.restitution != b.restitution || a.friction != b.friction)
            return true;
    }
    return false;
}

StepReport Simulator::step(const ExternalForces& external) {
    StepReport report;
    if (m_sleeping) {
        if (!forcesChanged(external)) {
            ++m_stepCount;
            report.sleeping = true;
            return report;
        }
        m_sleeping = false;
        m_quietSteps = 0;
    }
    const int substeps = substepsFor(external);
    if (substeps > m_settings.maxSubsteps) {
        std::ostringstream msg;
        msg << "time step " << m_settings.dt << " s needs more than " << m_settings.maxSubsteps << " substeps with "
            << integratorName(m_settings.integrator) << " (stable step " << stableStep(external)
            << " s): lower dt, soften the stiffest spring, raise the lightest mass, or use implicit-euler";
        report.problem = msg.str();
        ++m_stepCount;
        return report;
    }
    const double h = m_settings.dt / substeps;
    const bool contacts = !external.planes.empty();
    for (int s = 0; s < substeps; ++s) {
        if (contacts)
            m_substepStart = m_state.position;
        m_integrator->step(*m_model, external, m_state, h);
        if (contacts)
            resolvePlaneContacts(*m_model, external.planes, m_substepStart, h, external.gravity, m_state);
        updateVoidNodes(*m_model, m_state);
    }
    report.substeps = substeps;
    ++m_stepCount;

    if (!m_state.isFinite()) {
        m_state = m_lastGood;
        report.rolledBack = true;
        const std::string input = external.firstNonFinite();
        report.problem = !input.empty()
                             ? "non-finite input (" + input + "): the step was rolled back to the last good state"
                             : std::string("the state became non-finite with ") +
                                   std::string(integratorName(m_settings.integrator)) +
                                   ": the step was rolled back; lower dt or use implicit-euler";
        return report;
    }
    m_lastGood = m_state;

    if (m_settings.sleep) {
        double maxSpeedSquared = 0.0;  // squared: no square root per node
        for (const Vec3& v : m_state.velocity)
            maxSpeedSquared = std::max(maxSpeedSquared, v.squaredNorm());
        m_quietSteps = maxSpeedSquared < m_settings.sleepSpeed * m_settings.sleepSpeed ? m_quietSteps + 1 : 0;
        if (m_quietSteps >= m_settings.sleepSteps) {
            m_sleeping = true;
            m_sleepForces = external;
            for (Vec3& v : m_state.velocity)
                v.setZero();
            m_lastGood = m_state;
        }
    }
    return report;
}

}  // namespace softtouch
