#pragma once
/// The Bullet contender of the paper's Table 1: btSoftBody, the peer a game developer would pick
/// instead of our lattice. Optional: without libbullet-dev at configure time the contender reports
/// itself absent and the bench prints "n/a" for it.

#include "bench/contenders.h"
#include "bench/static_response.h"

#include <optional>

namespace softtouch::bench {

/// True when this build has Bullet (libbullet-dev found at configure time).
bool bulletAvailable();

/// Bullet's stiffness and solver effort.
struct BulletSetting {
    double stiffnessScale = 1.0; ///< Multiplies scenario.stiffness before it is mapped to Bullet's kLST (> 0).
    int iterations = 1;          ///< Position-solver iterations per step (m_cfg.piterations); Bullet's
                                 ///< default is 1. The per-iteration kLST is mapped so that the spring
                                 ///< stays the same spring at any count (bullet_peer.cpp). [1, 4096].
};

/// Simulates the scenario with Bullet's btSoftBody (timed: the steps and the mesh at every frame);
/// nullopt without Bullet, or for a mesh btSoftBodyHelpers::CreateFromTriMesh cannot take (no
/// triangles, or more than 46340 vertices: it allocates a vertices² table indexed by int).
std::optional<ContenderRun> runBullet(const InteractionScenario& scenario, const BulletSetting& setting);

/// Bullet's static response: the drag held at scenario.dragOffset and the body run until the held
/// surface stops moving (a position solver has no equilibrium equation to solve directly). nullopt
/// where runBullet() has no run.
std::optional<StaticResponse> settleBullet(const InteractionScenario& scenario, const BulletSetting& setting);

}  // namespace softtouch::bench
