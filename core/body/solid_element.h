#pragma once
/// The solid a lattice material describes and the Galerkin elements that discretise it: the element a body
/// with LatticeMaterial::element = Solid runs (core/body/element_body.h) and the high-degree Bernstein element the
/// converged reference solves (core/modes/solid_modes.h). A solid filling the lattice box, with the painted
/// modulus and density interpolated by the lattice's basis, its elasticity per unit of modulus the solid the
/// springs make on a cubic cell (materialElasticity()).

#include "core/base/result.h"
#include "core/body/lattice_body.h"
#include "core/body/network_elasticity.h"
#include "core/geometry/axis_basis.h"
#include "core/geometry/lattice.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
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

/// How a discretisation of the solid carries its inertia.
enum class SolidMass {
    Consistent,  ///< ∫ρ N_i N_j: the Galerkin mass (non-diagonal; a simulation would need a mass solve).
    Lumped,      ///< Row sums ∫ρ N_i on the diagonal: one mass per node, as the lattice's integrators need.
};

/// A Galerkin element over the box: a tensor-product basis per axis (Bernstein or clamped B-spline), how its
/// mass is carried and how its stiffness is integrated. The reference is the Bernstein basis of high degree
/// with everything exact; on a lattice's own basis it is the element a lattice would simulate if it were not
/// springs (docs/design/lattice.md, "Could another element on the same net do it?").
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
/// lowest modes stay within 0.6% of the converged solid (within 3.0% fully integrated; docs/design/lattice.md).
inline constexpr double kElementExactShare = 0.3;

/// The element a body with LatticeMaterial::element = Solid runs (core/body/element_body.h): the lattice's own basis,
/// consistent mass, reduced integration with kElementExactShare of the exact stiffness.
SolidElement simulatedElement(const Lattice& lattice);

/// The elasticity a material's painted values mean, whatever the lattice: for a Continuum material, the solid its
/// springs make on a cubic cell aligned with the box, at the mean painted modulus (Young's modulus the painted one
/// along every axis, Poisson's ratio 17/61, shear modulus 17/18 · 61/117 of it; spring kinds and anisotropy
/// applied). Springs on other cell shapes (flat or long cells, a clamped B-spline's end cells) make another solid:
/// that is the springs' error, which springDeparture() states and `modes --reference` measures, not the material's.
/// The legacy spring model (a stiffness per spring, whatever the cells) means nothing beyond its own network.
/// The solid element runs this solid, so its modes do not depend on the lattice's cells.
NetworkElasticity materialElasticity(const Lattice& lattice, const LatticeMaterial& material);

/// The solid a lattice material describes: the painted values interpolated by the lattice's basis, times the
/// elasticity per unit of them that materialElasticity() gives (lattice-independent for a Continuum material),
/// with anchors (pinned and heavy alike) held where the material holds them, carried to the reference net as
/// resampleMaterial() carries them. Refuses void nodes: the solid fills the box.
Result<SolidField> materialSolid(const Lattice& lattice, const LatticeMaterial& material, int degree);

}  // namespace softtouch
