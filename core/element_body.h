#pragma once
/// The solid element a lattice body can run instead of springs (LatticeMaterial::element,
/// docs/lattice.md "The solid element"): the Galerkin discretisation of the painted solid on the lattice's
/// own basis, the element core/solid_modes.h measures (simulatedElement()), made nonlinear so it can rotate.
///
/// At each quadrature point q the deformation gradient is F = Σ_i x_i ⊗ ∇N_i (world from the box frame,
/// ∇N_i the basis gradient at rest in the box frame, per metre). Its energy is that of linear elasticity
/// in the stretch, Ψ = ½ εᵀ C ε with ε = S − I and S = √(FᵀF) (the Biot strain, so rigid rotations cost
/// nothing and a small strain is linear elasticity's), C the painted modulus times the springs' elasticity
/// per unit of it (the solid the springs would make on a uniform cell). Its exact gradient is P = 2 F Y,
/// S Y + Y S = σ = C ε, solved in S's eigenbasis. Viscosity adds the rotated Kelvin-Voigt stress R η C
/// sym(Rᵀ Ḟ), which only dissipates. Node damping is ∫ γ ρ N_i N_j on absolute velocities.
///
/// The mass is the consistent ∫ ρ N_i N_j: a lumped one collapses this element's spectrum (docs/lattice.md),
/// so every step solves with its Cholesky factor over the free nodes (built once: it never changes).

#include "core/result.h"
#include "core/types.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <memory>
#include <span>
#include <vector>

namespace softtouch {

class Lattice;
struct LatticeMaterial;

/// One quadrature point: its weights and the nodes whose basis is non-zero there.
struct ElementPoint {
    double stiffness = 0.0;    ///< Quadrature weight × volume × painted modulus there, Pa·m³.
    double viscosity = 0.0;    ///< Quadrature weight × volume × painted viscosity there, Pa·s·m³.
    std::uint32_t first = 0;   ///< Its support in ElementBody::supportNode / supportGradient.
    std::uint32_t count = 0;
};

/// A lattice body's solid element, immutable once built (shared by every simulator of the body).
struct ElementBody {
    Eigen::Matrix<double, 6, 6> elasticity = Eigen::Matrix<double, 6, 6>::Zero(); ///< C per unit modulus, box frame.
    std::vector<ElementPoint> points;
    std::vector<std::uint32_t> supportNode;   ///< Node of each support entry.
    std::vector<Vec3> supportGradient;        ///< ∇N of that node at the point, box frame, 1/m.
    Eigen::MatrixXd mass;                     ///< ∫ρ N_i N_j over every node, kg.
    Eigen::MatrixXd nodeDamping;              ///< ∫γρ N_i N_j over every node, N·s/m.
    std::vector<int> slot;                    ///< Each node's row among the free nodes; -1 when held.
    std::vector<std::uint32_t> freeNodes;     ///< Free nodes in slot order.
    Eigen::LLT<Eigen::MatrixXd> massFactor;   ///< Of the free nodes' block of `mass`.
    bool viscous = false;                     ///< Some point has viscosity.
    bool nodeDamped = false;                  ///< Some node has node damping.
    double maxNodeDampingRate = 0.0;          ///< Largest painted node damping rate γ, 1/s (the step bound's).
    double maxDampingRatio = 0.0;             ///< Largest painted viscosity over modulus, s (the step bound's c/k).

    std::size_t nodeCount() const { return slot.size(); }
};

/// The element of a Continuum material on its lattice (simulatedElement(): degree Gauss points a span,
/// with kElementExactShare of the exactly integrated stiffness). `held` flags the nodes that do not move
/// (pinned and heavy anchors). Fails, saying why, for a material that is not Continuum or has void nodes.
Result<std::shared_ptr<const ElementBody>> buildElementBody(const Lattice& lattice, const LatticeMaterial& material,
                                                            std::span<const std::uint8_t> held);

/// Adds the elastic force −∂Ψ/∂x_i (and, as asked, the viscous and the node damping forces) to `force` on
/// the free nodes. Allocates nothing.
void addElementForces(const ElementBody& body, std::span<const Vec3> position, std::span<const Vec3> velocity,
                      std::span<Vec3> force, bool viscous, bool nodeDamping);
/// Adds only the damping forces (viscous and node damping), for the energy account's dissipation.
void addElementDampingForces(const ElementBody& body, std::span<const Vec3> position, std::span<const Vec3> velocity,
                             std::span<Vec3> force);
/// The elastic energy Σ_q w_q ½ εᵀ C ε, J.
double elementEnergy(const ElementBody& body, std::span<const Vec3> position);
/// The kinetic energy ½ vᵀ M v, J (held nodes do not move).
double elementKineticEnergy(const ElementBody& body, std::span<const Vec3> velocity);
/// a = M⁻¹ f over the free nodes (written to `acceleration` at the free nodes only). `work` is the
/// caller's scratch (3 × free nodes), so a step allocates nothing once it has its size.
void solveElementMass(const ElementBody& body, std::span<const Vec3> force, std::span<Vec3> acceleration,
                      Eigen::MatrixXd& work);
/// The stiffness at rest over the free nodes (3 × free square, unknown 3 s + c for slot s, component c): the
/// linearisation of addElementForces, as modes and step bounds need it.
Eigen::MatrixXd elementRestStiffness(const ElementBody& body, std::span<const Vec3> restPosition);
/// The viscous damping matrix at rest over the free nodes, laid out as elementRestStiffness().
Eigen::MatrixXd elementRestViscosity(const ElementBody& body, std::span<const Vec3> restPosition);

}  // namespace softtouch
