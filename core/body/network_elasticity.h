#pragma once
/// What solid the lattice's springs make: the elasticity a body shows under a uniform strain.
///
/// Under a uniform strain ε every spring stretches by L·nᵀεn, so the springs store
///   U = ½ Σ_s k_s L_s² (nᵀεn)² = ½ V eᵀ C e,   C_IJ = (1/V) Σ_s k_s L_s² m_I m_J,
/// with e the strain in Voigt order (ε_uu, ε_vv, ε_ww, 2ε_vw, 2ε_uw, 2ε_uv), m = (n_u², n_v², n_w²,
/// n_v n_w, n_u n_w, n_u n_v) in the box frame and V the box volume. Central springs obey Cauchy's
/// relations (C_12 = C_66, …), so the solid has Poisson's ratio 1/4 at best and is isotropic only by
/// accident of cell shape: on cubic cells the Continuum material's C is the cubic solid whose Young's
/// modulus along each axis is the painted one (docs/design/lattice.md, "Material"); on flat cells (a fish's
/// box) the same springs make a stiff in-plane, soft-in-shear solid. This is what the body does, so
/// it is what the editor and `softtouch-cli modes` show beside the painted value.

#include "core/body/lattice_body.h"
#include "core/geometry/lattice.h"

#include <Eigen/Core>

namespace softtouch {

/// The elasticity of a lattice body's spring network (box frame, per unit box volume).
struct NetworkElasticity {
    Eigen::Matrix<double, 6, 6> stiffness = Eigen::Matrix<double, 6, 6>::Zero(); ///< C, Pa, Voigt order above.
    bool resistsEveryStrain = false; ///< C is positive definite (false when spring kinds are scaled to 0).
    Vec3 youngsModulus = Vec3::Zero(); ///< E_u, E_v, E_w under uniaxial stress along each box axis, Pa (0 unless resistsEveryStrain).
    Vec3 shearModulus = Vec3::Zero();  ///< G_vw, G_uw, G_uv, Pa (0 unless resistsEveryStrain).
};

/// The effective elasticity of the non-void springs of `material` on `lattice` under a uniform strain,
/// either material model. For a uniform material on Bezier cells this is every cell's; for painted
/// maps and uneven B-spline cells it is the volume average the body feels under a uniform strain.
NetworkElasticity networkElasticity(const Lattice& lattice, const LatticeMaterial& material);

}  // namespace softtouch
