#include "core/simulator.h"

#include <algorithm>
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
    if (energyCheckSteps < 0 || energyCheckSteps > 1000000)
        return Status::error("energy check interval must be in [0, 1e6] steps, got " + std::to_string(energyCheckSteps));
    if (!(std::isfinite(energyTolerance) && energyTolerance > 0.0 && energyTolerance <= 1.0))
        return Status::error("energy tolerance must be in (0, 1], got " + std::to_string(energyTolerance));
    if (!(std::isfinite(sleepSpeed) && sleepSpeed >= 0.0))
        return Status::error("sleep speed must be finite and >= 0");
    return Status::success();
}

Simulator::Simulator(std::shared_ptr<const BodyModel> model, const SimulationSettings& settings)
    : m_model(std::move(model)), m_settings(settings), m_integrator(makeIntegrator(settings.integrator)) {
    m_state = restState(*m_model);
    resetEnergyAccount({});
}

void Simulator::restoreState(const BodyState& state) {
    m_state = state;
    m_sleeping = false;
    m_quietSteps = 0;
    m_guardFactor = 1;
    m_peakScale = 0.0;
    resetEnergyAccount({});
}

void Simulator::restoreState(const BodyState& state, long long stepCount) {
    assert(stepCount >= 0);
    restoreState(state);
    m_stepCount = stepCount;
    m_lastGoodStep = stepCount;
}

double Simulator::accountedEnergy(const ExternalForces& external, double* elasticAndKinetic) {
    const double moving = kineticEnergy(*m_model, m_state) + springEnergy(*m_model, m_state);
    if (elasticAndKinetic)
        *elasticAndKinetic = moving;
    double energy = external.gravity.isZero() ? moving : moving + gravityEnergy(*m_model, m_state, external.gravity);
    // Symplectic Euler (and this Verlet, the same scheme with the velocity as a backward difference)
    // conserves not E but the modified energy H̃ = E + (h/2) vᵀ f(x), f the conservative forces
    // (exactly for a linear body: v² + ω²x² − hω²xv is invariant under v' = v − hω²x, x' = x + hv').
    // Near the stability bound E itself swings by tens of percent in the stiffest modes while H̃ holds,
    // so H̃ is what the account compares.
    const std::size_t n = m_model->nodeCount();
    m_zeroVelocity.assign(n, Vec3::Zero());
    m_conservativeForce.resize(n);
    ExternalForces gravityOnly;
    gravityOnly.gravity = external.gravity;
    ForceTerms terms;
    terms.nodeDamping = false;
    accumulateForces(*m_model, gravityOnly, m_state.position, m_zeroVelocity, m_conservativeForce, m_scratch, terms);
    const double h = m_settings.dt / std::max(1, substepsFor(external));
    double correction = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (m_model->inverseMass[i] > 0.0)
            correction += m_state.velocity[i].dot(m_conservativeForce[i]);
    }
    return energy + 0.5 * h * correction;
}

void Simulator::beginDragWork(const ExternalForces& external) {
    m_dragStart.resize(external.drags.size());
    for (std::size_t d = 0; d < external.drags.size(); ++d)
        m_dragStart[d] = dragPull(external.drags[d]);
}

Simulator::DragPull Simulator::dragPull(const DragSpring& drag) const {
    Vec3 point, velocity;
    dragPointState(drag, m_state.position, m_state.velocity, point, velocity);
    DragPull pull;
    pull.force = drag.stiffness * (drag.target - point) + drag.damping * (drag.targetVelocity - velocity);
    // The pull reaches the free nodes by their renormalised shares (forEachDragShare), so it works
    // along their motion, not the point's (which pinned support nodes hold back).
    pull.sharedPosition.setZero();
    forEachDragShare(*m_model, drag, [&](std::uint32_t node, double share) { pull.sharedPosition += share * m_state.position[node]; });
    return pull;
}

double Simulator::dragWork(const ExternalForces& external) const {
    double work = 0.0;
    for (std::size_t d = 0; d < external.drags.size(); ++d) {
        const DragPull end = dragPull(external.drags[d]);
        work += 0.5 * (m_dragStart[d].force + end.force).dot(end.sharedPosition - m_dragStart[d].sharedPosition);
    }
    return work;
}

void Simulator::checkpoint() {
    m_lastGood = m_state;
    m_lastGoodStep = m_stepCount;
    m_stepsSinceCheckpoint = 0;
}

bool Simulator::accountsEnergy() const {
    // Implicit Euler only ever loses energy and XPBD's unconverged constraints hold less than their
    // springs' energy by design; the account is for the explicit schemes, which can gain it.
    return m_settings.energyCheckSteps > 0 && m_integrator->isExplicit();
}

void Simulator::resetEnergyAccount(const ExternalForces& external) {
    checkpoint();
    if (!accountsEnergy())
        return;
    m_accountGravity = external.gravity;
    m_accountEnergy = accountedEnergy(external, &m_accountScale);
    m_peakScale = std::max(m_peakScale, m_accountScale);
    m_accountWork = 0.0;
}

bool Simulator::checkEnergy(const ExternalForces& external, StepReport& report) {
    if (external.gravity != m_accountGravity) {  // gravity changed: its potential is measured anew
        resetEnergyAccount(external);
        return true;
    }
    double scale = 0.0;
    const double energy = accountedEnergy(external, &scale);
    // Near rest the energy is round-off: growth is measured against a millionth of the largest energy
    // the body has held (and a picojoule), not against nothing.
    m_peakScale = std::max(m_peakScale, scale);
    scale = std::max({scale, m_accountScale, std::abs(m_accountWork), 1e-6 * m_peakScale, 1e-12});
    const double growth = (energy - m_accountEnergy - m_accountWork) / scale;
    if (!(growth > m_settings.energyTolerance)) {
        checkpoint();
        return true;
    }
    const long long lost = m_stepCount - m_lastGoodStep;
    m_state = m_lastGood;  // passed its own check: never a state that was already bad
    report.rolledBack = true;
    report.energyGrowth = growth;
    std::ostringstream msg;
    msg.precision(3);
    msg << "energy grew " << 100.0 * growth << "% in " << lost << " steps with nothing doing that work ("
        << integratorName(m_settings.integrator) << ", " << substepsFor(external) << " substeps a step): rolled back "
        << lost << " steps";
    if (m_guardFactor < kMaxGuardFactor) {
        m_guardFactor *= 2;  // the account below measures H̃ anew at the new substep
        msg << " and now takes " << substepsFor(external) << " substeps a step";
    } else {
        msg << "; substeps are already " << kMaxGuardFactor << "x: lower dt, add damping or use implicit-euler";
    }
    report.problem = msg.str();
    resetEnergyAccount(external);
    return false;
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
    const double needed = std::ceil(m_settings.dt / stableStep(external) - 1e-9) * m_guardFactor;
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
    const bool accountEnergy = accountsEnergy();
    if (accountEnergy && !external.drags.empty())
        beginDragWork(external);
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
        resetEnergyAccount(external);
        report.rolledBack = true;
        const std::string input = external.firstNonFinite();
        report.problem = !input.empty()
                             ? "non-finite input (" + input + "): the step was rolled back to the last good state"
                             : std::string("the state became non-finite with ") +
                                   std::string(integratorName(m_settings.integrator)) +
                                   ": the step was rolled back; lower dt or use implicit-euler";
        return report;
    }
    if (accountEnergy) {
        if (!external.drags.empty())
            m_accountWork += dragWork(external);
        if (++m_stepsSinceCheckpoint >= m_settings.energyCheckSteps && !checkEnergy(external, report))
            return report;
    } else {
        checkpoint();
    }

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
            resetEnergyAccount(external);
        }
    }
    return report;
}

}  // namespace softtouch
