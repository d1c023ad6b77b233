#pragma once
/// The contenders of the paper's Table 1, each timing the same InteractionScenario.

#include "bench/scenario.h"
#include "core/integrator.h"
#include "core/lattice.h"

namespace softtouch::bench {

/// Our method: a lattice around the mesh is simulated, the mesh evaluated from it at the frame rate
/// (one thread, like the others). Binding and lattice set-up are not timed (done once per asset).
TimingResult timeLattice(const InteractionScenario& scenario, IntegratorKind integrator,
                         const LatticeShape& shape = {});

/// A mass-spring on the mesh: every vertex a node, every edge a spring (the paper's "global"). With
/// `localRadius` > 0, only vertices within that distance of the dragged vertex are simulated and the
/// rest of the mesh stays static (the paper's "local mass-spring", its reference 32).
TimingResult timeMeshSpring(const InteractionScenario& scenario, IntegratorKind integrator, double localRadius = 0.0);

}  // namespace softtouch::bench
