// Symplectic Euler and central-difference (Verlet) integration.
#include "core/solver/integrator.h"

#include "core/body/element_body.h"

#include <Eigen/Core>

#include <array>
#include <memory>

namespace softtouch {
namespace {

/// Measures a substep's StepWork for the energy account: each drag's pull and the share-weighted
/// velocity of the free nodes it pulls, before and after the update (work h g·(v + v')/2), and the
/// springs' damping from the force pass's scratch. Node damping is scheme-specific: the caller adds it.
class WorkMeter {
public:
    bool on = false;   ///< Measure at all (Integrator::setMeasuresWork).
    StepWork work;     ///< The last substep's.

    /// Where accumulateForces() writes each drag's pull (empty when not measuring).
    std::span<Vec3> pulls(const ExternalForces& external) {
        if (!on)
            return {};
        m_pull.resize(external.drags.size());  // grows once: no allocation per step
        return m_pull;
    }
    /// Where accumulateForces() writes a solid element's damping forces (empty when not measuring or no element).
    std::span<Vec3> elementDamping(const BodyModel& model) {
        if (!on || !model.element)
            return {};
        m_elementDamping.resize(model.nodeCount());  // grows once
        return m_elementDamping;
    }
    /// After the force pass, before the update.
    void begin(const BodyModel& model, const ExternalForces& external, const BodyState& state) {
        work = {};
        if (!on)
            return;
        m_sharedVelocity.resize(external.drags.size());
        for (std::size_t d = 0; d < external.drags.size(); ++d)
            m_sharedVelocity[d] = sharedVelocity(model, external.drags[d], state);
        m_nodeForcePower = nodeForcePower(model, external, state);
        if (model.element)  // the element's damping forces (from the force pass), held over the substep
            m_elementDampingPower = power(model, m_elementDamping, state);
    }
    void end(const BodyModel& model, const ExternalForces& external, const BodyState& state,
             const SpringScratch& scratch, double h) {
        if (!on)
            return;
        for (std::size_t d = 0; d < external.drags.size(); ++d) {
            const Vec3 after = sharedVelocity(model, external.drags[d], state);
            work.external += 0.5 * h * m_pull[d].dot(m_sharedVelocity[d] + after);
        }
        // Node forces held over the substep work h F·(v + v')/2 on each free node, as a drag's pull does.
        work.external += 0.5 * h * (m_nodeForcePower + nodeForcePower(model, external, state));
        if (model.anySpringDamping)
            work.dissipated += springDampingLoss(model.springTable, scratch, state.velocity, h);
        if (model.element)
            work.dissipated -= 0.5 * h * (m_elementDampingPower + power(model, m_elementDamping, state));
    }

private:
    static Vec3 sharedVelocity(const BodyModel& model, const DragSpring& drag, const BodyState& state) {
        Vec3 v = Vec3::Zero();
        forEachDragShare(model, drag, [&](std::uint32_t node, double share) { v += share * state.velocity[node]; });
        return v;
    }
    static double nodeForcePower(const BodyModel& model, const ExternalForces& external, const BodyState& state) {
        if (external.nodeForces.size() != model.nodeCount())
            return 0.0;
        double power = 0.0;
        for (std::size_t i = 0; i < model.nodeCount(); ++i)
            if (model.inverseMass[i] > 0.0)
                power += external.nodeForces[i].dot(state.velocity[i]);
        return power;
    }
    static double power(const BodyModel& model, const std::vector<Vec3>& force, const BodyState& state) {
        double p = 0.0;
        for (std::size_t i = 0; i < model.nodeCount(); ++i)
            if (model.inverseMass[i] > 0.0)
                p += force[i].dot(state.velocity[i]);
        return p;
    }
    double m_nodeForcePower = 0.0;       ///< Σ F·v over the free nodes at the start of the substep, W.
    std::vector<Vec3> m_elementDamping;  ///< A solid element's damping forces at the start of the substep, N.
    double m_elementDampingPower = 0.0;  ///< Their Σ F·v then, W.
    std::vector<Vec3> m_pull;            ///< N per drag, held over the substep.
    std::vector<Vec3> m_sharedVelocity;  ///< m/s per drag, Σ share · v over the free support at the start.
};

/// Turns the forces on the free nodes into accelerations in place: f/m per node, or on a solid element the
/// product with (M + h K̃_s)⁻¹, its consistent mass and the share of its viscosity the substep takes implicitly
/// (elementStepViscosity()): whatever the viscosity, the substep is then stable at the undamped bound, which the
/// Simulator's step bound assumes. Keeps the inverses of the last few substep lengths (a drag or a stiffer state
/// changes the substeps and may change them back); a new length inverts once, in the step that first takes it.
class Accelerations {
public:
    void operator()(const BodyModel& model, std::span<Vec3> force, double h) {
        if (model.element) {
            applyElementFreeMatrix(*model.element, inverseFor(model, h), force, force, m_work);
            return;
        }
        for (std::size_t i = 0; i < model.nodeCount(); ++i)
            force[i] *= model.inverseMass[i];
    }

private:
    struct Inverse {
        std::shared_ptr<const ElementBody> body;  // held, so a new body at the same address is not taken for it
        double h = 0.0;                           // 0 without viscosity: the mass alone, whatever the substep
        Eigen::MatrixXd matrix;
    };
    const Eigen::MatrixXd& inverseFor(const BodyModel& model, double h) {
        const ElementBody& e = *model.element;
        const double key = e.viscous ? h : 0.0;
        for (Inverse& f : m_inverses)
            if (f.body == model.element && f.h == key)
                return f.matrix;
        Inverse& slot = m_inverses[m_next];
        m_next = (m_next + 1) % m_inverses.size();
        Eigen::MatrixXd mass = elementFreeBlock(e, e.mass);
        if (e.viscous)
            mass += h * elementStepViscosity(e, model.elementViscosityModes(), h);
        const Eigen::Index free = mass.rows();
        slot = {model.element, key, Eigen::LLT<Eigen::MatrixXd>(mass).solve(Eigen::MatrixXd::Identity(free, free))};
        return slot.matrix;
    }
    std::array<Inverse, 4> m_inverses;
    std::size_t m_next = 0;
    Eigen::MatrixXd m_work;
};

/// Semi-implicit (symplectic) Euler: velocities first, then positions with the new velocities.
/// Conserves momentum exactly and energy on average; stable for h < 2/omega_max.
class SymplecticEuler final : public Integrator {
public:
    IntegratorKind kind() const override { return IntegratorKind::SymplecticEuler; }
    bool isExplicit() const override { return true; }
    void step(const BodyModel& model, const ExternalForces& external, BodyState& state, double h) override {
        m_force.resize(model.nodeCount());
        accumulateForces(model, external, state.position, state.velocity, m_force, m_scratch, {}, m_meter.pulls(external),
                         m_meter.elementDamping(model));
        m_meter.begin(model, external, state);
        const bool nodeDamping = m_meter.on && model.anyNodeDamping;
        double nodeLoss = 0.0;
        m_accelerations(model, m_force, h);
        for (std::size_t i = 0; i < model.nodeCount(); ++i) {
            if (model.inverseMass[i] == 0.0)
                continue;
            const Vec3 before = state.velocity[i];
            state.velocity[i] += h * m_force[i];
            state.position[i] += h * state.velocity[i];
            if (nodeDamping)  // −d v held over the substep: works −h d v·(v + v')/2
                nodeLoss += 0.5 * h * model.nodeDamping[i] * before.dot(before + state.velocity[i]);
        }
        m_meter.end(model, external, state, m_scratch, h);
        m_meter.work.dissipated += nodeLoss;
    }
    void setMeasuresWork(bool measure) override { m_meter.on = measure; }
    StepWork lastWork() const override { return m_meter.work; }

private:
    std::vector<Vec3> m_force;
    SpringScratch m_scratch;
    WorkMeter m_meter;
    Accelerations m_accelerations;
};

/// Central differences, as in the paper: M (x+ − 2x + x−)/h² + D (x+ − x−)/2h + f_int(x) = F.
/// With the diagonal (node) damping D taken central in time, each node solves in closed form:
///   x+ = (2x − x− + h² a + (h d / 2m) x−) / (1 + h d / 2m),
/// where a holds every other force at time n (spring damping uses the backward velocity). The state
/// velocity is the backward difference (x − x−)/h, so x− = x − h v survives save/restore.
class Verlet final : public Integrator {
public:
    IntegratorKind kind() const override { return IntegratorKind::Verlet; }
    bool isExplicit() const override { return true; }
    void step(const BodyModel& model, const ExternalForces& external, BodyState& state, double h) override {
        m_force.resize(model.nodeCount());
        // Node damping is handled implicitly below, so it stays out of the explicit forces; a solid element's
        // couples the nodes as its mass does and is taken explicitly (with the backward velocity).
        ForceTerms terms;
        terms.nodeDamping = model.element != nullptr;
        accumulateForces(model, external, state.position, state.velocity, m_force, m_scratch, terms, m_meter.pulls(external),
                         m_meter.elementDamping(model));
        m_meter.begin(model, external, state);
        m_accelerations(model, m_force, h);
        const bool nodeDamping = m_meter.on && model.anyNodeDamping;
        double nodeLoss = 0.0;
        for (std::size_t i = 0; i < model.nodeCount(); ++i) {
            if (model.inverseMass[i] == 0.0)
                continue;
            const Vec3 x = state.position[i];
            const Vec3 before = state.velocity[i];
            const Vec3 previous = x - h * before;
            const double c = 0.5 * h * model.nodeDamping[i] * model.inverseMass[i];
            const Vec3 next = (2.0 * x - previous + h * h * m_force[i] + c * previous) / (1.0 + c);
            state.velocity[i] = (next - x) / h;
            state.position[i] = next;
            // Central node damping is v' = v + h/m (f − d v̄), v̄ = (v + v')/2: it works −h d |v̄|².
            if (nodeDamping)
                nodeLoss += 0.25 * h * model.nodeDamping[i] * (before + state.velocity[i]).squaredNorm();
        }
        m_meter.end(model, external, state, m_scratch, h);
        m_meter.work.dissipated += nodeLoss;
    }
    void setMeasuresWork(bool measure) override { m_meter.on = measure; }
    StepWork lastWork() const override { return m_meter.work; }

private:
    std::vector<Vec3> m_force;
    SpringScratch m_scratch;
    WorkMeter m_meter;
    Accelerations m_accelerations;
};

}  // namespace

std::unique_ptr<Integrator> makeSymplecticEuler() { return std::make_unique<SymplecticEuler>(); }
std::unique_ptr<Integrator> makeVerlet() { return std::make_unique<Verlet>(); }

}  // namespace softtouch
