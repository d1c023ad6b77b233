#include "core/haptics/haptic_coupling.h"

#include "core/base/ranges.h"

#include <algorithm>
#include <cmath>

namespace softtouch {

using ranges::finiteIn;

DeviceCalibration DeviceCalibration::fit(const DeviceInfo& device, const Vec3& sceneMin, const Vec3& sceneMax) {
    DeviceCalibration c;
    const Vec3 deviceSize = device.workspaceMax - device.workspaceMin;
    const Vec3 sceneSize = sceneMax - sceneMin;
    double scale = 0.0;
    for (int a = 0; a < 3; ++a)
        if (deviceSize[a] > 0.0) scale = std::max(scale, sceneSize[a] / deviceSize[a]);
    c.scale = scale > 0.0 ? scale : 1.0;
    const Vec3 deviceCentre = 0.5 * (device.workspaceMin + device.workspaceMax);
    c.origin = 0.5 * (sceneMin + sceneMax) - c.scale * deviceCentre;
    return c;
}

Status CouplingSettings::validate() const {
    if (!finiteIn(stiffness, 1e-12, 1e9)) return Status::error("coupling stiffness must be in (0, 1e9] N/m");
    if (!finiteIn(damping, 0.0, 1e6)) return Status::error("coupling damping must be in [0, 1e6] N·s/m");
    if (!finiteIn(avatarMassKg, 1e-9, 100.0)) return Status::error("avatar mass must be in (0, 100] kg");
    if (!finiteIn(contactEpsilon, 0.0, 1.0)) return Status::error("contact epsilon must be in [0, 1] m");
    if (!finiteIn(wallStiffness, 0.0, 1e9)) return Status::error("wall stiffness must be in [0, 1e9] N/m");
    return Status::success();
}

double renderableStiffness(double stiffness, const DeviceInfo& device, const DeviceCalibration& calibration) {
    if (device.stableStiffnessNPerM <= 0.0) return stiffness;
    return std::min(stiffness, device.stableStiffnessNPerM / (calibration.scale * calibration.scale));
}

DragCoupling dragCoupling(const DragSpring& drag, std::span<const Vec3> position, std::span<const Vec3> velocity) {
    DragCoupling c;
    dragPointState(drag, position, velocity, c.point, c.pointVelocity);
    // The paper's drag force on the particle, F = Ks·d + Kd·v (the same expression accumulateForces()
    // applies to the body); the avatar feels the opposite force.
    c.forceOnBody = drag.stiffness * (drag.target - c.point) + drag.damping * (drag.targetVelocity - c.pointVelocity);
    c.reaction = -c.forceOnBody;
    return c;
}

AvatarContact avatarPlaneContact(const CollisionPlane& plane, const Vec3& previous, const Vec3& position,
                                 const Vec3& velocity, const CouplingSettings& settings, double wallStiffness, double h) {
    AvatarContact out;
    out.responseVelocity = velocity;
    out.proxyPosition = position;
    const Vec3& n = plane.normal;
    const double eps = settings.contactEpsilon;
    const double s = (position - plane.point).dot(n);
    const double sBefore = (previous - plane.point).dot(n);
    const double vn = velocity.dot(n);
    // Vn = (N·V)·N, Vt = V − Vn, V' = Vt − Kr·Vn (the paper's response).
    const Vec3 normalVelocity = vn * n;
    const Vec3 tangentVelocity = velocity - normalVelocity;
    if (s > eps) return out;
    const bool arriving = sBefore > eps;
    if (arriving && vn < 0.0) {
        out.kind = ContactCase::Collision;
        out.responseVelocity = tangentVelocity - plane.restitution * normalVelocity;
    } else if (s >= -eps && vn < 0.0) {
        out.kind = ContactCase::Contact;
        out.responseVelocity = tangentVelocity;
    } else if (s < -eps) {
        out.kind = ContactCase::Penetration;
        out.force = wallStiffness * (-s) * n;
    } else {
        return out;  // in the band, moving out: nothing to do
    }
    if (out.kind != ContactCase::Penetration)
        out.force = settings.avatarMassKg * (out.responseVelocity - velocity) / h;
    if (s < 0.0) out.proxyPosition = position - s * n;
    return out;
}

Vec3 PassivityController::apply(const Vec3& force, const Vec3& velocity, double h, double maxForceN, bool control) {
    Vec3 f = force;
    // Energy the environment would hold after this tick: E − F·v·h (F·v > 0 delivers energy to the hand).
    const double wanted = m_energy - f.dot(velocity) * h;
    const double speed2 = velocity.squaredNorm();
    if (control && wanted < 0.0 && speed2 > 0.0) {
        const double alpha = -wanted / (h * speed2);  // N·s/m, makes the energy exactly zero
        f -= alpha * velocity;
        m_dissipated += -wanted;
        ++m_activeTicks;
    }
    if (maxForceN > 0.0) {
        const double norm = f.norm();
        if (norm > maxForceN) {
            f *= maxForceN / norm;  // uniform scaling: never raises the energy delivered this tick
            ++m_clampedTicks;
        }
    }
    m_energy -= f.dot(velocity) * h;
    if (control && m_energy < 0.0 && m_energy > -1e-12) m_energy = 0.0;  // rounding of the exact correction
    return f;
}

}  // namespace softtouch
