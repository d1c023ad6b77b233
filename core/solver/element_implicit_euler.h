#pragma once
/// Implicit Euler's step of a solid element body (core/body/element_body.h), which the integrator hands it: the
/// consistent mass couples every node, so the system is not the springs' block pattern.

#include "core/body/forces.h"
#include "core/solver/integrator.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <vector>

namespace softtouch {

/// Linearised backward Euler (as the springs' implicit Euler):
///   (M + h D + h C_t + h² K_t + drags) Δv = h (f + h K_t v) − h² Σ_drags k w (wᵀ v),   v += Δv,  x += h v,
/// with M and D the element's consistent mass and node damping, K_t and C_t its corotated stiffness and
/// viscosity at the step's state (addElementTangent()). Solved by conjugate gradients, matrix-free,
/// preconditioned by the factorised matrix of the body at rest for this h (dense: the element's nodes couple
/// widely), so a step's answer depends on its state and inputs alone.
class ElementImplicitEuler {
public:
    void step(const BodyModel& model, const ExternalForces& external, BodyState& state, double h);
    LinearSolveStats lastSolve() const { return m_stats; }

private:
    void factorRest(const BodyModel& model, double h);
    void apply(const BodyModel& model, const ExternalForces& external, double h, const Eigen::VectorXd& p, Eigen::VectorXd& y);

    const BodyModel* m_model = nullptr;
    double m_restStep = -1.0;
    Eigen::LLT<Eigen::MatrixXd> m_rest;
    LinearSolveStats m_stats;
    std::vector<Mat3> m_rotations;
    std::vector<Vec3> m_force, m_nodes, m_product;
    SpringScratch m_scratch;
    Eigen::VectorXd m_rhs, m_x, m_r, m_z, m_p, m_Ap;
};

}  // namespace softtouch
