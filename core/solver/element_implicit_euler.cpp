#include "core/solver/element_implicit_euler.h"

#include <cmath>
#include <limits>

namespace softtouch {

namespace {

constexpr int kMaxIterations = 100;

}  // namespace

void ElementImplicitEuler::factorRest(const BodyModel& model, double h) {
    const ElementBody& e = *model.element;
    m_rest.compute(h * h * elementRestStiffness(e) + h * elementRestViscosity(e) +
                   elementFreeMatrix(e, e.mass + h * e.nodeDamping));
    m_model = &model;
    m_restStep = h;
}

/// y = A p over the free nodes, p and y laid out 3 per free node.
void ElementImplicitEuler::apply(const BodyModel& model, const ExternalForces& external, double h, const Eigen::VectorXd& p,
                                 Eigen::VectorXd& y) {
    const ElementBody& e = *model.element;
    const std::size_t free = e.freeNodes.size();
    std::fill(m_nodes.begin(), m_nodes.end(), Vec3::Zero());
    for (std::size_t s = 0; s < free; ++s)
        m_nodes[e.freeNodes[s]] = p.segment<3>(Eigen::Index(3 * s));
    std::fill(m_product.begin(), m_product.end(), Vec3::Zero());
    addElementTangent(e, m_rotations, h * h, h, m_nodes, m_product);
    for (const DragSpring& drag : external.drags) {
        Vec3 shared = Vec3::Zero();
        forEachDragShare(model, drag, [&](std::uint32_t node, double share) { shared += share * m_nodes[node]; });
        const double k = h * h * drag.stiffness + h * drag.damping;
        forEachDragShare(model, drag, [&](std::uint32_t node, double share) { m_product[node] += k * share * shared; });
    }
    addElementMatrixTimes(e, e.mass, 1.0, m_nodes, m_product);
    if (e.nodeDamped)
        addElementMatrixTimes(e, e.nodeDamping, h, m_nodes, m_product);
    y.resize(Eigen::Index(3 * free));
    for (std::size_t s = 0; s < free; ++s)
        y.segment<3>(Eigen::Index(3 * s)) = m_product[e.freeNodes[s]];
}

void ElementImplicitEuler::step(const BodyModel& model, const ExternalForces& external, BodyState& state, double h) {
    const ElementBody& e = *model.element;
    if (&model != m_model || h != m_restStep)
        factorRest(model, h);
    const std::size_t n = model.nodeCount(), free = e.freeNodes.size();
    m_force.resize(n);
    m_nodes.resize(n);
    m_product.resize(n);
    accumulateForces(model, external, state.position, state.velocity, m_force, m_scratch);
    elementRotations(e, state.position, m_rotations);

    // rhs = h f + h² K_t v (the element's), less the drags' h² k w (wᵀ v).
    std::fill(m_product.begin(), m_product.end(), Vec3::Zero());
    addElementTangent(e, m_rotations, 1.0, 0.0, state.velocity, m_product);
    for (const DragSpring& drag : external.drags) {
        Vec3 shared = Vec3::Zero();
        forEachDragShare(model, drag, [&](std::uint32_t node, double share) { shared += share * state.velocity[node]; });
        forEachDragShare(model, drag, [&](std::uint32_t node, double share) { m_product[node] += drag.stiffness * share * shared; });
    }
    m_rhs.resize(Eigen::Index(3 * free));
    for (std::size_t s = 0; s < free; ++s) {
        const std::uint32_t i = e.freeNodes[s];
        m_rhs.segment<3>(Eigen::Index(3 * s)) = h * m_force[i] - h * h * m_product[i];
    }

    // Conjugate gradients to a relative residual of 1e-10, preconditioned by the rest matrix.
    m_stats = {};
    m_x.setZero(m_rhs.size());
    const double tolerance = 1e-10 * m_rhs.norm();
    bool converged = tolerance == 0.0;
    if (!converged) {
        m_r = m_rhs;
        m_z = m_rest.solve(m_r);
        m_p = m_z;
        double rz = m_r.dot(m_z);
        for (int iteration = 0; iteration < kMaxIterations && !converged; ++iteration) {
            m_stats.iterations = iteration + 1;
            apply(model, external, h, m_p, m_Ap);
            const double alpha = rz / m_p.dot(m_Ap);
            m_x += alpha * m_p;
            m_r -= alpha * m_Ap;
            converged = m_r.norm() <= tolerance;
            if (converged)
                break;
            m_z = m_rest.solve(m_r);
            const double next = m_r.dot(m_z);
            m_p = m_z + (next / rz) * m_p;
            rz = next;
        }
    }
    if (!converged || !m_x.allFinite())
        m_x.setConstant(std::numeric_limits<double>::quiet_NaN());  // the simulator rolls back and reports
    for (std::size_t s = 0; s < free; ++s) {
        const std::uint32_t i = e.freeNodes[s];
        state.velocity[i] += m_x.segment<3>(Eigen::Index(3 * s));
        state.position[i] += h * state.velocity[i];
    }
}

}  // namespace softtouch
