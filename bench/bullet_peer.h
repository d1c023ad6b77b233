#pragma once
/// The Bullet contender of the paper's Table 1: btSoftBody, the peer a game developer would pick
/// instead of our lattice. Optional: without libbullet-dev at configure time the contender reports
/// itself absent and the bench prints "n/a" for it.

#include "bench/scenario.h"

#include <optional>

namespace softtouch::bench {

/// True when this build has Bullet (libbullet-dev found at configure time).
bool bulletAvailable();

/// Simulates the scenario with Bullet's btSoftBody and returns the wall time; nullopt without Bullet,
/// or for a mesh btSoftBodyHelpers::CreateFromTriMesh cannot take (no triangles, or more than 46340
/// vertices: it allocates a vertices² table indexed by int).
std::optional<TimingResult> timeBulletSoftBody(const InteractionScenario& scenario);

}  // namespace softtouch::bench
