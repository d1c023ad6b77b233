// Symplectic Euler and central-difference (Verlet) integration.
#include "core/integrator.h"

namespace softtouch {
namespace {

/// Semi-implicit (symplectic) Euler: velocities first, then positions with the new velocities.
/// Conserves momentum exactly and energy on average; stable for h < 2/omega_max.
class SymplecticEuler final : public Integrator {
public:
    IntegratorKind kind() const override { return IntegratorKind::SymplecticEuler; }
    bool isExplicit() const override { return true; }
    void step(const BodyModel& model, const ExternalForces& external, BodyState& state, double h) override {
        m_force.resize(model.nodeCount());
        accumulateForces(model, external, state.position, state.velocity, m_force, m_scratch);
        for (std::size_t i = 0; i < model.nodeCount(); ++i) {
            if (model.inverseMass[i] == 0.0)
                continue;
            state.velocity[i] += h * model.inverseMass[i] * m_force[i];
            state.position[i] += h * state.velocity[i];
        }
    }

private:
    std::vector<Vec3> m_force;
    SpringScratch m_scratch;
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
        // Node damping is handled implicitly below, so it stays out of the explicit forces.
        ForceTerms terms;
        terms.nodeDamping = false;
        accumulateForces(model, external, state.position, state.velocity, m_force, m_scratch, terms);
        for (std::size_t i = 0; i < model.nodeCount(); ++i) {
            if (model.inverseMass[i] == 0.0)
                continue;
            const Vec3 x = state.position[i];
            const Vec3 previous = x - h * state.velocity[i];
            const double c = 0.5 * h * model.nodeDamping[i] * model.inverseMass[i];
            const Vec3 next = (2.0 * x - previous + h * h * model.inverseMass[i] * m_force[i] + c * previous) / (1.0 + c);
            state.velocity[i] = (next - x) / h;
            state.position[i] = next;
        }
    }

private:
    std::vector<Vec3> m_force;
    SpringScratch m_scratch;
};

}  // namespace

std::unique_ptr<Integrator> makeSymplecticEuler() { return std::make_unique<SymplecticEuler>(); }
std::unique_ptr<Integrator> makeVerlet() { return std::make_unique<Verlet>(); }

}  // namespace softtouch
