#pragma once
/// The modes of the solid a lattice material describes, converged: the reference a lattice's own modes
/// (core/modes/modes.h) are measured against.
///
/// A lattice body is a discretisation: its springs on a 4x4x4 control net store the energy of a solid
/// (core/body/network_elasticity.h) only under uniform strain, and its lumped node masses carry that solid's
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

#include "core/base/result.h"
#include "core/body/lattice_body.h"
#include "core/body/solid_element.h"
#include "core/geometry/lattice.h"

#include <Eigen/Core>

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace softtouch {

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

/// The `count` lowest elastic modes of `solid` on `element`; `solid.pinned` names the element's nodes (i +
/// count_u (j + count_v k)). Fails as solidModes() above does. Deformations that cost no energy (a reduced
/// integration's hourglass modes) are counted in `rigidModes` with the rigid motions.
Result<SolidModes> solidModes(const SolidField& solid, const SolidElement& element, int count = 3);

/// How far the centre of mass of `solid` moves hanging under `gravity` (m/s²) on `element`: the linear static solve
/// K u = ∫ρ N g, u weighted by each node's share of the mass. A measure every lattice of one body shares, whatever
/// its nodes. Fails where the anchors do not hold the solid.
Result<Vec3> solidSag(const SolidField& solid, const SolidElement& element, const Vec3& gravity);

/// The largest departure of the springs' solid from the material's that the front ends pass without a word.
inline constexpr double kSpringDepartureTolerance = 0.05;

/// How far a Continuum material's springs on a lattice are from the material they stand for: each constant of
/// networkElasticity() against materialElasticity(), springs / material - 1. On a cubic cell they are the
/// material; on flat or long cells central springs cannot be (shear across the thin side would need springs of
/// negative stiffness, docs/design/lattice.md).
struct SpringDeparture {
    std::array<double, 6> relative{};  ///< E_u, E_v, E_w, G_vw, G_uw, G_uv.
    double largest() const;            ///< The largest |relative|.
    /// "E_u +67%, G_uw -87%": every constant off by more than kSpringDepartureTolerance, the largest first.
    std::string describe() const;
};

/// The springs' departure from the material; nullopt for the legacy spring model (its springs are its material)
/// and where the springs or the material resist no uniform strain.
std::optional<SpringDeparture> springDeparture(const Lattice& lattice, const LatticeMaterial& material);

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
