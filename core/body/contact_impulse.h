#pragma once
/// The velocity rule the impulse-based contacts share (core/body/colliders: a body against a static solid;
/// core/body/body_contacts: two bodies): sequential impulses with accumulated, clamped impulses (E. Catto,
/// "Iterative Dynamics with Temporal Coherence", GDC 2005). A normal impulse that only pushes in total, so
/// a later sweep can take back what an earlier one overdid, and Coulomb friction bounded by μ times it.

#include "core/base/types.h"

#include <algorithm>

namespace softtouch {

/// Gauss-Seidel sweeps over the contacts per velocity pass: contacts share nodes, so one contact's
/// correction moves its neighbours, and a resting body needs a few rounds to settle them all.
inline constexpr int kContactSweeps = 4;

/// One contact's impulses as the sweeps accumulate them.
struct ContactImpulse {
    Vec3 normal = Vec3::UnitY();          ///< Unit: the way the contact pushes.
    double inverseMass = 0.0;             ///< How the contact's relative velocity answers an impulse on it
                                          ///< (Σ w² m⁻¹ over its sides), > 0.
    double target = 0.0;                  ///< Normal velocity the contact ends with (restitution), m/s.
    double normalImpulse = 0.0;           ///< Accumulated, >= 0, N·s.
    Vec3 frictionImpulse = Vec3::Zero();  ///< Accumulated, |.| <= friction × normalImpulse, N·s.
};

/// The normal velocity a contact found approaching at `vn` (< 0: approaching) leaves with: restitution
/// reflects it, except below `restingSpeed`, where a bounce would only jitter a body at rest.
inline double contactTargetSpeed(double vn, double restingSpeed, double restitution) {
    const double bounce = -vn < restingSpeed ? 0.0 : restitution;
    return vn < 0.0 ? -bounce * vn : 0.0;
}

/// One sweep's update of `c` at the contact's current (relative) velocity: accumulates and clamps its
/// impulses and returns the impulse to apply now (changing that velocity by inverseMass times it).
inline Vec3 sequentialImpulse(ContactImpulse& c, const Vec3& velocity, double friction) {
    const double vn = velocity.dot(c.normal);
    const double accumulated = std::max(0.0, c.normalImpulse + (c.target - vn) / c.inverseMass);
    const double normalChange = accumulated - c.normalImpulse;
    c.normalImpulse = accumulated;
    const Vec3 tangent = velocity - vn * c.normal;
    Vec3 frictionImpulse = c.frictionImpulse - tangent / c.inverseMass;
    const double limit = friction * c.normalImpulse;
    if (frictionImpulse.norm() > limit)
        frictionImpulse *= limit / frictionImpulse.norm();
    const Vec3 frictionChange = frictionImpulse - c.frictionImpulse;
    c.frictionImpulse = frictionImpulse;
    return normalChange * c.normal + frictionChange;
}

}  // namespace softtouch
