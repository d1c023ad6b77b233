// The scripted device: replays a trajectory file (docs/formats.md) for tests, demos and CI.
#include "io/documents/trajectory_file.h"
#include "plugins/input_device_plugin.h"

#include <QObject>

namespace softtouch {

class ScriptedDevicePlugin final : public QObject, public InputDevicePlugin {
    Q_OBJECT
    Q_PLUGIN_METADATA(IID SoftTouchInputDevicePlugin_iid)
    Q_INTERFACES(softtouch::InputDevicePlugin)
public:
    QString name() const override { return "scripted"; }
    QString description() const override { return "Replays a trajectory file (*.sttraj)"; }
    unsigned capabilities() const override {
        return unsigned(DeviceCapability::Position3d) | unsigned(DeviceCapability::Buttons) |
               unsigned(DeviceCapability::Pressure) | unsigned(DeviceCapability::Tilt) |
               unsigned(DeviceCapability::ForceFeedback) | unsigned(DeviceCapability::Virtual) |
               unsigned(DeviceCapability::NeedsArgument);
    }
    int deviceCount() override { return 0; }  // needs a file: never "connected"
    std::unique_ptr<InputDevice> createDevice(int, const QString& argument) override {
        if (argument.isEmpty()) {
            m_error = "the scripted device needs a trajectory file (*.sttraj, docs/formats.md)";
            return nullptr;
        }
        auto trajectory = io::loadTrajectory(argument.toStdString());
        if (!trajectory) {
            m_error = QString::fromStdString(trajectory.message());
            return nullptr;
        }
        m_error.clear();
        return std::make_unique<TrajectoryDevice>(std::move(trajectory->samples), std::move(trajectory->device));
    }
    QString errorString() const override { return m_error; }

private:
    QString m_error;
};

}  // namespace softtouch

#include "scripted_plugin.moc"
