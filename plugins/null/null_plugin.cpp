// The null device as a plugin: what the registry opens when nothing is connected.
#include "plugins/input_device_plugin.h"

#include <QObject>

namespace softtouch {

class NullDevicePlugin final : public QObject, public InputDevicePlugin {
    Q_OBJECT
    Q_PLUGIN_METADATA(IID SoftTouchInputDevicePlugin_iid)
    Q_INTERFACES(softtouch::InputDevicePlugin)
public:
    QString name() const override { return "null"; }
    QString description() const override { return "No device: nothing moves, no force"; }
    unsigned capabilities() const override { return unsigned(DeviceCapability::Virtual); }
    int deviceCount() override { return 1; }
    std::unique_ptr<InputDevice> createDevice(int, const QString&) override { return std::make_unique<NullDevice>(); }
    QString errorString() const override { return {}; }
};

}  // namespace softtouch

#include "null_plugin.moc"
