#pragma once
/// Volume preservation: a squashed cartoon body bulges instead of losing volume (docs/design/lattice.md,
/// "Volume preservation").
///
/// The kept quantity is the volume of the mesh as the lattice map carries it: by the change of variables
/// x = F(u), V = ∫_Ω det J(u) du over the mesh's region Ω of the parameter box, J = [x_u x_v x_w] =
/// Σ_i x_i ∇N_i(u)ᵀ. It is sampled at the centres u_q of G³ equal cells of the box, each weighted by the
/// cell's parameter volume times the fraction of it inside the mesh (core/geometry/mesh_volume), so V0 is the mesh's
/// volume and V(x) = Σ_q w_q det J(u_q) follows it as the lattice deforms, at a cost that does not grow
/// with the mesh. Its gradient is exact: ∂ det J / ∂x_i = ∂_u N_i (x_v × x_w) + ∂_v N_i (x_w × x_u) +
/// ∂_w N_i (x_u × x_v).
///
/// It acts as one compliant constraint C(x) = V(x) − V0 on the whole body after every substep of every
/// integrator (one mechanism for all four), in XPBD's form (Macklin, Müller & Chentanez, "XPBD:
/// Position-Based Simulation of Compliant Constrained Dynamics", MIG 2016): with inverse masses w_i,
///   Δλ = −C / (Σ_i w_i |∇_i C|² + α / h²),  Δx_i = w_i ∇_i C Δλ,  Δv_i = Δx_i / h,
/// which is the symplectic Euler step of the force −∇(C² / 2α) taken implicitly along ∇C. The compliance
/// α = V0 / K comes from a bulk modulus K = E p / (1 − p), E the springs' modulus (mean k / L over the
/// springs) and p ∈ [0, 1] the material's `volumePreservation`: p = 1/2 resists a volume change as much
/// as the springs resist a stretch, p = 0.9 nine times as much, and p = 1 is a hard constraint (α = 0:
/// Newton iterations until |C| < 1e-6 V0).
///
/// p is painted per node. The body keeps one constraint, stiff as its largest p, over a volume in which
/// each sample counts by the painted map carried to it through the lattice basis, p(u_q) / max p: where
/// the map is 0 the mesh's volume is not kept (a fin squashes flat), where it is highest it counts fully,
/// and a squashed painted region bulges within itself and the regions painted beside it. Every sample's
/// det J is unchanged by a translation, so Σ_i ∇_i C = 0 for any map and the correction keeps momentum.

#include "core/base/types.h"
#include "core/geometry/lattice.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace softtouch {

struct BodyModel;
struct BodyState;
struct CollisionPlane;

/// The sampled volume of a body and how stiffly it is kept. Empty (inactive) when preservation is 0.
struct VolumeConstraint {
    double preservation = 0.0;          ///< The largest painted p, [0, 1]; 0: off.
    double restVolume = 0.0;            ///< V0, m³ (the mesh's volume; the box's when there is no mesh).
    double compliance = 0.0;            ///< α = V0 / K, m³/Pa; 0 at p = 1 (hard).
    int cells = 0;                      ///< G: samples per box axis.
    std::array<int, 3> nodes{};         ///< Lattice nodes per axis.
    /// Per axis: basis values and slopes of every node at the G sample parameters, [g * nodes + i].
    std::array<std::vector<double>, 3> value, slope;
    std::vector<double> weight;         ///< w_q on the G³ grid (q = gu + G·(gv + G·gw)): parameter volume ×
                                        ///< the fraction inside the mesh × p(u_q) / max p; 0 outside it.
    bool active() const { return preservation > 0.0 && !weight.empty() && restVolume > 0.0; }
};

/// Cells per box axis the volume is sampled on: the lattice's largest node count, at least 4.
int volumeSampleCells(const Lattice& lattice);

/// The constraint of `lattice` sampled on G³ cells (G = volumeSampleCells) with `occupancy` the fraction
/// of each cell inside the mesh (index cu + G·(cv + G·cw); empty: the whole box). `preservation`: p per
/// lattice node (see above; a uniform map weighs every sample alike). `modulus` E in Pa (> 0).
VolumeConstraint buildVolumeConstraint(const Lattice& lattice, const std::vector<double>& occupancy,
                                       std::span<const double> preservation, double modulus);

/// V(x) = Σ_q w_q det J(u_q) of node positions `x`; with `gradient` (one entry per node, zeroed here)
/// also ∂V/∂x_i. The tangents x_u, x_v, x_w on the whole grid are sums over one axis at a time (a
/// tensor-product lattice), and the gradient is the same sums transposed.
double sampledVolume(const VolumeConstraint& volume, std::span<const Vec3> x, std::span<Vec3> gradient = {});

/// One substep's correction (see above) on `state`, which the integrator has just advanced by `h`.
/// A node resting on one of `planes` moves only along it (the part of its correction into the plane is
/// dropped), so a body squashed between planes bulges sideways instead of into them. `scratch` holds one
/// entry per node. Returns V before the correction.
double enforceVolume(const BodyModel& model, BodyState& state, double h, std::vector<Vec3>& scratch,
                     std::span<const CollisionPlane> planes = {});

/// The signed volume a closed triangle mesh encloses, m³ (divergence theorem; for reports and tests).
double enclosedVolume(std::span<const Vec3f> positions, std::span<const std::array<std::uint32_t, 3>> triangles);

}  // namespace softtouch
