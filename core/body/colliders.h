#pragma once
/// Colliders beyond planes: spheres, capsules, boxes and static meshes (rocks, the tank's furniture, a stick), tested at
/// points of the mesh's surface carried by the lattice, so a fin touches the rock rather than the lattice
/// box (docs/design/lattice.md, "Colliders").

#include "core/base/result.h"
#include "core/base/types.h"
#include "core/geometry/lattice.h"
#include "core/geometry/mesh.h"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace softtouch {

struct BodyModel;
struct BodyState;
class MeshSurface;

/// The solid shapes a body collides with.
enum class ColliderShape : std::uint8_t { Sphere, Capsule, Box, Mesh };

/// A static solid with the planes' contact response (restitution, Coulomb friction).
struct Collider {
    ColliderShape shape = ColliderShape::Sphere;
    Vec3 centre = Vec3::Zero();                  ///< Centre, metres.
    double radius = 0.5;                         ///< Sphere and capsule radius, metres, > 0.
    Vec3 axis = Vec3::UnitY();                   ///< Capsule: unit direction of its segment.
    double halfLength = 0.5;                     ///< Capsule: half its segment's length (end centres at ±), >= 0.
    Vec3 halfExtents = Vec3::Constant(0.5);      ///< Box: half its edge lengths along `axes`, > 0.
    Mat3 axes = Mat3::Identity();                ///< Box and mesh: orientation (columns unit, orthonormal).
    std::shared_ptr<const MeshSurface> surface;  ///< Mesh: its surface in its own frame, metres: closed, or a
                                                 ///< one-sided sheet (MeshSurface::sides()).
    double scale = 1.0;                          ///< Mesh: uniform scale of that frame, (0, 1e6]; world point =
                                                 ///< centre + axes × scale × mesh point.
    double restitution = 0.0;                    ///< [0, 1]: 1 elastic, 0 sticks.
    double friction = 0.5;                       ///< Coulomb coefficient, [0, 10].
    /// Checks sizes and ranges and normalises the capsule's axis; errors name the field.
    Status validate();
    bool operator==(const Collider&) const = default;
};

/// "sphere", "capsule", "box", "mesh".
const char* colliderShapeName(ColliderShape shape);

/// Radius of a sphere about `collider.centre` that holds the whole collider, metres.
double colliderBoundingRadius(const Collider& collider);

/// Signed distance from `p` to the collider's surface (negative inside), metres, and the outward unit
/// normal of the nearest surface point.
double colliderDistance(const Collider& collider, const Vec3& p, Vec3& normal);

/// The points of a body where collisions are tested, each a material point given by its lattice weights.
struct ContactPoints {
    std::vector<std::uint32_t> start;  ///< Point q's weights are terms[start[q] .. start[q + 1]).
    std::vector<NodeWeight> terms;
    std::size_t size() const { return start.empty() ? 0 : start.size() - 1; }
    /// Point q's value of a per-node field (its position from node positions, its velocity from theirs).
    Vec3 at(std::size_t q, std::span<const Vec3> nodeValues) const {
        Vec3 sum = Vec3::Zero();
        for (std::uint32_t t = start[q]; t < start[q + 1]; ++t)
            sum += terms[t].weight * nodeValues[terms[t].node];
        return sum;
    }
};

/// Surface points of `mesh` for contact: one vertex per occupied cell of a `cells`³ grid over the mesh's
/// bounds (a few hundred for a fish), with their lattice weights.
ContactPoints meshContactPoints(const Lattice& lattice, const Mesh& mesh, int cells = 16);

/// What a contact pass keeps for the next, per collider.
/// - The impulses each contact point ended the last substep with: the next substep starts from them (warm
///   starting), so a body resting on many points settles and sleeps.
/// - Each point's clearance at its last distance query, and where it was: the distance is 1-Lipschitz, so
///   clearance − |x − there| bounds the point's distance from below, and a point that bound keeps outside
///   needs no query (a mesh collider's costs FCL ~10 µs; a resting body asks for hundreds of points in
///   every sweep of every substep). Only queries whose answer would be "outside" are skipped, so the pass
///   does what it would do without the bound (up to rounding at the surface itself).
struct ColliderImpulses {
    std::vector<double> normal;   ///< Per contact point, N·s.
    std::vector<Vec3> friction;   ///< Per contact point, N·s.
    std::vector<double> clearance;  ///< Per contact point: a lower bound of its distance where it was queried.
    std::vector<Vec3> queriedAt;    ///< Per contact point: where that was, metres.
    Collider queriedFor;            ///< The collider those queries were made against (a moved one starts over).
};

/// What one contact pass did.
struct ColliderPass {
    int contacts = 0;          ///< Points found inside a collider.
    double deepest = 0.0;      ///< Largest depth found, metres (before the correction).
};

/// False when no collider can touch the body: the mesh lies in the convex hull of the nodes (the basis is a
/// partition of unity with non-negative values), so a collider whose bounding sphere misses the nodes'
/// bounding box touches nothing. Cheap: one pass over the nodes.
bool collidersMayTouch(const BodyModel& model, std::span<const Collider> colliders, const BodyState& state);

/// Pushes every contact point of `model` that is inside a collider back onto its surface and gives it the
/// planes' velocity response (the normal approach removed, times restitution reflected; friction on the
/// tangential part), each correction spread to the free nodes by their weights and inverse masses as a
/// drag's force is (the point moves by exactly the correction to first order). Four Gauss-Seidel sweeps.
/// Without contact points (no mesh) the free nodes themselves are tested. `restingSpeed`: approach speeds
/// below it do not bounce.
ColliderPass resolveColliders(const BodyModel& model, std::span<const Collider> colliders, BodyState& state,
                              double restingSpeed, std::vector<ColliderImpulses>& impulses);

}  // namespace softtouch
