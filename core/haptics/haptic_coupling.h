#pragma once
/// What the hand feels: the reaction of the paper's drag spring, the paper's point-to-plane contact
/// model applied to the avatar, the mapping between the device's frame and the scene, and the
/// passivity controller that keeps the rendered environment from ever adding energy.

#include "core/body/forces.h"
#include "core/haptics/input_device.h"

#include <span>

namespace softtouch {

/// Device frame to scene: p_scene = origin + scale · R · p_device. Forces go back with the transpose
/// and the same scale, F_device = scale · Rᵀ · F_scene, so power is the same in both frames
/// (F_device · v_device = F_scene · v_scene) and passivity measured on the device holds in the scene.
struct DeviceCalibration {
    Vec3 origin = Vec3::Zero();     ///< Scene point of the device origin, metres.
    Mat3 rotation = Mat3::Identity(); ///< Device axes in the scene, orthonormal.
    double scale = 1.0;             ///< Scene metres per device metre, (0, 1e6].

    /// A device position in the scene, metres.
    Vec3 positionToScene(const Vec3& p) const { return origin + scale * (rotation * p); }
    /// A device velocity in the scene, m/s.
    Vec3 velocityToScene(const Vec3& v) const { return scale * (rotation * v); }
    /// A scene force as the device must render it, newtons.
    Vec3 forceToDevice(const Vec3& f) const { return scale * (rotation.transpose() * f); }
    /// Fits the device workspace box onto a scene box (uniform scale, centres matched, no rotation).
    static DeviceCalibration fit(const DeviceInfo& device, const Vec3& sceneMin, const Vec3& sceneMax);
};

/// Settings of the coupling between the avatar (the device point in the scene) and the body.
struct CouplingSettings {
    double stiffness = 50.0;       ///< Ks of the drag spring, N/m (scene), (0, 1e9]. Capped by the device's
                                   ///< stable stiffness (see renderableStiffness()).
    double damping = 1.0;          ///< Kd of the drag spring, N·s/m (scene), [0, 1e6].
    double avatarMassKg = 0.05;    ///< Effective mass of hand plus handle, kg, (0, 100]: turns the contact
                                   ///< model's velocity response into the force that produces it in one tick.
    double contactEpsilon = 1e-3;  ///< ε of the point-to-plane model, metres (scene), [0, 1].
    double wallStiffness = 1e9;    ///< Penalty stiffness against penetration, N/m (scene), [0, 1e9]; capped
                                   ///< like Ks by the device's stable stiffness.
    bool passivityControl = true;  ///< Passivity observer + controller (Hannaford & Ryu 2002). Off only for studies.
    /// Checks every field against its range.
    Status validate() const;
};

/// The largest scene stiffness a device renders stably through a calibration: a scene spring k is
/// felt as k · scale² on the device, so k ≤ stableStiffnessNPerM / scale². Devices that report no
/// stable stiffness (0) leave k as it is (they render no force anyway).
double renderableStiffness(double stiffness, const DeviceInfo& device, const DeviceCalibration& calibration);

/// The drag spring between the avatar and the grabbed material point, evaluated on a body state.
struct DragCoupling {
    Vec3 point = Vec3::Zero();          ///< Material point position, metres.
    Vec3 pointVelocity = Vec3::Zero();  ///< Its velocity, m/s.
    Vec3 forceOnBody = Vec3::Zero();    ///< Ks·d + Kd·v with d = avatar − point, v = avatar velocity − point velocity, N.
    Vec3 reaction = Vec3::Zero();       ///< What the avatar feels: −forceOnBody, N.
};

/// The paper's drag coupling F = Ks·d + Kd·v on a state (dragPointState() finds the point).
DragCoupling dragCoupling(const DragSpring& drag, std::span<const Vec3> position, std::span<const Vec3> velocity);

/// Cases of the paper's point-to-plane model, for a point at signed distance s = (U − P)·N moving
/// with normal velocity Vn = N·V.
enum class ContactCase : std::uint8_t {
    None,        ///< s > ε, or inside the band moving away.
    Collision,   ///< Arrived this tick (was beyond ε) moving in: V' = Vt − Kr·Vn.
    Contact,     ///< Already touching (|s| ≤ ε) and moving in: resting contact, V' = Vt (Kr = 0, as for the body).
    Penetration, ///< s < −ε and not arriving: the paper steps back; a hand cannot be stepped back, so the
                 ///< avatar is shown on the plane and a penalty spring pushes the hand out.
};

/// The avatar's answer to one plane.
struct AvatarContact {
    ContactCase kind = ContactCase::None; ///< Which case applied.
    Vec3 responseVelocity = Vec3::Zero(); ///< V' the model asks for, m/s (V when nothing applies).
    Vec3 proxyPosition = Vec3::Zero();    ///< Where the avatar is shown: on the plane when behind it, metres.
    Vec3 force = Vec3::Zero();            ///< Force on the hand, N: m·(V' − V)/h for collision and contact,
                                          ///< wall stiffness × depth along N for penetration.
};

/// The paper's point-to-plane model for the avatar: `previous` is its position one tick (h seconds)
/// ago, `position` and `velocity` its state now; `wallStiffness` is already capped for the device.
AvatarContact avatarPlaneContact(const CollisionPlane& plane, const Vec3& previous, const Vec3& position,
                                 const Vec3& velocity, const CouplingSettings& settings, double wallStiffness, double h);

/// Passivity observer and controller (Hannaford & Ryu, "Time-domain passivity control of haptic
/// interfaces", IEEE Trans. Robotics and Automation 18(1), 2002), on the device port.
///
/// Why this and not a fixed virtual-coupling damping bound (Colgate, Stanley & Brown 1995): the
/// bound needs a model of the device's own damping and of the environment, and either makes every
/// contact feel mushy or is not guaranteed when the body, Ks or the planes change at run time. The
/// observer needs nothing but the force sent and the device velocity: the energy the environment has
/// absorbed from the hand, E(n) = −Σ F(k)·v(k)·h, must never go below zero (a passive environment
/// cannot return more than it was given). When a tick would make it negative, the controller adds
/// the one-tick damping α = −E/(h|v|²) along −v that brings it back to exactly zero; it does nothing
/// while E ≥ 0, so a passive coupling is rendered untouched. The clamp to the device's maximum force
/// scales the force down uniformly, which can only lower the energy a tick delivers, so E ≥ 0 holds
/// after clamping too.
class PassivityController {
public:
    /// The force to send for a wanted `force` at device velocity `velocity` (device frame), with the
    /// clamp |F| ≤ maxForceN (≤ 0: no clamp). Updates the observed energy with the force returned.
    Vec3 apply(const Vec3& force, const Vec3& velocity, double h, double maxForceN, bool control = true);
    /// Energy absorbed by the environment so far, joules (≥ 0 under control).
    double energy() const { return m_energy; }
    /// Energy the controller has dissipated so far, joules.
    double dissipated() const { return m_dissipated; }
    /// Ticks on which the controller acted.
    long long activeTicks() const { return m_activeTicks; }
    /// Ticks on which the force was clamped to the device maximum.
    long long clampedTicks() const { return m_clampedTicks; }
    /// Forgets the history (a new grab, a new session).
    void reset() { *this = PassivityController(); }

private:
    double m_energy = 0.0;
    double m_dissipated = 0.0;
    long long m_activeTicks = 0;
    long long m_clampedTicks = 0;
};

}  // namespace softtouch
