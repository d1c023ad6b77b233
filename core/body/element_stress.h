#pragma once
/// The solid element's work at its quadrature points (core/body/element_body.h), points in SIMD lanes: each
/// function takes kStressLanes points at once, every quantity an array with one entry per point, so that every
/// loop over the lanes compiles to vector instructions. A 3x3 eigensolve of the stretch at every point is most
/// of the element's force pass; here it is cyclic Jacobi (square roots and divisions, no trigonometry, no
/// branch), which the lanes share.
///
/// Matrices are column-major, entry (row α, column c) at 3c + α: the deformation gradient's column c is
/// ∂x/∂X_c. Symmetric tensors are held as Voigt vectors (uu, vv, ww, vw, uw, uv).

#include <Eigen/Core>

#include <array>

namespace softtouch {

/// Points per call. Four fill an AVX register of doubles and two SSE2 ones.
inline constexpr int kStressLanes = 8;

/// One quantity at every lane.
using Lanes = std::array<double, kStressLanes>;

/// The stretch of F at each lane: FᵀF − I = V diag(g) Vᵀ, the singular values s = √(1 + g) and the Biot strain
/// S − I = V diag(g / (1 + s)) Vᵀ (no cancellation for small strains).
struct StretchLanes {
    std::array<Lanes, 9> basis;    ///< V, column-major: column a is the eigenvector of g_a.
    std::array<Lanes, 3> singular; ///< s.
    std::array<Lanes, 6> strain;   ///< S − I, Voigt order, tensor entries (not doubled shears).
};

/// The stretch of the deformation gradients `f` (nine entries, column-major). A collapsed direction (g ≤ −1)
/// keeps a length of 1e-6, as a step that inverts a point must not divide by zero.
void stretchLanes(const std::array<Lanes, 9>& f, StretchLanes& out);

/// The elastic stress at each lane: σ = k C ε (ε the strain with doubled shears, C the elasticity per unit
/// modulus, k the point's modulus × weight) and the first Piola-Kirchhoff stress P = 2 F Y with S Y + Y S = σ,
/// the exact gradient of ½ εᵀ C ε in F (S's eigenbasis makes the Sylvester equation diagonal). Adds ½ εᵀσ of
/// each lane to `energy` when it is given.
void elasticStressLanes(const Eigen::Matrix<double, 6, 6>& elasticity, const Lanes& modulus, const std::array<Lanes, 9>& f,
                        const StretchLanes& stretch, std::array<Lanes, 9>& stress, Lanes* energy = nullptr);

/// The rotation of F's polar decomposition, R = F S⁻¹, at each lane.
void rotationLanes(const std::array<Lanes, 9>& f, const StretchLanes& stretch, std::array<Lanes, 9>& rotation);

/// The corotated linear stress R (a C sym(Rᵀ G)) at each lane, written to `stress`: with G the velocity
/// gradient Ḟ and a the point's viscosity × weight, the rotated Kelvin-Voigt stress; with G the gradient of a
/// node field, implicit Euler's system product (addElementTangent()).
void corotatedStressLanes(const Eigen::Matrix<double, 6, 6>& elasticity, const Lanes& factor,
                          const std::array<Lanes, 9>& rotation, const std::array<Lanes, 9>& gradient,
                          std::array<Lanes, 9>& stress);

}  // namespace softtouch
