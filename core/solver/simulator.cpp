#include "core/body/element_body.h"
#include "core/body/strain_limits.h"
#include "core/geometry/mesh.h"
#include "core/solver/simulator.h"

#include "core/base/ranges.h"

#include <algorithm>
#include <cassert>

#include <cmath>
#include <numeric>
#include <sstream>

namespace softtouch {

Status SimulationSettings::validate() const {
    for (const auto& [range, value] : {std::pair{ranges::kDt, dt}, std::pair{ranges::kXpbdSubsteps, double(xpbdSubsteps)},
                                       std::pair{ranges::kEnergyCheckSteps, double(energyCheckSteps)}})
        if (std::string problem = range.problem(value); !problem.empty())
            return Status::error(std::move(problem));
    if (!(std::isfinite(stabilitySafety) && stabilitySafety > 0.0 && stabilitySafety <= 2.0))
        return Status::error("stability safety must be in (0, 2], got " + std::to_string(stabilitySafety));
    if (maxSubsteps < 1)
        return Status::error("max substeps must be at least 1");
    if (!(std::isfinite(energyTolerance) && energyTolerance > 0.0 && energyTolerance <= 1.0))
        return Status::error("energy tolerance must be in (0, 1], got " + std::to_string(energyTolerance));
    if (!(std::isfinite(sleepSpeed) && sleepSpeed >= 0.0))
        return Status::error("sleep speed must be finite and >= 0");
    return Status::success();
}

namespace {

/// Power iterations of the current-state stiffness estimate: from a fresh vector (construction,
/// restore, rollback) and, warm-started, at each energy check.
constexpr int kFreshIterations = 24;
constexpr int kCheckIterations = 1;
/// Substeps after which the energy is checked even before energyCheckSteps steps have passed.
constexpr int kCheckSubsteps = 256;
/// XPBD's E is not conserved even where the scheme is stable: its Gauss-Seidel pass trades energy between
/// springs, and a stable undamped run's E rises up to about 1.4x from a trough to the next peak (a pinned bar
/// at 24 steps/s). Its account starts from the energy the body could swing to, this many times its elastic
/// energy, so only growth past the swing counts; an instability compounds past it within a few checks.
constexpr double kXpbdSwing = 2.0;

}  // namespace

Simulator::Simulator(std::shared_ptr<const BodyModel> model, const SimulationSettings& settings)
    : m_model(std::move(model)), m_settings(settings), m_integrator(makeIntegrator(settings.integrator)) {
    m_state = restState(*m_model);
    if (m_integrator->isExplicit()) {  // here rather than in a step (they allocate)
        (void)m_model->maxStiffnessOverMass();   // the substep bound
        (void)m_model->elementViscosityModes();  // what a solid element's substeps take implicitly
    }
    m_integrator->setMeasuresWork(accountsEnergy());
    if (accountsEnergy()) {
        // The energy of the stiffest motion at a millionth of the body's size: growth of a few percent of
        // that is round-off, invisible in any frame (1e-7 m on a 0.3 m fish), and is not energy from nowhere.
        const double mass = std::accumulate(m_model->mass.begin(), m_model->mass.end(), 0.0);
        const double motion = 1e-6 * boundsOf(m_model->restPositions).diagonal();
        m_noiseEnergy = std::max(0.5 * mass * m_model->maxStiffnessOverMass() * motion * motion, 1e-12);
        if (m_integrator->isExplicit())
            m_tracker.reset(*m_model);
        trackStiffness(kFreshIterations);
    }
    resetEnergyAccount({});
}

void Simulator::restoreState(const BodyState& state) { restoreState(state, m_stepCount); }

void Simulator::restoreState(const BodyState& state, long long stepCount) {
    // A new run: what the guard learnt about the old one goes (rewind() keeps it).
    m_guardFactor = 1;
    m_stopped.clear();
    m_peakScale = 0.0;
    rewind(state, stepCount);
}

void Simulator::trackStiffness(int iterations) {
    // The bound the explicit schemes substep below follows the state; XPBD's substeps do not depend on it.
    if (!accountsEnergy() || !m_integrator->isExplicit() || !m_state.isFinite())
        return;
    const double lambda = m_tracker.estimate(*m_model, m_state.position, iterations);
    if (std::isfinite(lambda)) {
        m_currentStiffness = lambda;
    } else {  // a vector spoilt by an extreme state: start it afresh next time
        m_tracker.reset(*m_model);
        m_currentStiffness = 0.0;
    }
}

Simulator::EnergyParts Simulator::energyParts(const ExternalForces& external, double h) {
    EnergyParts parts;
    parts.elastic = kineticEnergy(*m_model, m_state) + springEnergy(*m_model, m_state);
    const bool gravity = !external.gravity.isZero();
    const double energy = gravity ? parts.elastic + gravityEnergy(*m_model, m_state, external.gravity) : parts.elastic;
    if (!m_integrator->isExplicit()) {
        // XPBD: no modified energy to conserve. Where its springs are soft for the substep it is symplectic
        // Euler, whose E swings a little about H̃; where they are stiff its one projection only takes energy
        // out. E itself is what it must not gain.
        parts.modified = energy;
        return parts;
    }
    // Symplectic Euler (and this Verlet, the same scheme with the velocity as a backward difference)
    // conserves not E but the modified energy H̃ = E + (h/2) vᵀ f(x), f the conservative forces
    // (exactly for a linear body: v² + ω²x² − hω²xv is invariant under v' = v − hω²x, x' = x + hv').
    // Near the stability bound E itself swings by tens of percent in the stiffest modes while H̃ holds,
    // so H̃ is what the account compares.
    const std::size_t n = m_model->nodeCount();
    m_zeroVelocity.assign(n, Vec3::Zero());
    m_conservativeForce.resize(n);
    ForceTerms terms;
    terms.nodeDamping = false;
    accumulateForces(*m_model, ExternalForces{}, m_state.position, m_zeroVelocity, m_conservativeForce, m_scratch, terms);
    double springPower = 0.0, gravityPower = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (m_model->inverseMass[i] > 0.0) {
            springPower += m_state.velocity[i].dot(m_conservativeForce[i]);
            if (gravity)
                gravityPower += m_model->mass[i] * external.gravity.dot(m_state.velocity[i]);
        }
    }
    parts.springPower = springPower;
    parts.conservativePower = springPower + gravityPower;
    parts.modified = energy + 0.5 * h * parts.conservativePower + stepMassEnergy(h);
    return parts;
}

double Simulator::stepMassEnergy(double h) const {
    // A solid element's substep solves with M + h K̃_s (the viscosity it takes implicitly): the scheme is
    // symplectic Euler on that mass, whose kinetic energy has the extra (h/2) vᵀK̃_s v.
    if (!m_model->element || !m_model->element->viscous)
        return 0.0;
    return 0.5 * h * elementStepViscosityProduct(*m_model->element, m_model->elementViscosityModes(), h, m_state.velocity);
}

double Simulator::accountedEnergy(const ExternalForces& external) {
    return energyParts(external, m_settings.dt / std::max(1, substepsFor(external))).modified;
}

double Simulator::nodeEnergy(std::size_t i, const Vec3& gravity, double h) const {
    const BodyModel& m = *m_model;
    const Vec3& x = m_state.position[i];
    const Vec3& v = m_state.velocity[i];
    double e = 0.5 * m.mass[i] * v.squaredNorm() - m.mass[i] * gravity.dot(x) + 0.5 * h * m.mass[i] * gravity.dot(v);
    // A spring's share of H̃: ½ k (L − L₀)² and (h/2)(v_a·f_a + v_b·f_b) = −(h/2) k (L − L₀) r̂·(v_b − v_a).
    const SpringTable& t = m.springTable;
    auto spring = [&](std::uint32_t k) {
        const Vec3 r = m_state.position[t.b[k]] - m_state.position[t.a[k]];
        const double length = r.norm();
        const double stretch = length - t.restLength[k];
        double se = 0.5 * t.stiffness[k] * stretch * stretch;
        if (length > 0.0)
            se -= 0.5 * h * t.stiffness[k] * stretch * r.dot(m_state.velocity[t.b[k]] - m_state.velocity[t.a[k]]) / length;
        return se;
    };
    for (std::uint32_t e2 = t.startOffset[i]; e2 < t.startOffset[i + 1]; ++e2)
        e += spring(t.startSpring[e2]);
    for (std::uint32_t e2 = t.endOffset[i]; e2 < t.endOffset[i + 1]; ++e2)
        e += spring(t.endSpring[e2]);
    return e;
}

void Simulator::resolveContactsAccounted(const ExternalForces& external, double h) {
    // The same response as resolvePlaneContacts, node by node; a contact changes only its node's
    // position and velocity, so H̃ changes by that node's share (applied in order: exact).
    if (m_model->element) {  // its kinetic energy couples the nodes: the whole body's H̃ before and after
        const double before = energyParts(external, h).modified;
        resolvePlaneContacts(*m_model, external.planes, m_substepStart, h, external.gravity, m_state);
        m_account.contacts += energyParts(external, h).modified - before;
        return;
    }
    const double restingSpeed = restingContactSpeed(external.gravity, h);
    for (const CollisionPlane& plane : external.planes) {
        for (std::size_t i = 0; i < m_model->nodeCount(); ++i) {
            if (m_model->inverseMass[i] == 0.0 || (m_state.position[i] - plane.point).dot(plane.normal) > 0.0)
                continue;
            const double before = nodeEnergy(i, external.gravity, h);
            (void)resolvePlaneContact(plane, m_substepStart[i], restingSpeed, m_state.position[i], m_state.velocity[i]);
            m_account.contacts += nodeEnergy(i, external.gravity, h) - before;
        }
    }
}

void Simulator::checkpoint() {
    m_lastGood = m_state;
    m_lastGoodStep = m_stepCount;
    m_stepsSinceCheckpoint = 0;
    m_substepsSinceCheckpoint = 0;
}

bool Simulator::accountsEnergy() const {
    // Implicit Euler only ever loses energy. The explicit schemes gain it past their bound, and so does
    // XPBD's one Gauss-Seidel pass per substep on stiff springs between nodes of very different mass (a
    // light lattice on heavy anchors): projected one after another, each spring's correction undoes part of
    // the one before, and the velocities the corrections leave grow.
    return m_settings.energyCheckSteps > 0 && (m_integrator->isExplicit() || m_settings.integrator == IntegratorKind::Xpbd);
}

void Simulator::resetEnergyAccount(const ExternalForces& external) {
    checkpoint();
    if (!accountsEnergy())
        return;
    m_accountGravity = external.gravity;
    m_accountStep = m_settings.dt / std::max(1, substepsFor(external));
    const EnergyParts parts = energyParts(external, m_accountStep);
    m_account = EnergyAccount{};
    m_dissipatedAtCheck = 0.0;
    startAccountAt(parts);
    m_peakScale = std::max(m_peakScale, m_accountScale);
}

void Simulator::startAccountAt(const EnergyParts& parts) {
    const double swing = m_integrator->isExplicit() ? 1.0 : kXpbdSwing;
    m_account.start = parts.modified + (swing - 1.0) * parts.elastic;
    m_accountScale = parts.elastic;  // the account restarts once half of it is gone
}

void Simulator::rebaseAccount(const ExternalForces& external, double h) {
    // H̃ = E + (h/2) vᵀf (and a solid element's (h/2) vᵀK̃_s v): at a new h the same state has a different H̃,
    // so the start moves by the difference (the account keeps what it has seen so far).
    moveAccountStep(energyParts(external, m_accountStep), h);
}

void Simulator::moveAccountStep(const EnergyParts& parts, double h) {
    m_account.start += 0.5 * (h - m_accountStep) * parts.conservativePower + stepMassEnergy(h) - stepMassEnergy(m_accountStep);
    m_accountStep = h;
}

bool Simulator::checkEnergy(const ExternalForces& external, StepReport& report, bool regular) {
    if (external.gravity != m_accountGravity) {  // gravity changed: its potential is measured anew
        resetEnergyAccount(external);
        return true;
    }
    const EnergyParts parts = energyParts(external, m_accountStep);
    // Near rest the energy is round-off: growth is measured against a millionth of the largest energy
    // the body has held, or the body's noise energy, not against nothing.
    m_peakScale = std::max(m_peakScale, parts.elastic);
    const double floor = std::max(1e-6 * m_peakScale, m_noiseEnergy);
    // Against the energy the account started with (or what the drags or contacts moved, if more): not
    // the current kinetic + spring energy, which swings with the step in the stiffest modes.
    const double scale = std::max({m_accountScale, std::abs(m_account.work), std::abs(m_account.contacts),
                                   std::abs(m_account.limits), std::abs(m_account.volume), floor});
    const double growth = (parts.modified - m_account.expected()) / scale;
    // |(h/2) vᵀf_springs| ≤ (hω/2)(kinetic + spring) for any state when hω < 2 (Cauchy-Schwarz in the
    // energy norm), and a mode past its bound grows with H̃ = 0, where the two are equal: a share near
    // 1 is a step at or past its bound, whatever H̃ says.
    const double edgeShare = parts.elastic > floor ? std::abs(0.5 * m_accountStep * parts.springPower) / parts.elastic : 0.0;
    const double edgeLimit = 0.5 * (1.0 + std::min(m_settings.stabilitySafety, 0.9));
    const bool grew = growth > m_settings.energyTolerance || !std::isfinite(growth);
    // Damping only takes energy out of a motion the step resolves; over a check's span its booked work is
    // negative only where a mode past its bound flips sign every substep, and the damping force, a substep
    // late, pumps it. The account would take that pumping for energy that left and see no growth.
    const double pumped = m_dissipatedAtCheck - m_account.dissipated;
    const bool pumping = pumped > m_settings.energyTolerance * scale;
    const bool unstable = edgeShare > edgeLimit || pumping;
    if (!grew && !unstable) {
        if (!regular) {
            // A settle: the state is accepted (a rollback never goes before it) but the regular checks'
            // cadence, the stiffness tracking and the account go on as if it had not run, so where a caller
            // settles never changes the motion (a take replays bit for bit whatever its frame times).
            m_lastGood = m_state;
            m_lastGoodStep = m_stepCount;
            return true;
        }
        m_dissipatedAtCheck = m_account.dissipated;
        checkpoint();
        // The bound follows the state: a stiffer state takes more substeps from the next step on.
        trackStiffness(kCheckIterations);
        const double h = m_settings.dt / std::max(1, substepsFor(external));
        if (parts.elastic < 0.5 * m_accountScale) {
            // Damping (or work out) has taken half the energy: restart the account from here, so the
            // tolerance follows the energy down and later growth is measured against what is left.
            m_account = EnergyAccount{};
            m_dissipatedAtCheck = 0.0;
            startAccountAt(parts);
            moveAccountStep(parts, h);
        } else if (h != m_accountStep) {
            moveAccountStep(parts, h);
        }
        return true;
    }
    const long long lost = m_stepCount - m_lastGoodStep;
    report.energyGrowth = growth;
    std::ostringstream msg;
    msg.precision(3);
    if (grew)
        msg << "energy grew " << 100.0 * growth << "% in " << lost << (lost == 1 ? " step" : " steps")
            << " with nothing doing that work (";
    else
        msg << "unstable motion in " << lost << (lost == 1 ? " step" : " steps") << " (the fastest motion outran the step: "
            << (pumping ? "damping a substep late fed it " + std::to_string(int(std::lround(100.0 * pumped / scale))) +
                              "% of the body's energy; "
                        : std::to_string(int(std::lround(100.0 * edgeShare))) + "% of its energy in the step's (h/2)v·f term; ");
    msg << integratorName(m_settings.integrator) << ", " << substepsFor(external) << " substeps a step)";
    rollBack(external, msg.str(), report);
    return false;
}

void Simulator::rollBack(const ExternalForces& external, const std::string& why, StepReport& report) {
    const long long lost = m_stepCount - m_lastGoodStep;
    const double from = double(m_lastGoodStep) * m_settings.dt;
    m_state = m_lastGood;  // passed its own check: never a state that was already bad
    m_stepCount = m_lastGoodStep;  // and its time: the span is stepped again, so no frame jumps back
    report.rolledBack = true;
    report.rewoundSteps = int(std::min<long long>(lost, 1 << 30));
    std::ostringstream msg;
    msg.precision(4);
    msg << why << ": rolled back to t=" << from << " s";
    if (m_guardFactor < kMaxGuardFactor) {
        m_guardFactor *= 2;
        msg << " and steps the " << lost << (lost == 1 ? " step" : " steps") << " since again at "
            << substepsFor(external) << " substeps a step";
    } else {
        msg << "; substeps are already " << kMaxGuardFactor << "x, so the body stops there: lower dt, add damping "
            << "or use implicit-euler";
        m_stopped = msg.str();
        report.refused = true;
    }
    report.problem = msg.str();
    trackStiffness(kFreshIterations);
    resetEnergyAccount(external);
}

bool Simulator::settle(const ExternalForces& external, StepReport& report) {
    if (!accountsEnergy() || m_sleeping || !m_stopped.empty() || m_lastGoodStep == m_stepCount)
        return true;
    return checkEnergy(external, report, false);
}

void Simulator::rewind(const BodyState& state, long long stepCount) {
    assert(state.position.size() == m_state.position.size() && stepCount >= 0);
    m_state = state;
    m_stepCount = stepCount;
    m_sleeping = false;
    m_quietSteps = 0;
    trackStiffness(kFreshIterations);
    resetEnergyAccount({});
}

bool Simulator::isExplicit() const { return m_integrator->isExplicit(); }

double Simulator::stableStep(const ExternalForces& external) const {
    const BodyModel& m = *m_model;
    double lambda = std::max(m.maxStiffnessOverMass(), m_currentStiffness);
    double dampingRate = m.maxNodeDampingRate;  // largest d/m-like rate from node damping and drags
    // A drag adds the rank-one term Ks M^-1/2 ŵŵᵀ M^-1/2, eigenvalue Ks ŵᵀ M⁻¹ ŵ (Weyl's bound): Σ ŵ²/m with one
    // mass per node. A solid element's consistent mass has light wiggles that a point pull excites, so there it is
    // |L⁻¹ ŵ|², many times Σ ŵ²/m_i for a goal spring on one node.
    for (const DragSpring& drag : external.drags) {
        double sum = 0.0;
        if (m.element)
            sum = elementPullInverseMass(*m.element, [&](auto&& visit) { forEachDragShare(m, drag, visit); }, m_pullWork);
        else
            forEachDragShare(m, drag, [&](std::uint32_t node, double share) { sum += share * share * m.inverseMass[node]; });
        lambda += drag.stiffness * sum;
        // Each drag's damping alone moves the nodes it holds; on a consistent mass they share its light wiggles,
        // so the rates add up (Weyl) rather than the largest one counting.
        dampingRate = m.element ? dampingRate + drag.damping * sum : std::max(dampingRate, drag.damping * sum);
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
        return m_settings.xpbdSubsteps * m_guardFactor;
    if (!m_integrator->isExplicit())
        return 1;
    const double needed = std::ceil(m_settings.dt / stableStep(external) - 1e-9) * m_guardFactor;
    if (!(needed < double(m_settings.maxSubsteps) + 1.0))
        return m_settings.maxSubsteps + 1;  // refused by step()
    return std::max(1, int(needed));
}

bool Simulator::forcesChanged(const ExternalForces& e) const {
    const ExternalForces& s = m_sleepForces;
    if (e.gravity != s.gravity || e.drags.size() != s.drags.size() || e.planes.size() != s.planes.size() ||
        e.colliders != s.colliders || e.nodeForces != s.nodeForces)
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

void Simulator::applyCorrection(const BodyState& corrected, const ExternalForces& external) {
    assert(corrected.position.size() == m_state.position.size());
    const bool account = accountsEnergy() && m_accountStep > 0.0;
    const double before = account ? energyParts(external, m_accountStep).modified : 0.0;
    m_state = corrected;
    updateVoidNodes(*m_model, m_state);
    if (account)
        m_account.contacts += energyParts(external, m_accountStep).modified - before;
    m_sleeping = false;
    m_quietSteps = 0;
}

StepReport Simulator::step(const ExternalForces& external) {
    StepReport report;
    if (m_sleeping) {
        if (!forcesChanged(external)) {
            ++m_stepCount;
            m_lastGoodStep = m_stepCount;  // the state the body fell asleep in, which passed its check
            report.sleeping = true;
            return report;
        }
        m_sleeping = false;
        m_quietSteps = 0;
    }
    if (!m_stopped.empty()) {
        report.problem = m_stopped;
        report.refused = true;
        ++m_stepCount;
        return report;
    }
    const int substeps = substepsFor(external);
    if (substeps > m_settings.maxSubsteps) {
        std::ostringstream msg;
        msg << "time step " << m_settings.dt << " s needs more than " << m_settings.maxSubsteps << " substeps with "
            << integratorName(m_settings.integrator) << " (stable step " << stableStep(external)
            << " s): lower dt, soften the stiffest spring, raise the lightest mass, or use implicit-euler";
        report.problem = msg.str();
        report.refused = true;
        ++m_stepCount;
        return report;
    }
    const double h = m_settings.dt / substeps;
    const bool contacts = !external.planes.empty();
    const bool limits = m_model->strainLimits.any();
    const bool keepVolume = m_model->volume.active();
    const bool accountEnergy = accountsEnergy();
    if (accountEnergy && h != m_accountStep)
        rebaseAccount(external, h);  // the drags changed the bound since the last step
    for (int s = 0; s < substeps; ++s) {
        if (contacts)
            m_substepStart = m_state.position;
        m_integrator->step(*m_model, external, m_state, h);
        if (accountEnergy) {
            const StepWork work = m_integrator->lastWork();
            m_account.work += work.external;
            m_account.dissipated += work.dissipated;
        }
        // Runs a constraint pass; for the energy guard, books the change of H̃ it made into `account`.
        const auto booked = [&](double& account, auto&& pass) {
            const double before = accountEnergy ? energyParts(external, h).modified : 0.0;
            pass();
            if (accountEnergy)
                account += energyParts(external, h).modified - before;
        };
        if (keepVolume) {
            // Planes first, so the volume is restored around them; nodes resting on a plane move only along
            // it. A correction can carry a node near a plane through it, which the next contact pass takes
            // back with some volume, so with planes the two alternate a few times (the final contact pass
            // below ends it).
            booked(m_account.volume, [&] {
                for (int round = 0; round < (contacts ? 3 : 1); ++round) {
                    if (contacts)
                        resolvePlaneContacts(*m_model, external.planes, m_substepStart, h, external.gravity, m_state);
                    (void)enforceVolume(*m_model, m_state, h, m_volumeScratch, external.planes);
                }
            });
        }
        if (limits && strainLimitsViolated(*m_model, m_model->strainLimits, m_state)) {
            booked(m_account.limits, [&] {
                const StrainLimitPass pass = enforceStrainLimits(*m_model, m_model->strainLimits, m_state);
                report.strainCorrections += pass.corrections;
                report.worstStrainExcess = std::max(report.worstStrainExcess, pass.worstExcess);
            });
        }
        if (contacts) {
            if (accountEnergy)
                resolveContactsAccounted(external, h);
            else
                resolvePlaneContacts(*m_model, external.planes, m_substepStart, h, external.gravity, m_state);
        }
        if (collidersMayTouch(*m_model, external.colliders, m_state)) {
            booked(m_account.contacts, [&] {
                const ColliderPass pass = resolveColliders(*m_model, external.colliders, m_state,
                                                           restingContactSpeed(external.gravity, h), m_colliderImpulses);
                report.colliderContacts += pass.contacts;
                report.deepestContact = std::max(report.deepestContact, pass.deepest);
            });
        } else {
            m_colliderImpulses.clear();  // out of reach: the next contact starts without a stale warm start
        }
        updateVoidNodes(*m_model, m_state);
    }
    report.substeps = substeps;
    ++m_stepCount;

    if (!m_state.isFinite()) {
        const std::string input = external.firstNonFinite();
        if (input.empty() && accountEnergy) {
            // The inputs were sane, so the explicit step itself blew up: the span is taken again at finer
            // substeps, as after energy growth.
            rollBack(external, std::string("the state became non-finite with ") +
                                   std::string(integratorName(m_settings.integrator)), report);
            return report;
        }
        // Stepping again would give the same result: the body holds its last good state (from the last
        // check, which is never before the last frame shown or written) and the clock goes on.
        m_state = m_lastGood;
        resetEnergyAccount(external);
        report.rolledBack = true;
        report.problem = !input.empty()
                             ? "non-finite input (" + input + "): the step was rolled back to the last good state"
                             : std::string("the state became non-finite with ") +
                                   std::string(integratorName(m_settings.integrator)) +
                                   ": the step was rolled back; lower dt or use implicit-euler";
        return report;
    }
    if (accountEnergy) {
        // Every energyCheckSteps steps, or every step once steps take many substeps (a check costs
        // about two substeps; thousands of substeps between checks would let an instability explode).
        m_substepsSinceCheckpoint += substeps;
        if ((++m_stepsSinceCheckpoint >= m_settings.energyCheckSteps || m_substepsSinceCheckpoint >= kCheckSubsteps) &&
            !checkEnergy(external, report, true))
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
