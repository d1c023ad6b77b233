#pragma once
/// The input-device interface of the haptic loop, Qt-free so a game engine can embed the loop and
/// bring its own devices. Positions and forces are in the device's own frame (metres, newtons); the
/// loop maps them to the scene through a DeviceCalibration. Plugins (plugins/) wrap real devices.

#include "core/base/types.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace softtouch {

/// What a device can do; filled by the device, read by the loop (clamps) and the editor (choice dialog).
struct DeviceInfo {
    std::string name = "none";         ///< Shown to the user ("Null device", "Xbox Controller", …).
    int degreesOfFreedom = 0;          ///< Sensed translational/rotational axes, [0, 6].
    Vec3 workspaceMin = Vec3::Zero();  ///< Lower corner of the reachable box, device frame, metres.
    Vec3 workspaceMax = Vec3::Zero();  ///< Upper corner of the reachable box, device frame, metres.
    double maxForceN = 0.0;            ///< Largest force the device may be sent, newtons, [0, 1e4]; 0 without force feedback.
    double stableStiffnessNPerM = 0.0; ///< Largest stiffness it renders stably at 1 kHz, N/m, [0, 1e6].
    int buttons = 0;                   ///< Number of buttons, [0, 32].
    bool forceFeedback = false;        ///< True when sendForce() reaches an actuator.
};

/// One reading of a device, in the device frame.
struct DeviceSample {
    double time = 0.0;                 ///< Seconds since the loop started (filled by the device from the loop's clock).
    Vec3 position = Vec3::Zero();      ///< Metres, device frame.
    Vec3 velocity = Vec3::Zero();      ///< m/s, device frame.
    std::uint32_t buttons = 0;         ///< Bit i set while button i is held.
    double pressure = 0.0;             ///< Normalised pen or trigger pressure, [0, 1].
    double tiltX = 0.0;                ///< Pen tilt about the device y axis, radians, [-pi/2, pi/2].
    double tiltY = 0.0;                ///< Pen tilt about the device x axis, radians, [-pi/2, pi/2].
};

/// A device the haptic loop reads and, when it has force feedback, drives. read() and sendForce()
/// are called from the loop's thread only, once per tick, and must not block.
class InputDevice {
public:
    virtual ~InputDevice() = default;
    /// Capabilities; constant while the device is open.
    virtual const DeviceInfo& info() const = 0;
    /// The device's state at loop time `seconds` (the loop's clock; a replaying device uses it to pick
    /// its sample, a live one may ignore it).
    virtual DeviceSample read(double seconds) = 0;
    /// Applies a force (device frame, newtons, already clamped to info().maxForceN). Devices without
    /// force feedback ignore it.
    virtual void sendForce(const Vec3& forceN) = 0;
};

/// The device used when nothing is connected: stays at the origin, no buttons, no force feedback.
class NullDevice final : public InputDevice {
public:
    NullDevice();
    const DeviceInfo& info() const override { return m_info; }
    DeviceSample read(double seconds) override;
    void sendForce(const Vec3& forceN) override;

private:
    DeviceInfo m_info;
};

/// A device that replays a trajectory: samples at increasing times, read by time with linear
/// interpolation (exactly the stored sample at its own time; held before the first and after the
/// last). The scripted plugin wraps it around a trajectory file; tests script it directly. Forces
/// sent to it are kept (lastForce(), sentForces()) so tests can check what the loop sent.
class TrajectoryDevice final : public InputDevice {
public:
    /// `samples` must have increasing times; `info` is what the device claims to be.
    TrajectoryDevice(std::vector<DeviceSample> samples, DeviceInfo info);
    const DeviceInfo& info() const override { return m_info; }
    DeviceSample read(double seconds) override;
    void sendForce(const Vec3& forceN) override;

    /// The last force sent, newtons.
    const Vec3& lastForce() const { return m_lastForce; }
    /// Every force sent, in order (kept only when keepForces(true) was called; off by default).
    const std::vector<Vec3>& sentForces() const { return m_sentForces; }
    /// Keeps every sent force (tests); reserves room for `expected` of them.
    void keepForces(bool keep, std::size_t expected = 0);
    /// The stored samples.
    std::span<const DeviceSample> samples() const { return m_samples; }

private:
    std::vector<DeviceSample> m_samples;
    DeviceInfo m_info;
    std::size_t m_cursor = 0;  ///< Search start: reads are mostly in increasing time.
    Vec3 m_lastForce = Vec3::Zero();
    bool m_keepForces = false;
    std::vector<Vec3> m_sentForces;
};

/// A device that returns its samples one per read, in order, whatever the time (the last one is
/// held): replays a loop recording tick for tick, so the replay cannot depend on clock rounding.
class SampleSequenceDevice final : public InputDevice {
public:
    SampleSequenceDevice(std::vector<DeviceSample> samples, DeviceInfo info);
    const DeviceInfo& info() const override { return m_info; }
    DeviceSample read(double seconds) override;
    void sendForce(const Vec3& forceN) override;

private:
    std::vector<DeviceSample> m_samples;
    DeviceInfo m_info;
    std::size_t m_next = 0;
};

/// Default capabilities of a scripted device: 3 DoF, ±0.1 m workspace, 3.3 N, 1,000 N/m (a Touch-class
/// desktop device), 2 buttons, force feedback (the forces are recorded, not felt).
DeviceInfo scriptedDeviceInfo();

}  // namespace softtouch
