#pragma once
/// Animator-facing material controls. Animators think in "how fast does it wobble" and "how quickly
/// does it settle", not in N/m and N·s/m, so the editor shows both views of one material:
///
///   f = (1/2π) √(k̄ / m̄)        natural frequency of a mean node on a mean spring, Hz
///   ζ = c̄ / (2 √(k̄ m̄))         damping ratio of that oscillator (1 = critically damped)
///
/// with k̄, c̄, m̄ the means over non-void nodes. Setting f scales every node's stiffness by
/// (f'/f)², setting ζ every node's damping, so painted variations are kept. (The body's lowest mode is
/// lower than f because many springs act in series; f is a per-node measure, stated as such in the UI.)

#include "core/lattice_body.h"

namespace softtouch::ui {

/// Means over non-void nodes.
struct MaterialSummary {
    double meanMass = 0.0;       ///< kg.
    double totalMass = 0.0;      ///< kg, non-void nodes (anchors at their own mass, not multiplied).
    double meanStiffness = 0.0;  ///< N/m.
    double meanDamping = 0.0;    ///< N·s/m.
    double frequencyHz = 0.0;    ///< f above.
    double dampingRatio = 0.0;   ///< ζ above.
};

/// Summarises a material.
MaterialSummary summarise(const LatticeMaterial& material);
/// Scales stiffness so that summarise().frequencyHz becomes `hz` (> 0). Damping is rescaled too so
/// the damping ratio stays the same.
void setFrequency(LatticeMaterial& material, double hz);
/// Scales damping so that summarise().dampingRatio becomes `ratio` (>= 0).
void setDampingRatio(LatticeMaterial& material, double ratio);
/// Scales one per-node field so its mean over non-void nodes becomes `mean`.
void setMean(std::vector<double>& values, const LatticeMaterial& material, double mean);

}  // namespace softtouch::ui
