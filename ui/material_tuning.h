#pragma once
/// Animator-facing material controls. Animators think in "how fast does it wobble" and "how quickly
/// does it settle", not in N/m and N·s/m, so the editor shows the body's lowest vibration modes
/// (core/modes/modes.h: the whole body with its anchors and voids, not one node on one spring) beside the
/// raw values. Setting the lowest mode's frequency scales every spring by (f'/f)² — the mode shapes do
/// not change when K is scaled, so the lowest mode lands on f' exactly — and both damping terms by
/// f'/f, which keeps every damping ratio. Setting the lowest mode's damping ratio scales both damping
/// terms by ζ'/ζ. Painted variations are kept either way.

#include "core/body/lattice_body.h"
#include "core/modes/modes.h"
#include "core/scene/scene.h"

#include <optional>

namespace softtouch::ui {

/// Means and totals of the painted values over non-void nodes (the modes come from materialModes()).
/// Means are in the material model's units (materialRanges()).
struct MaterialSummary {
    double meanMass = 0.0;       ///< kg per node, or kg/m³.
    double totalMass = 0.0;      ///< kg, non-void nodes (anchors at their own mass, not multiplied).
    double meanStiffness = 0.0;  ///< N/m, or Pa.
    double meanDamping = 0.0;    ///< Spring damping, N·s/m, or viscosity Pa·s.
    double meanNodeDamping = 0.0; ///< Node damping, N·s/m, or rate 1/s.
};

/// Summarises a material's painted values.
MaterialSummary summarise(const Lattice& lattice, const LatticeMaterial& material);

/// Largest lattice the editor analyses on every edit (free-node unknowns); finer lattices are analysed
/// by `softtouch-cli modes`.
inline constexpr int kLiveModalUnknowns = 1200;

/// The lowest `count` modes of the body built from `lattice` and `material`, or a reason why not.
/// `follow`: the body follows a base animation with these goal springs (their stiffness counts; nullptr: none).
Result<ModalAnalysis> materialModes(const Lattice& lattice, const LatticeMaterial& material, int count = 3,
                                    const FollowSettings* follow = nullptr);

/// Scales stiffness so the lowest mode lands on `hz` (> 0), damping so every damping ratio stays.
/// Returns false (material unchanged) when the body has no elastic mode. With goal springs (`follow`), which
/// the material does not scale, the mode's shape changes with the scale: a few steps land it within 0.1%, or,
/// where the goal springs make the mode (uniform goals), nothing can and it returns false, unchanged.
bool setFrequency(const Lattice& lattice, LatticeMaterial& material, double hz, const FollowSettings* follow = nullptr);
/// Scales both damping terms so the lowest mode's damping ratio becomes `ratio` (>= 0). A body with no
/// damping at all gets node damping first. Returns false when the body has no elastic mode.
bool setDampingRatio(const Lattice& lattice, LatticeMaterial& material, double ratio,
                     const FollowSettings* follow = nullptr);
/// Scales one per-node field so its mean over non-void nodes becomes `mean`.
void setMean(std::vector<double>& values, const LatticeMaterial& material, double mean);

}  // namespace softtouch::ui
