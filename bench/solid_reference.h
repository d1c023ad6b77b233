#pragma once
/// The one reference every contender of Table 1 is graded against: the converged solid under the same
/// pull. A continuum filling the lattice's box (the solid element on Bezier nets over it, contenders.h), its
/// Young's modulus calibrated like every contender to the common static displacement, its viscosity of the
/// same relaxation time, then refined in space (4x4x4, 6x6x6, 8x8x8 at one modulus) and in time (Verlet at
/// the scenario's step / 16, checked at / 32 on the coarsest net), with the estimate of how far the finest
/// run still is from the limit (analysis::refinementUncertainty, the study's rule).
///
/// Why the box and not the ellipsoid inside it: the solid element fills its lattice's box, and so does
/// every lattice SoftTouch simulates; the mesh bodies are closed membranes, which no solid is. The
/// reference says what an object that is solid under the same pull does; docs/measurements/performance.md
/// discusses what that means for each contender.

#include "bench/contenders.h"
#include "bench/equal_response.h"
#include "bench/static_response.h"
#include "analysis/converged_reference.h"

#include <ostream>
#include <string>
#include <vector>

namespace softtouch::bench {

struct SolidReference {
    Calibration calibration;                      ///< The modulus's scale (contenders.h) on the finest net.
    SolidMaterial material;                       ///< At the calibrated scale.
    std::vector<Vec3f> frames;                    ///< The mesh at every frame of the finest run.
    std::vector<analysis::ReferenceLevel> levels; ///< Every run, the time check first.
    analysis::RefinementUncertainty uncertainty;  ///< Of `frames`, fraction of the diagonal (RMS).
    std::string description;                      ///< One line: what the reference is.
};

/// What to refine.
struct SolidReferenceOptions {
    std::vector<int> nodes = {4, 6, 8};  ///< Bezier nodes per axis, coarsest first; the last is the reference.
    int stepDivision = 16;               ///< Verlet at scenario.dt / this; the coarsest net also at half of it.
};

/// Calibrates and refines the solid for `scenario` to the static displacement `target` (m), starting the
/// calibration at `firstScale`. Progress goes to `log`.
SolidReference solidReference(const InteractionScenario& scenario, double target, double firstScale,
                              const SolidReferenceOptions& options, std::ostream& log);

/// The solid's static displacement at `scale` on n³ nodes: implicit Euler at a large step with the drag
/// held at its final offset until what it holds stops (the solid has no spring energy for
/// settleOurs()'s Newton).
StaticResponse settleSolid(const InteractionScenario& scenario, double scale, int nodes);

}  // namespace softtouch::bench
