// Extended position-based dynamics (Macklin, Müller, Chentanez 2016), one iteration per substep
// ("Small Steps in Physics Simulation", Macklin et al. 2019).
#include "core/solver/integrator.h"

namespace softtouch {
namespace {

/// Each spring is a distance constraint C = |x_a − x_b| − L with compliance α = 1/k. Per substep
/// h (λ starts at 0 since there is one iteration):
///   α̃ = α / h²,  γ = α̃ β h = c / (k h)          (β = c, the spring damping)
///   Δλ = (−C − γ ∇C·(x − x_prev)) / ((1 + γ) (w_a + w_b) + α̃)
/// Gravity and air damping enter as forces in the prediction. A drag spring is a compliant
/// constraint too, C = p − target with p = Σ w_n x_n (three components, compliance 1/Ks, damping Kd),
/// so even a very stiff drag cannot make the substep unstable — as a force it would (h·ω > 2).
/// Spring projections move each pair along ∇C with weights 1/m, so they conserve linear momentum.
///
/// For the Simulator's energy guard it measures the work that crosses the body in a substep: each node
/// force f (held over the substep) does f·Δx, and each drag, whose projection applies the force Δλ/h² at
/// its point, does Δλ/h²·Δp. What damping takes out is not booked: the guard only looks for growth.
class Xpbd final : public Integrator {
public:
    IntegratorKind kind() const override { return IntegratorKind::Xpbd; }
    bool isExplicit() const override { return false; }
    void setMeasuresWork(bool measure) override { m_measure = measure; }
    StepWork lastWork() const override { return m_work; }
    void step(const BodyModel& model, const ExternalForces& external, BodyState& state, double h) override {
        m_work = {};
        const std::size_t n = model.nodeCount();
        m_force.resize(n);
        m_previous.resize(n);
        ForceTerms terms;
        terms.springs = false;
        ExternalForces withoutDrags;  // drags are constraints below
        withoutDrags.gravity = external.gravity;
        accumulateForces(model, withoutDrags, state.position, state.velocity, m_force, m_scratch, terms);
        if (external.nodeForces.size() == n)
            for (std::size_t i = 0; i < n; ++i)
                m_force[i] += external.nodeForces[i];
        for (std::size_t i = 0; i < n; ++i) {
            m_previous[i] = state.position[i];
            if (model.inverseMass[i] == 0.0)
                continue;
            state.velocity[i] += h * model.inverseMass[i] * m_force[i];
            state.position[i] += h * state.velocity[i];
        }
        for (const Spring& s : model.springs) {
            if (s.stiffness <= 0.0)
                continue;
            const double wa = model.inverseMass[s.a];
            const double wb = model.inverseMass[s.b];
            const double wsum = wa + wb;
            if (wsum == 0.0)
                continue;
            Vec3& xa = state.position[s.a];
            Vec3& xb = state.position[s.b];
            const Vec3 r = xa - xb;
            const double length = r.norm();
            if (length <= 0.0)
                continue;
            const Vec3 gradient = r * (1.0 / length);
            const double C = length - s.restLength;
            const double compliance = 1.0 / (s.stiffness * h * h);
            const double gamma = s.damping / (s.stiffness * h);
            const double rate = gradient.dot((xa - m_previous[s.a]) - (xb - m_previous[s.b]));
            const double dlambda = (-C - gamma * rate) / ((1.0 + gamma) * wsum + compliance);
            xa += wa * dlambda * gradient;
            xb -= wb * dlambda * gradient;
        }
        m_dragForces.clear();
        for (const DragSpring& drag : external.drags)
            m_dragForces.push_back(projectDrag(model, drag, state, h));
        for (std::size_t i = 0; i < n; ++i) {
            if (model.inverseMass[i] == 0.0)
                continue;
            state.velocity[i] = (state.position[i] - m_previous[i]) / h;
        }
        if (m_measure)
            measureWork(model, external, state);
    }

private:
    /// The substep's work on the body: node forces over each node's move, drags over their point's move.
    void measureWork(const BodyModel& model, const ExternalForces& external, const BodyState& state) {
        if (external.nodeForces.size() == model.nodeCount())
            for (std::size_t i = 0; i < model.nodeCount(); ++i)
                if (model.inverseMass[i] != 0.0)
                    m_work.external += external.nodeForces[i].dot(state.position[i] - m_previous[i]);
        for (std::size_t d = 0; d < external.drags.size(); ++d) {
            Vec3 moved = Vec3::Zero();
            for (const NodeWeight& w : external.drags[d].support)
                moved += w.weight * (state.position[w.node] - m_previous[w.node]);
            m_work.external += m_dragForces[d].dot(moved);
        }
    }

    /// One compliant projection of C = p − target, p = Σ w_n x_n over the drag's support (gradient w_n I;
    /// pinned and void nodes have no inverse mass, so they do not move). Returns the force it applied at
    /// the point over the substep, Δλ/h², N.
    Vec3 projectDrag(const BodyModel& model, const DragSpring& drag, BodyState& state, double h) const {
        if (drag.stiffness <= 0.0)
            return Vec3::Zero();
        const std::vector<NodeWeight>& weights = drag.support;
        double generalisedInverseMass = 0.0;
        Vec3 point = Vec3::Zero(), moved = Vec3::Zero();
        for (const NodeWeight& w : weights) {
            generalisedInverseMass += w.weight * w.weight * model.inverseMass[w.node];
            point += w.weight * state.position[w.node];
            moved += w.weight * (state.position[w.node] - m_previous[w.node]);
        }
        if (generalisedInverseMass == 0.0)
            return Vec3::Zero();
        const double compliance = 1.0 / (drag.stiffness * h * h);
        const double gamma = drag.damping / (drag.stiffness * h);
        const Vec3 C = point - drag.target;
        const Vec3 rate = moved - h * drag.targetVelocity;
        const Vec3 dlambda = (-C - gamma * rate) / ((1.0 + gamma) * generalisedInverseMass + compliance);
        for (const NodeWeight& w : weights)
            state.position[w.node] += (w.weight * model.inverseMass[w.node]) * dlambda;
        return dlambda / (h * h);
    }

    bool m_measure = false;
    StepWork m_work;
    std::vector<Vec3> m_dragForces;  ///< Per drag, the force its projection applied this substep.
    std::vector<Vec3> m_force;
    SpringScratch m_scratch;
    std::vector<Vec3> m_previous;
};

}  // namespace

std::unique_ptr<Integrator> makeXpbd() { return std::make_unique<Xpbd>(); }

}  // namespace softtouch
