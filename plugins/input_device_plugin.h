#pragma once
/// The input-device plugin interface (Qt plugins, found by interface as in Tiled): each plugin
/// declares its name and capabilities, says how many devices of its kind are connected, and opens
/// them as core InputDevice objects that the haptic loop drives. Failures leave a message in
/// errorString(). Plugins are registered with softtouch_add_device_plugin() (cmake/).

#include "core/haptics/input_device.h"

#include <QtPlugin>
#include <QString>

#include <memory>

namespace softtouch {

/// What a plugin's devices can do (before one is opened; DeviceInfo tells the exact figures).
enum class DeviceCapability : unsigned {
    Position3d = 1u << 0,     ///< Senses a 3D position (or integrates one from rate control).
    Buttons = 1u << 1,        ///< Has buttons.
    Pressure = 1u << 2,       ///< Senses pressure.
    Tilt = 1u << 3,           ///< Senses tilt.
    ForceFeedback = 1u << 4,  ///< Renders forces (some of its devices may not).
    Virtual = 1u << 5,        ///< Not hardware (null, scripted): never picked as "the connected device".
    NeedsArgument = 1u << 6,  ///< createDevice() needs an argument (a trajectory file for the scripted device).
};

/// One kind of input device.
class InputDevicePlugin {
public:
    virtual ~InputDevicePlugin() = default;
    /// Stable short name ("null", "scripted", "sdl2", "openhaptics"), used on the command line.
    virtual QString name() const = 0;
    /// A line for the device choice dialog.
    virtual QString description() const = 0;
    /// Bitwise OR of DeviceCapability values.
    virtual unsigned capabilities() const = 0;
    /// Devices of this kind connected now (0 when none, or when the driver is missing).
    virtual int deviceCount() = 0;
    /// Opens device `index` (or, with NeedsArgument, the device described by `argument`). Returns
    /// nullptr on failure and sets errorString().
    virtual std::unique_ptr<InputDevice> createDevice(int index, const QString& argument) = 0;
    /// What went wrong last, for a person: names the device or file and the fix.
    virtual QString errorString() const = 0;
};

}  // namespace softtouch

#define SoftTouchInputDevicePlugin_iid "org.softtouch.InputDevicePlugin/1.0"
Q_DECLARE_INTERFACE(softtouch::InputDevicePlugin, SoftTouchInputDevicePlugin_iid)
