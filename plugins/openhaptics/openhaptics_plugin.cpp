// 3D Systems Touch / Phantom devices through the OpenHaptics HD API. Built only when the SDK is found
// (plugins/openhaptics/CMakeLists.txt, docs/haptics.md); not compiled on machines without it.
//
// OpenHaptics owns the servo loop (hdStartScheduler, 1 kHz): device state may only be touched inside
// its frames. A scheduler callback copies the state out through a seqlock and applies the latest force
// the SoftTouch loop stored in atomics, so neither thread ever waits for the other.
#include "plugins/input_device_plugin.h"

#include <QObject>

#include <HD/hd.h>

#include <atomic>

namespace softtouch {

namespace {

QString hdErrorText(const HDErrorInfo& error) {
    return QString("%1 (OpenHaptics error %2, internal %3)")
        .arg(QString::fromLatin1(hdGetErrorString(error.errorCode)))
        .arg(error.errorCode)
        .arg(error.internalErrorCode);
}

class OpenHapticsDevice final : public InputDevice {
public:
    explicit OpenHapticsDevice(HHD handle) : m_handle(handle) {
        hdMakeCurrentDevice(m_handle);
        m_info.name = QString("%1 (OpenHaptics)").arg(QString::fromLatin1(hdGetString(HD_DEVICE_MODEL_TYPE))).toStdString();
        m_info.degreesOfFreedom = 6;
        HDdouble workspace[6] = {};
        hdGetDoublev(HD_USABLE_WORKSPACE_DIMENSIONS, workspace);  // mm: min x y z, max x y z
        m_info.workspaceMin = Vec3(workspace[0], workspace[1], workspace[2]) * 1e-3;
        m_info.workspaceMax = Vec3(workspace[3], workspace[4], workspace[5]) * 1e-3;
        HDdouble force = 0.0, stiffness = 0.0;
        hdGetDoublev(HD_NOMINAL_MAX_CONTINUOUS_FORCE, &force);  // N
        hdGetDoublev(HD_NOMINAL_MAX_STIFFNESS, &stiffness);     // N/mm
        m_info.maxForceN = force;
        m_info.stableStiffnessNPerM = stiffness * 1e3;
        m_info.buttons = 2;
        m_info.forceFeedback = true;
        hdEnable(HD_FORCE_OUTPUT);
        m_callback = hdScheduleAsynchronous(&OpenHapticsDevice::servo, this, HD_MAX_SCHEDULER_PRIORITY);
        hdStartScheduler();
    }
    ~OpenHapticsDevice() override {
        hdStopScheduler();
        hdUnschedule(m_callback);
        hdDisableDevice(m_handle);
    }
    const DeviceInfo& info() const override { return m_info; }

    DeviceSample read(double seconds) override {
        DeviceSample s;
        unsigned before = 0;
        do {  // seqlock read: retry while the servo thread is writing
            before = m_sequence.load(std::memory_order_acquire);
            s.position = Vec3(m_position[0].load(std::memory_order_relaxed), m_position[1].load(std::memory_order_relaxed),
                              m_position[2].load(std::memory_order_relaxed));
            s.velocity = Vec3(m_velocity[0].load(std::memory_order_relaxed), m_velocity[1].load(std::memory_order_relaxed),
                              m_velocity[2].load(std::memory_order_relaxed));
            s.buttons = m_buttons.load(std::memory_order_relaxed);
            std::atomic_thread_fence(std::memory_order_acquire);
        } while ((before & 1u) || before != m_sequence.load(std::memory_order_relaxed));
        s.time = seconds;
        return s;
    }
    void sendForce(const Vec3& force) override {
        for (int a = 0; a < 3; ++a) m_force[a].store(force[a], std::memory_order_relaxed);
    }

private:
    static HDCallbackCode HDCALLBACK servo(void* data) {
        auto* self = static_cast<OpenHapticsDevice*>(data);
        hdBeginFrame(self->m_handle);
        HDdouble p[3], v[3];
        HDint buttons = 0;
        hdGetDoublev(HD_CURRENT_POSITION, p);  // mm
        hdGetDoublev(HD_CURRENT_VELOCITY, v);  // mm/s
        hdGetIntegerv(HD_CURRENT_BUTTONS, &buttons);
        const HDdouble f[3] = {self->m_force[0].load(std::memory_order_relaxed),
                               self->m_force[1].load(std::memory_order_relaxed),
                               self->m_force[2].load(std::memory_order_relaxed)};
        hdSetDoublev(HD_CURRENT_FORCE, f);
        hdEndFrame(self->m_handle);
        self->m_sequence.fetch_add(1, std::memory_order_acq_rel);  // odd: writing
        for (int a = 0; a < 3; ++a) {
            self->m_position[a].store(p[a] * 1e-3, std::memory_order_relaxed);
            self->m_velocity[a].store(v[a] * 1e-3, std::memory_order_relaxed);
        }
        self->m_buttons.store(std::uint32_t(buttons), std::memory_order_relaxed);
        self->m_sequence.fetch_add(1, std::memory_order_release);  // even: done
        return HD_DEVICE_ERROR(hdGetError()) ? HD_CALLBACK_DONE : HD_CALLBACK_CONTINUE;
    }

    HHD m_handle;
    HDSchedulerHandle m_callback = 0;
    DeviceInfo m_info;
    std::atomic<unsigned> m_sequence{0};
    std::atomic<double> m_position[3] = {0.0, 0.0, 0.0};
    std::atomic<double> m_velocity[3] = {0.0, 0.0, 0.0};
    std::atomic<std::uint32_t> m_buttons{0};
    std::atomic<double> m_force[3] = {0.0, 0.0, 0.0};
};

}  // namespace

class OpenHapticsDevicePlugin final : public QObject, public InputDevicePlugin {
    Q_OBJECT
    Q_PLUGIN_METADATA(IID SoftTouchInputDevicePlugin_iid)
    Q_INTERFACES(softtouch::InputDevicePlugin)
public:
    QString name() const override { return "openhaptics"; }
    QString description() const override { return "3D Systems Touch / Phantom (OpenHaptics)"; }
    unsigned capabilities() const override {
        return unsigned(DeviceCapability::Position3d) | unsigned(DeviceCapability::Buttons) |
               unsigned(DeviceCapability::ForceFeedback);
    }
    int deviceCount() override {
        // OpenHaptics has no enumeration: the default device is there if it initialises.
        const HHD handle = hdInitDevice(HD_DEFAULT_DEVICE);
        if (HD_DEVICE_ERROR(hdGetError())) return 0;
        hdDisableDevice(handle);
        return 1;
    }
    std::unique_ptr<InputDevice> createDevice(int index, const QString& argument) override {
        if (index != 0) {
            m_error = "OpenHaptics: only the default device (index 0) is supported";
            return nullptr;
        }
        // The argument, when given, names a device configuration from Touch Setup.
        const QByteArray config = argument.toLocal8Bit();
        const HHD handle = hdInitDevice(argument.isEmpty() ? HD_DEFAULT_DEVICE : config.constData());
        const HDErrorInfo error = hdGetError();
        if (HD_DEVICE_ERROR(error)) {
            m_error = "OpenHaptics: cannot initialise the device: " + hdErrorText(error) +
                      "; is it connected and configured in Touch Setup?";
            return nullptr;
        }
        m_error.clear();
        return std::make_unique<OpenHapticsDevice>(handle);
    }
    QString errorString() const override { return m_error; }

private:
    QString m_error;
};

}  // namespace softtouch

#include "openhaptics_plugin.moc"
