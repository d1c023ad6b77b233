#pragma once
/// The modes of the solid a lattice material describes, converged: the reference a lattice's own modes
/// (core/modes.h) are measured against.
///
/// A lattice body is a discretisation: its springs on a 4x4x4 control net store the energy of a solid
/// (core/network_elasticity.h) only under uniform strain, and its lumped node masses carry that solid's
/// inertia only roughly. How far its modes are from the solid's is the lattice's own error, the part of
/// "speed against accuracy" a finer lattice buys. This solves the same solid without the lattice's
/// approximations: a Galerkin (Rayleigh-Ritz) discretisation of linear elasticity over a tensor-product
/// Bernstein basis of high degree on the lattice box, with the consistent mass matrix ∫ρ N_i N_j:
///
///   K_(iα)(jβ) = ∫ e(x) ∂_k N_i T_(αk)(βl) ∂_l N_j dV,   M_(iα)(jβ) = δ_αβ ∫ ρ(x) N_i N_j dV,
///
/// with T = Pᵀ C P (C the elasticity per unit of the painted modulus in Voigt order, P the map from the
/// displacement gradient to Voigt strain), e(x) and ρ(x) the painted modulus and density interpolated by
/// the body's own lattice basis, Gauss-Legendre quadrature exact for the polynomial parts. Rayleigh-Ritz
/// frequencies fall towards the solid's as the degree rises (tests/core/test_solid_modes checks an axial
/// rod against its closed form and the convergence in degree).

#include "core/axis_basis.h"
#include "core/lattice.h"
#include "core/lattice_body.h"
#include "core/network_elasticity.h"
#include "core/result.h"

#include <Eigen/Core>

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace softtouch {

/// T = Pᵀ C P: the 9x9 elasticity acting on displacement gradients, columns (α, k) = 3α + k meaning ∂u_α/∂x_k,
/// P the map from gradients to Voigt strain (ε_uu, ε_vv, ε_ww, 2ε_vw, 2ε_uw, 2ε_uv).
Eigen::Matrix<double, 9, 9> gradientElasticity(const Eigen::Matrix<double, 6, 6>& c);

/// Highest Bernstein degree solidModes() takes (kMaxBasisOrder - 1), and the degree it uses by default.
inline constexpr int kMaxSolidDegree = 7;
inline constexpr int kDefaultSolidDegree = 5;

/// A solid filling a box, in the box frame (parameters s in [0,1]^3, x = s .* size).
struct SolidField {
    Vec3 size = Vec3::Ones();                        ///< Box edge lengths, m.
    Eigen::Matrix<double, 6, 6> elasticity =         ///< C per unit of `modulus`, Voigt order (uu, vv, ww, vw, uw, uv).
        Eigen::Matrix<double, 6, 6>::Zero();
    std::function<double(const Vec3&)> modulus;      ///< Scale of C at parameters s (>= 0).
    std::function<double(const Vec3&)> density;      ///< kg/m³ at parameters s (> 0).
    /// Reference nodes held fixed: one flag per node of the (degree+1)^3 Bernstein net, index i + n(j + n k).
    /// Empty: a free body.
    std::vector<std::uint8_t> pinned;
};

/// Largest relative change of a mode between degrees P-1 and P that materialSolidModes() still calls
/// converged.
inline constexpr double kSolidConvergedSpread = 0.02;

/// The result of solidModes().
struct SolidModes {
    std::vector<double> frequencyHz;  ///< Lowest elastic modes first, Hz.
    int degree = 0;                   ///< Polynomial degree of the element (its highest along any axis).
    int unknowns = 0;                 ///< 3 × free reference nodes.
    int rigidModes = 0;               ///< Zero-frequency modes skipped (rigid motions, and any hourglass modes).
    /// materialSolidModes() only: the largest relative change of a mode from degree P-1 to P (-1 when P = 1).
    /// A solid held at points or along lines is not held at all in the limit (elasticity feels no
    /// constraint of zero area), so such anchors never converge: its frequencies wander with the degree.
    double spread = -1.0;
    bool converged() const { return spread >= 0.0 && spread <= kSolidConvergedSpread; }
};

/// The `count` lowest elastic modes of `solid` at Bernstein degree `degree` (1..kMaxSolidDegree).
/// Fails, saying why, on a bad degree, a field that is not positive and finite, or every node pinned.
Result<SolidModes> solidModes(const SolidField& solid, int degree, int count = 3);

/// How a discretisation of the solid carries its inertia.
enum class SolidMass {
    Consistent,  ///< ∫ρ N_i N_j: the Galerkin mass (non-diagonal; a simulation would need a mass solve).
    Lumped,      ///< Row sums ∫ρ N_i on the diagonal: one mass per node, as the lattice's integrators need.
};

/// A Galerkin element over the box: a tensor-product basis per axis (Bernstein or clamped B-spline), how its
/// mass is carried and how its stiffness is integrated. The reference is the Bernstein basis of high degree
/// with everything exact; on a lattice's own basis it is the element a lattice would simulate if it were not
/// springs (docs/lattice.md, "Could another element on the same net do it?").
struct SolidElement {
    std::array<AxisBasis, 3> axes;
    SolidMass mass = SolidMass::Consistent;
    /// Gauss points per knot span and axis for the stiffness; 0: degree + 3, exact for a cubic modulus (degree + 1
    /// is exact for a constant one). Fewer than degree + 1 (reduced integration) softens the element and can leave
    /// deformations that cost no energy.
    int stiffnessPoints = 0;
    /// Reduced integration: each axis's degree in Gauss points a span (stiffnessPoints is then ignored), blended
    /// with `exactShare` of the stiffness at degree + 1 points: K = (1 - share) K_reduced + share K_exact. Any
    /// share above 0 gives every deformation an energy (it stabilises the hourglass modes).
    bool reduced = false;
    double exactShare = 0.0;  ///< With `reduced`, 0 to 1.
};

/// The Bernstein element of `degree` per axis, consistent mass, exact stiffness: what solidModes(solid,
/// degree) solves.
SolidElement bernsteinElement(int degree);

/// The lattice's own basis as an element (`mass` and `stiffnessPoints` at their defaults).
SolidElement latticeElement(const Lattice& lattice);

/// The share of the exactly integrated stiffness in the element a body simulates (simulatedElement()). Reduced
/// integration alone leaves a Bezier lattice deformations that cost no energy; with 0.2 of the exact stiffness
/// blended in they rise above a free cube's third mode on a 4x4x4 net, and 0.3 leaves a margin; the fish's three
/// lowest modes stay within 0.6% of the converged solid (within 3.0% fully integrated; docs/lattice.md).
inline constexpr double kElementExactShare = 0.3;

/// The element a body with LatticeMaterial::element = Solid runs (core/element_body.h): the lattice's own basis,
/// consistent mass, reduced integration with kElementExactShare of the exact stiffness.
SolidElement simulatedElement(const Lattice& lattice);

/// The `count` lowest elastic modes of `solid` on `element`; `solid.pinned` names the element's nodes (i +
/// count_u (j + count_v k)). Fails as solidModes() above does. Deformations that cost no energy (a reduced
/// integration's hourglass modes) are counted in `rigidModes` with the rigid motions.
Result<SolidModes> solidModes(const SolidField& solid, const SolidElement& element, int count = 3);

/// How far the centre of mass of `solid` moves hanging under `gravity` (m/s²) on `element`: the linear static solve
/// K u = ∫ρ N g, u weighted by each node's share of the mass. A measure every lattice of one body shares, whatever
/// its nodes. Fails where the anchors do not hold the solid.
Result<Vec3> solidSag(const SolidField& solid, const SolidElement& element, const Vec3& gravity);

/// The elasticity a material's painted values mean, whatever the lattice: for a Continuum material, the solid its
/// springs make on a cubic cell aligned with the box, at the mean painted modulus (Young's modulus the painted one
/// along every axis, Poisson's ratio 17/61, shear modulus 17/18 · 61/117 of it; spring kinds and anisotropy
/// applied). Springs on other cell shapes (flat or long cells, a clamped B-spline's end cells) make another solid:
/// that is the springs' error, which springDeparture() states and `modes --reference` measures, not the material's.
/// The legacy spring model (a stiffness per spring, whatever the cells) means nothing beyond its own network.
/// The solid element runs this solid, so its modes do not depend on the lattice's cells.
NetworkElasticity materialElasticity(const Lattice& lattice, const LatticeMaterial& material);

/// The largest departure of the springs' solid from the material's that the front ends pass without a word.
inline constexpr double kSpringDepartureTolerance = 0.05;

/// How far a Continuum material's springs on a lattice are from the material they stand for: each constant of
/// networkElasticity() against materialElasticity(), springs / material - 1. On a cubic cell they are the
/// material; on flat or long cells central springs cannot be (shear across the thin side would need springs of
/// negative stiffness, docs/lattice.md).
struct SpringDeparture {
    std::array<double, 6> relative{};  ///< E_u, E_v, E_w, G_vw, G_uw, G_uv.
    double largest() const;            ///< The largest |relative|.
    /// "E_u +67%, G_uw -87%": every constant off by more than kSpringDepartureTolerance, the largest first.
    std::string describe() const;
};

/// The springs' departure from the material; nullopt for the legacy spring model (its springs are its material)
/// and where the springs or the material resist no uniform strain.
std::optional<SpringDeparture> springDeparture(const Lattice& lattice, const LatticeMaterial& material);

/// The solid a lattice material describes: the painted values interpolated by the lattice's basis, times the
/// elasticity per unit of them that materialElasticity() gives (lattice-independent for a Continuum material),
/// with anchors (pinned and heavy alike) held where the material holds them, carried to the reference net as
/// resampleMaterial() carries them. Refuses void nodes: the solid fills the box.
Result<SolidField> materialSolid(const Lattice& lattice, const LatticeMaterial& material, int degree);

/// materialSolid() then solidModes(), at `degree` and at degree - 1 to fill `spread`.
Result<SolidModes> materialSolidModes(const Lattice& lattice, const LatticeMaterial& material,
                                      int degree = kDefaultSolidDegree, int count = 3);

/// A lattice body's modes against the converged solid of its material.
struct SolidComparison {
    SolidModes solid;                ///< The solid's modes (and whether they converged).
    std::vector<double> latticeHz;   ///< The body's lowest modes, Hz (its material alone: no goal springs).
    /// latticeHz[m] / solid.frequencyHz[m] - 1 per mode; empty when the solid did not converge.
    std::vector<double> error;
};

/// materialSolidModes() beside the lowest `count` modes of buildLatticeBody(lattice, material): what
/// `softtouch-cli modes --reference` prints and the editor's "Compare with the solid" shows.
Result<SolidComparison> compareWithSolid(const Lattice& lattice, const LatticeMaterial& material,
                                         int degree = kDefaultSolidDegree, int count = 3);

/// "+0.3% / -2.6% / -11.9%": mode errors (SolidComparison::error) as every front end prints them.
std::string describeModeErrors(const std::vector<double>& errors);

}  // namespace softtouch
