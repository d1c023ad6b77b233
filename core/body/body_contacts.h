#pragma once
/// Bodies against bodies: two fish that meet push each other apart (docs/design/lattice.md, "Bodies against bodies").
///
/// A body's deformed mesh is its lattice map X applied to its rest mesh, so a world point p lies inside
/// body B exactly when X_B⁻¹(p) lies inside B's rest mesh (while the map does not fold). The pass therefore
/// pulls each contact point of A back into B's rest space (Newton on X_B(u) = p, from an affine fit of B's
/// nodes), asks B's rest surface for the signed distance there (core/geometry/mesh_surface.h, FCL), and maps depth and
/// normal forward through the map's Jacobian. The same in the other direction. Each contact is then resolved
/// between the two material points, A's sample and B's point at p, as a collider contact is, except that both
/// sides move: position corrections and impulses are split by the points' inverse masses Σ w_i² / m_i, so
/// momentum is conserved exactly.

#include "core/base/result.h"
#include "core/base/types.h"
#include "core/geometry/lattice.h"

#include <span>

namespace softtouch {

struct BodyModel;
struct BodyState;
class MeshSurface;

/// Whether and how a scene's objects collide with each other.
struct BodyCollisionSettings {
    bool enabled = false;       ///< Off: objects pass through each other (as before; an eye inside a head).
    double restitution = 0.0;   ///< [0, 1]: 1 elastic, 0 they stay together.
    double friction = 0.3;      ///< Coulomb coefficient between bodies, [0, 10].
    /// Checks ranges; errors name the field.
    Status validate() const;
    bool operator==(const BodyCollisionSettings&) const = default;
};

/// One body as the pass sees it.
struct ContactBody {
    const BodyModel* model = nullptr;
    const Lattice* lattice = nullptr;
    const MeshSurface* restSurface = nullptr;  ///< Its rest mesh; null: the lattice box is the body.
    BodyState* state = nullptr;
};

/// Where world point p lies in a lattice deformed to `nodes`: parameters with X(uvw) = p (Newton, starting
/// from `uvw`), and the map's Jacobian dX/duvw there. False when Newton does not converge.
bool latticeParameters(const Lattice& lattice, std::span<const Vec3> nodes, const Vec3& p, Vec3& uvw, Mat3& jacobian);

/// What one pass did.
struct BodyContactPass {
    int contacts = 0;        ///< Points found inside the other body.
    double deepest = 0.0;    ///< Largest depth found, metres (before the correction).
};

/// False when the two bodies' node bounding boxes are apart (each mesh lies in its nodes' convex hull).
bool bodiesMayTouch(const ContactBody& a, const ContactBody& b);

/// Pushes every contact point of each body that is inside the other back to the surface and removes the
/// approach velocity (restitution, Coulomb friction), both bodies taking their share. `restingSpeed`:
/// approach speeds below it do not bounce.
BodyContactPass resolveBodyContacts(ContactBody& a, ContactBody& b, const BodyCollisionSettings& settings,
                                    double restingSpeed);

}  // namespace softtouch
