#pragma once
/// The solid element a lattice body can run instead of springs (LatticeMaterial::element,
/// docs/design/lattice.md "The solid element"): the Galerkin discretisation of the painted solid on the lattice's
/// own basis, the element core/modes/solid_modes.h measures (simulatedElement()), made nonlinear so it can rotate.
///
/// At each quadrature point q the deformation gradient is F = Σ_i x_i ⊗ ∇N_i (world from the box frame,
/// ∇N_i the basis gradient at rest in the box frame, per metre). Its energy is that of linear elasticity
/// in the stretch, Ψ = ½ εᵀ C ε with ε = S − I and S = √(FᵀF) (the Biot strain, so rigid rotations cost
/// nothing and a small strain is linear elasticity's), C the painted modulus times the springs' elasticity
/// per unit of it (the solid the springs would make on a uniform cell). Its exact gradient is P = 2 F Y,
/// S Y + Y S = σ = C ε, solved in S's eigenbasis. Viscosity adds the rotated Kelvin-Voigt stress R η C
/// sym(Rᵀ Ḟ), which only dissipates. Node damping is ∫ γ ρ N_i N_j on absolute velocities.
///
/// The mass is the consistent ∫ ρ N_i N_j: a lumped one collapses this element's spectrum (docs/design/lattice.md),
/// so an explicit step multiplies the forces by its inverse over the free nodes (with the share of the viscosity the
/// substep takes implicitly, elementStepViscosity()), inverted once per substep length.
///
/// The work at the quadrature points is core/body/element_stress.h's, eight points at a time in SIMD lanes; the
/// maps between the nodes and the points are core/body/element_rule.h's.

#include "core/base/result.h"
#include "core/base/types.h"
#include "core/body/element_rule.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <array>
#include <memory>
#include <span>
#include <vector>

namespace softtouch {

class Lattice;
struct LatticeMaterial;

/// A lattice body's solid element, immutable once built (shared by every simulator of the body).
struct ElementBody {
    Eigen::Matrix<double, 6, 6> elasticity = Eigen::Matrix<double, 6, 6>::Zero(); ///< C per unit modulus, box frame.
    Mat3 frame = Mat3::Identity();            ///< The box's axes (columns): the rest rotation at every point.
    std::array<int, 3> counts{};              ///< Nodes per axis (node index i + n_u (j + n_v k)).
    std::vector<ElementRule> rules;           ///< The reduced rule (1 − share) and the exact one (share).
    Eigen::MatrixXd mass;                     ///< ∫ρ N_i N_j over every node, kg.
    Eigen::MatrixXd nodeDamping;              ///< ∫γρ N_i N_j over every node, N·s/m.
    std::vector<int> slot;                    ///< Each node's row among the free nodes; -1 when held.
    std::vector<std::uint32_t> freeNodes;     ///< Free nodes in slot order.
    Eigen::LLT<Eigen::MatrixXd> massFactor;   ///< Of the free nodes' block of `mass`.
    /// L⁻¹ of massFactor (M = L Lᵀ over the free nodes): a pull w on the nodes moves them as wᵀ M⁻¹ w = |L⁻¹ w|²,
    /// which the step bound of a drag needs. A consistent mass's inverse reaches light wiggles of the control net,
    /// many times what the nodes' ∫ρ N_i say.
    Eigen::MatrixXd inverseFactor;
    /// K̃ = ½ λ Σ_q η_q ∇N_i·∇N_j over every node, N·s/m (elementViscosityBound()); empty without viscosity.
    /// Whatever the points' rotations, the viscous matrix is at most 2 K̃: what an explicit substep takes
    /// implicitly is part of it (elementStepViscosity()).
    Eigen::MatrixXd viscosityBound;
    bool viscous = false;                     ///< Some point has viscosity.
    bool nodeDamped = false;                  ///< Some node has node damping.
    double maxNodeDampingRate = 0.0;          ///< Largest painted node damping rate γ, 1/s (the step bound's).

    std::size_t nodeCount() const { return slot.size(); }
};

/// The element of a Continuum material on its lattice (simulatedElement(): degree Gauss points a span,
/// with kElementExactShare of the exactly integrated stiffness). `held` flags the nodes that do not move
/// (pinned and heavy anchors). Fails, saying why, for a material that is not Continuum or has void nodes.
Result<std::shared_ptr<const ElementBody>> buildElementBody(const Lattice& lattice, const LatticeMaterial& material,
                                                            std::span<const std::uint8_t> held);

/// Adds the elastic force −∂Ψ/∂x_i (and, as asked, the viscous and the node damping forces) to `force` on
/// the free nodes. With `dampingOut` (one entry per node, zeroed first) it also receives the damping forces
/// alone, for the energy account's dissipation. Its scratch is the calling thread's: it allocates on a thread's
/// first call only.
void addElementForces(const ElementBody& body, std::span<const Vec3> position, std::span<const Vec3> velocity,
                      std::span<Vec3> force, bool viscous, bool nodeDamping, std::span<Vec3> dampingOut = {});
/// The rotation of each quadrature point's deformation at `position` (rule by rule, points in order): what
/// addElementTangent() turns the material's stiffness by.
void elementRotations(const ElementBody& body, std::span<const Vec3> position, std::vector<Mat3>& rotations);
/// y += Σ_q (a E_q + b η_q) Bᵀ R_q C R_qᵀ B p on the free nodes: the corotated stiffness (a) and viscosity (b)
/// at the state `rotations` were taken from, applied to the node field p (held nodes' p ignored). Implicit
/// Euler's system product, with a = h² and b = h. The stress's own change under rotation (geometric stiffness)
/// is left out: the matrix stays positive definite, and at rest it is exactly the linearisation.
void addElementTangent(const ElementBody& body, const std::vector<Mat3>& rotations, double a, double b,
                       std::span<const Vec3> p, std::span<Vec3> y);

/// The elastic energy Σ_q w_q ½ εᵀ C ε, J.
double elementEnergy(const ElementBody& body, std::span<const Vec3> position);
/// aᵀ M b over the free nodes, kg·m² for displacements: ½ vᵀMv is the kinetic energy.
double elementMassProduct(const ElementBody& body, std::span<const Vec3> a, std::span<const Vec3> b);
/// out_i += scale Σ_j m_ij in_j on the free rows i, over every column j, for one of the element's node matrices
/// (`mass` or `nodeDamping`): a consistent mass or damping times a node field.
void addElementMatrixTimes(const ElementBody& body, const Eigen::MatrixXd& nodeMatrix, double scale,
                           std::span<const Vec3> in, std::span<Vec3> out);
/// wᵀ M⁻¹ w for a pull spread over the free nodes by `share(visit)`, which calls visit(node, weight) for each:
/// 1/kg. `work` is the caller's (the free node count), so a step allocates nothing once it has its size.
template <typename Shares>
double elementPullInverseMass(const ElementBody& body, Shares&& shares, Eigen::VectorXd& work) {
    work.setZero(body.inverseFactor.rows());
    shares([&](std::uint32_t node, double weight) { work += weight * body.inverseFactor.col(body.slot[node]); });
    return work.squaredNorm();
}
/// A node matrix's block over the free nodes, acting on each component alike: 3 × free square, laid out as
/// elementRestStiffness().
Eigen::MatrixXd elementFreeMatrix(const ElementBody& body, const Eigen::MatrixXd& nodeMatrix);
/// out = A in over the free nodes (written at the free nodes only; `in` and `out` may be the same), for a
/// free × free matrix A in slot order acting on each component alike: an explicit substep's inverse mass
/// (M + h K̃_s)⁻¹ (elementStepViscosity()) turns forces into accelerations. `work` is the caller's scratch, so a
/// step allocates nothing once it has its size.
void applyElementFreeMatrix(const ElementBody& body, const Eigen::MatrixXd& matrix, std::span<const Vec3> in,
                            std::span<Vec3> out, Eigen::MatrixXd& work);
/// A node matrix's block over the free nodes (slot order), acting on each component alike.
Eigen::MatrixXd elementFreeBlock(const ElementBody& body, const Eigen::MatrixXd& nodeMatrix);

/// The modes of the viscosity bound over the free nodes: K̃ φ_j = k_j M φ_j, φ_j M-normalised, so that
/// K̃ = (M Φ) diag(k) (M Φ)ᵀ. Empty for a body without viscosity (K̃_s is then zero).
struct ElementViscosityModes {
    Eigen::MatrixXd massModes;  ///< M Φ, free × free (slot order).
    Eigen::VectorXd rates;      ///< k_j, 1/s, ascending.
};
ElementViscosityModes elementViscosityModes(const ElementBody& body);

/// The share of a substep's viscosity that its explicit step carries: a mode of K̃ with h k ≤ this is left to it.
inline constexpr double kExplicitViscosityShare = 0.25;

/// The viscosity an explicit substep of h takes implicitly, K̃_s over the free nodes (slot order, every component
/// alike), N·s/m: the substep solves (M + h K̃_s) Δv = h f, with the viscous force in f at the substep's start.
/// K̃_s keeps of each mode of K̃ the rate above kExplicitViscosityShare / h. The scheme is symplectic Euler on the
/// mass M + h K̃_s, stable while M + h K̃_s − h C/2 − h² K/4 stays positive definite; with C ≤ 2 K̃ at any rotation
/// that holds when M (1 − 0.25) − h² K/4 does, which at the step bound h ≤ 2 s/ω is 0.75 − s² > 0, true for the
/// simulator's stabilitySafety s up to 0.86 (0.8 by default): the viscosity never substeps. The smooth modes an
/// animator sees have rates below 0.25/h on ordinary materials and are not slowed at all.
Eigen::MatrixXd elementStepViscosity(const ElementBody& body, const ElementViscosityModes& modes, double h);
/// vᵀ K̃_s v over the free nodes at a substep of h, W: (h/2) times it is the extra kinetic energy of the substep's
/// mass, which the energy account's H̃ includes.
double elementStepViscosityProduct(const ElementBody& body, const ElementViscosityModes& modes, double h,
                                   std::span<const Vec3> velocity);
/// The stiffness at rest over the free nodes (3 × free square, unknown 3 s + c for slot s, component c): the
/// linearisation of addElementForces, as modes and step bounds need it.
Eigen::MatrixXd elementRestStiffness(const ElementBody& body);
/// The viscous damping matrix at rest over the free nodes, laid out as elementRestStiffness().
Eigen::MatrixXd elementRestViscosity(const ElementBody& body);
/// K̃ over every node (ElementBody::viscosityBound): half the bound λ Σ_q η_q ∇N_i·∇N_j on the viscous matrix
/// at any rotation of the points, λ the largest eigenvalue of C on symmetric strains.
Eigen::MatrixXd elementViscosityBound(const ElementBody& body);

}  // namespace softtouch
