#pragma once
/// The static response of a contender of ours: the drag held at the scenario's final offset, and how
/// far what the drag holds goes once nothing moves. Equal static displacement under the same pull is
/// what makes the contenders of Table 1 comparable (equal_response.h).
///
/// The equilibrium is a minimum of the elastic energy plus the drag spring's,
///     E(x) = Σ_springs ½ k (|x_a − x_b| − L)² + ½ Ks |Σ_n w_n x_n − target|²,
/// found by Newton's method from the rest shape (or a given start) with each spring's Hessian made
/// positive semi-definite as our implicit Euler makes it (the transverse term k·max(0, 1 − L/l) is
/// dropped under compression) and a backtracking line search on E. Why not backward Euler, whose
/// fixed point is the same equilibrium: on the mesh bodies, which are closed membranes of edge springs
/// with nothing resisting bending, a pull sideways wrinkles the compressed side; large implicit steps
/// (velocity cleared after each) overshoot there and creep, and each one first spends 30 CG iterations
/// before its direct solve (1.1 s a step at 24,928 triangles against 0.6 s for a Newton iteration).
/// The line search makes every iteration lower E, so the settle ends in a stable equilibrium and the
/// same one every time.

#include "bench/contenders.h"

#include <vector>

namespace softtouch::bench {

/// Where a settle ended.
struct StaticResponse {
    double displacement = 0.0; ///< |held material's mean − its rest position| at equilibrium, m.
    int steps = 0;             ///< Newton iterations (ours) or simulation steps (Bullet) it took.
    bool converged = false;    ///< The displacement stopped changing (see settleOurs()) within the cap.
};

/// Settles `body` under the drag held at scenario.dragOffset: at most 40 Newton iterations, converged
/// once two in a row change the displacement by less than 2·10⁻⁴ of itself. `start`, when given and of
/// the body's node count, is where the iterations start (a neighbouring stiffness's equilibrium takes
/// fewer); it receives the equilibrium.
StaticResponse settleOurs(const InteractionScenario& scenario, const OurBody& body, std::vector<Vec3>* start = nullptr);

}  // namespace softtouch::bench
