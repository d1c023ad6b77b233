#pragma once
/// What acts on a body from outside during one step, and the state the solver writes.

#include "core/base/types.h"
#include "core/body/body_model.h"
#include "core/body/colliders.h"
#include "core/body/spring_forces.h"
#include "core/geometry/lattice.h"

#include <span>
#include <vector>

namespace softtouch {

/// Positions and velocities of every node (void nodes included: derived from their donors).
struct BodyState {
    std::vector<Vec3> position; ///< Metres.
    std::vector<Vec3> velocity; ///< m/s.
    /// True when every value is finite.
    bool isFinite() const;
};

/// The rest state of a model: rest positions, zero velocities.
BodyState restState(const BodyModel& model);

/// A spring from a material point of the body to a target (the paper's drag force
/// F = Ks·d + Kd·v, where d is the distance to the target and v the relative velocity). The point
/// is given by its lattice weights; its force is spread to the nodes by the same weights.
struct DragSpring {
    std::vector<NodeWeight> support;       ///< Weights of the dragged material point; sum 1.
    Vec3 target = Vec3::Zero();            ///< Where the point is pulled, metres.
    Vec3 targetVelocity = Vec3::Zero();    ///< Velocity of the target, m/s (for the Kd term).
    double stiffness = 50.0;               ///< Ks, N/m, [0, 1e9].
    double damping = 1.0;                  ///< Kd, N·s/m, [0, 1e6].
};

/// An infinite collision plane (the paper's point-to-plane model).
struct CollisionPlane {
    Vec3 point = Vec3::Zero();       ///< Any point on the plane, metres.
    Vec3 normal = Vec3::UnitY();     ///< Unit normal pointing to the free side.
    double restitution = 0.0;        ///< Kr: 1 elastic, 0 sticks. Range [0, 1].
    double friction = 0.5;           ///< Coulomb coefficient on tangential velocity. Range [0, 10].
};

/// External influences for one step.
struct ExternalForces {
    Vec3 gravity = Vec3::Zero();            ///< m/s^2. Zero: no gravity pass.
    std::vector<DragSpring> drags;          ///< Any number (two hands, drivers).
    std::vector<CollisionPlane> planes;     ///< Empty: no collision pass.
    std::vector<Collider> colliders;        ///< Spheres, capsules, boxes; empty: no collider pass.
    /// A force on each node (one entry per node, N), held over the step: the inertia of a body that follows
    /// a base animation, seen from the animation (core/animation/base_motion.h). Empty: none. Booked by the energy
    /// account as external work, like the drags'.
    std::vector<Vec3> nodeForces;
    /// Names the first non-finite input, or returns an empty string when all are finite.
    std::string firstNonFinite() const;
};

/// Which force terms accumulateForces() adds.
struct ForceTerms {
    /// Spring forces: elastic k(|r|-L) r̂ and damping c ((v_b - v_a)·r̂) r̂; on a solid element body, the element's
    /// elastic and viscous forces (its elastic force always: it has no springs to leave out).
    bool springs = true;
    bool nodeDamping = true;   ///< −d_i v_i on every node (the paper's D, absolute velocity).
};

/// Adds all forces on every node into `force` (which is zeroed first): springs, spring damping, node
/// damping, gravity (m·g), node forces, drags. Only free nodes' forces are meaningful; pinned and void nodes get
/// gravity and damping but no spring or drag force. `scratch` is the caller's, so nothing is allocated.
/// When `dragPulls` is given (one entry per drag), it receives each drag's pull F = Ks·d + Kd·v, N. When
/// `elementDamping` is given (one entry per node) on a solid element body, it receives the element's damping
/// forces alone (viscous and node damping; `force` holds them too), N: what the energy account needs.
void accumulateForces(const BodyModel& model, const ExternalForces& external, std::span<const Vec3> position,
                      std::span<const Vec3> velocity, std::span<Vec3> force, SpringScratch& scratch,
                      ForceTerms terms = {}, std::span<Vec3> dragPulls = {}, std::span<Vec3> elementDamping = {});

/// The current position and velocity of a drag's material point.
void dragPointState(const DragSpring& drag, std::span<const Vec3> position, std::span<const Vec3> velocity,
                    Vec3& point, Vec3& pointVelocity);

/// Calls share(node, weight) for each free node of a drag's support with its weight in the drag's
/// force distribution (renormalised so the full force reaches the body when part of the support is
/// void or pinned). Calls nothing when no node of the support can move. Allocates nothing.
template <typename Share>
void forEachDragShare(const BodyModel& model, const DragSpring& drag, Share&& share) {
    double total = 0.0;
    for (const NodeWeight& w : drag.support) {
        if (model.inverseMass[w.node] > 0.0)
            total += w.weight;
    }
    if (total <= 0.0)
        return;
    const double scale = 1.0 / total;
    for (const NodeWeight& w : drag.support) {
        if (model.inverseMass[w.node] > 0.0 && w.weight != 0.0)
            share(w.node, w.weight * scale);
    }
}

/// Point-to-plane response after a step (the paper's model): a node behind a plane is put back onto
/// it and its inward velocity Vn answered with V' = Vt·(friction loss) − Kr·Vn. Only a node that
/// arrives (was in front of the plane at `stepStart`) bounces; one that was already touching is a
/// resting contact and gets Kr = 0, so bodies settle instead of chattering.
void resolvePlaneContacts(const BodyModel& model, std::span<const CollisionPlane> planes,
                          std::span<const Vec3> stepStart, double stepSeconds, const Vec3& gravity, BodyState& state);
/// Below this approach speed (m/s) a contact is resting and does not bounce: about the speed gravity
/// adds in two steps of h seconds.
inline double restingContactSpeed(const Vec3& gravity, double h) { return 2.0 * gravity.norm() * h; }
/// One free node against one plane, as resolvePlaneContacts does it: returns false (and changes
/// nothing) when the node at x is in front of the plane; `stepStart` is its position before the step.
bool resolvePlaneContact(const CollisionPlane& plane, const Vec3& stepStart, double restingSpeed, Vec3& x, Vec3& v);

/// Moves every void node by the mean displacement (and velocity) of its donors.
void updateVoidNodes(const BodyModel& model, BodyState& state);

/// Kinetic energy ½ Σ m v² of the simulated nodes (½ vᵀMv on a solid element body), joules.
double kineticEnergy(const BodyModel& model, const BodyState& state);
/// Elastic energy ½ Σ k (|r| − L)² (the element's ½ εᵀCε on a solid element body), joules.
double springEnergy(const BodyModel& model, const BodyState& state);
/// Gravitational energy −Σ m g·x of the simulated nodes, joules.
double gravityEnergy(const BodyModel& model, const BodyState& state, const Vec3& gravity);
/// aᵀ M b over the free nodes, M the body's mass (one per node, or a solid element's consistent one): the
/// inner product that keeps modes apart, kg·m².
double massInnerProduct(const BodyModel& model, std::span<const Vec3> a, std::span<const Vec3> b);
/// Total linear momentum Σ m v of the simulated nodes, kg·m/s.
Vec3 linearMomentum(const BodyModel& model, const BodyState& state);

}  // namespace softtouch
