#pragma once
/// Finds the input-device plugins in a folder (QPluginLoader, by interface) and picks a device:
/// the first connected hardware device, or the null device when nothing is connected.

#include "plugins/input_device_plugin.h"

#include <QList>
#include <QPluginLoader>
#include <QStringList>

namespace softtouch {

/// The loaded plugins of one folder.
class DeviceRegistry {
public:
    /// The build's or the installation's plugin folder: $SOFTTOUCH_PLUGIN_PATH when set, otherwise
    /// <executable folder>/../lib/softtouch/devices.
    static QString defaultFolder();

    /// Loads every library in `folder` that implements InputDevicePlugin; the others are skipped and
    /// listed in problems().
    explicit DeviceRegistry(const QString& folder = defaultFolder());
    ~DeviceRegistry();
    DeviceRegistry(const DeviceRegistry&) = delete;
    DeviceRegistry& operator=(const DeviceRegistry&) = delete;

    /// The plugins found, in file name order.
    const QList<InputDevicePlugin*>& plugins() const { return m_plugins; }
    /// The plugin named `name`, or nullptr.
    InputDevicePlugin* plugin(const QString& name) const;
    /// Files that were not loadable plugins, each with the reason.
    const QStringList& problems() const { return m_problems; }

    /// A device: the plugin `name` (device `index`, `argument`) when given, otherwise the first
    /// hardware plugin with a connected device, otherwise the null device (the null plugin's, or
    /// core's NullDevice when that plugin is missing). `chosen` receives the plugin name used, and
    /// `error` why a named plugin could not open a device (then nullptr is returned).
    std::unique_ptr<InputDevice> open(const QString& name = {}, int index = 0, const QString& argument = {},
                                      QString* chosen = nullptr, QString* error = nullptr) const;

private:
    QList<QPluginLoader*> m_loaders;
    QList<InputDevicePlugin*> m_plugins;
    QStringList m_problems;
};

}  // namespace softtouch
