// SDL2 joysticks and gamepads as rate-controlled 3D devices, with SDL_Haptic force effects when the
// pad has them (a constant-force effect, or rumble scaled by the force magnitude) and no force
// feedback otherwise. Builds and loads without a pad: deviceCount() is then 0.
//
// Mapping (gamepad): left stick x → x, left stick y → z, right stick y → y (up), each moving the
// point at up to kSpeed inside the ±kHalfWorkspace box; right trigger → pressure; buttons A, B, X, Y,
// shoulders… → bits 0.. . A raw joystick uses its axes 0, 1 and 3 the same way.
#include "plugins/input_device_plugin.h"

#include <QObject>

#include <SDL.h>

#include <algorithm>
#include <cmath>

namespace softtouch {

namespace {

constexpr double kSpeed = 0.2;           // m/s at full deflection
constexpr double kHalfWorkspace = 0.1;   // m
constexpr double kDeadZone = 0.12;       // fraction of full deflection
constexpr double kNominalForceN = 1.0;   // force rendered as the full effect level
constexpr double kEffectPeriod = 0.01;   // s between effect updates (USB pads take ~100 Hz)

double axis(Sint16 raw) {
    const double v = std::clamp(double(raw) / 32767.0, -1.0, 1.0);
    if (std::abs(v) < kDeadZone) return 0.0;
    return (v - std::copysign(kDeadZone, v)) / (1.0 - kDeadZone);
}

bool initSdl() {
    static const bool ok = [] {
        SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");
        SDL_SetHint(SDL_HINT_JOYSTICK_ALLOW_BACKGROUND_EVENTS, "1");
        return SDL_InitSubSystem(SDL_INIT_JOYSTICK | SDL_INIT_GAMECONTROLLER) == 0;
    }();
    return ok;
}

class Sdl2Device final : public InputDevice {
public:
    Sdl2Device(SDL_GameController* pad, SDL_Joystick* joystick) : m_pad(pad), m_joystick(joystick) {
        m_info.name = SDL_JoystickName(joystick) ? SDL_JoystickName(joystick) : "SDL2 joystick";
        m_info.degreesOfFreedom = 3;
        m_info.workspaceMin = Vec3::Constant(-kHalfWorkspace);
        m_info.workspaceMax = Vec3::Constant(kHalfWorkspace);
        m_info.buttons = pad ? int(SDL_CONTROLLER_BUTTON_MAX) : std::min(32, SDL_JoystickNumButtons(joystick));
        // Haptics are optional: without the subsystem or an actuator the pad has no force feedback.
        if (SDL_WasInit(SDL_INIT_HAPTIC) || SDL_InitSubSystem(SDL_INIT_HAPTIC) == 0) {
            m_haptic = SDL_HapticOpenFromJoystick(joystick);
            if (m_haptic) {
                if (SDL_HapticQuery(m_haptic) & SDL_HAPTIC_CONSTANT) {
                    SDL_HapticEffect effect{};
                    effect.type = SDL_HAPTIC_CONSTANT;
                    effect.constant.direction.type = SDL_HAPTIC_CARTESIAN;
                    effect.constant.length = SDL_HAPTIC_INFINITY;
                    m_effect = SDL_HapticNewEffect(m_haptic, &effect);
                    if (m_effect >= 0) SDL_HapticRunEffect(m_haptic, m_effect, 1);
                }
                if (m_effect < 0 && SDL_HapticRumbleSupported(m_haptic) == SDL_TRUE && SDL_HapticRumbleInit(m_haptic) == 0)
                    m_rumble = true;
            }
        }
        m_info.forceFeedback = m_effect >= 0 || m_rumble;
        m_info.maxForceN = m_info.forceFeedback ? kNominalForceN : 0.0;
        // A rate-controlled pad renders no stiffness the hand could destabilise; this keeps the
        // rendered coupling soft enough that the effect does not saturate on small pulls.
        m_info.stableStiffnessNPerM = m_info.forceFeedback ? 100.0 : 0.0;
    }
    ~Sdl2Device() override {
        if (m_haptic) SDL_HapticClose(m_haptic);
        if (m_pad) SDL_GameControllerClose(m_pad);
        else SDL_JoystickClose(m_joystick);
    }
    const DeviceInfo& info() const override { return m_info; }

    DeviceSample read(double seconds) override {
        SDL_JoystickUpdate();
        Vec3 rate = Vec3::Zero();
        DeviceSample s;
        s.time = seconds;
        if (m_pad) {
            rate = Vec3(axis(SDL_GameControllerGetAxis(m_pad, SDL_CONTROLLER_AXIS_LEFTX)),
                        -axis(SDL_GameControllerGetAxis(m_pad, SDL_CONTROLLER_AXIS_RIGHTY)),
                        axis(SDL_GameControllerGetAxis(m_pad, SDL_CONTROLLER_AXIS_LEFTY)));
            s.pressure = std::clamp(SDL_GameControllerGetAxis(m_pad, SDL_CONTROLLER_AXIS_TRIGGERRIGHT) / 32767.0, 0.0, 1.0);
            for (int b = 0; b < SDL_CONTROLLER_BUTTON_MAX && b < 32; ++b)
                if (SDL_GameControllerGetButton(m_pad, SDL_GameControllerButton(b))) s.buttons |= 1u << b;
        } else {
            const int axes = SDL_JoystickNumAxes(m_joystick);
            auto get = [&](int a) { return a < axes ? axis(SDL_JoystickGetAxis(m_joystick, a)) : 0.0; };
            rate = Vec3(get(0), -get(3), get(1));
            for (int b = 0; b < m_info.buttons; ++b)
                if (SDL_JoystickGetButton(m_joystick, b)) s.buttons |= 1u << b;
        }
        const double dt = m_haveTime ? std::clamp(seconds - m_lastTime, 0.0, 0.1) : 0.0;
        m_lastTime = seconds;
        m_haveTime = true;
        const Vec3 before = m_position;
        m_position = (m_position + kSpeed * dt * rate).cwiseMax(m_info.workspaceMin).cwiseMin(m_info.workspaceMax);
        s.position = m_position;
        s.velocity = dt > 0.0 ? Vec3((m_position - before) / dt) : Vec3::Zero();
        return s;
    }

    void sendForce(const Vec3& force) override {
        if (!m_info.forceFeedback || m_lastTime - m_lastEffect < kEffectPeriod) return;
        m_lastEffect = m_lastTime;
        const double level = std::clamp(force.norm() / kNominalForceN, 0.0, 1.0);
        if (m_effect >= 0) {
            SDL_HapticEffect effect{};
            effect.type = SDL_HAPTIC_CONSTANT;
            effect.constant.direction.type = SDL_HAPTIC_CARTESIAN;
            const Vec3 d = force.norm() > 0.0 ? Vec3(force.normalized() * 10000.0) : Vec3::Zero();
            effect.constant.direction.dir[0] = Sint32(d.x());
            effect.constant.direction.dir[1] = Sint32(d.z());
            effect.constant.direction.dir[2] = Sint32(d.y());
            effect.constant.length = SDL_HAPTIC_INFINITY;
            effect.constant.level = Sint16(level * 32767.0);
            SDL_HapticUpdateEffect(m_haptic, m_effect, &effect);
        } else if (m_rumble) {
            if (level > 0.01) SDL_HapticRumblePlay(m_haptic, float(level), Uint32(2000 * kEffectPeriod));
            else SDL_HapticRumbleStop(m_haptic);
        }
    }

private:
    SDL_GameController* m_pad = nullptr;
    SDL_Joystick* m_joystick = nullptr;
    SDL_Haptic* m_haptic = nullptr;
    int m_effect = -1;
    bool m_rumble = false;
    DeviceInfo m_info;
    Vec3 m_position = Vec3::Zero();
    double m_lastTime = 0.0;
    double m_lastEffect = -1.0;
    bool m_haveTime = false;
};

}  // namespace

class Sdl2DevicePlugin final : public QObject, public InputDevicePlugin {
    Q_OBJECT
    Q_PLUGIN_METADATA(IID SoftTouchInputDevicePlugin_iid)
    Q_INTERFACES(softtouch::InputDevicePlugin)
public:
    QString name() const override { return "sdl2"; }
    QString description() const override { return "Joystick or gamepad (SDL2), with force effects when the pad has them"; }
    unsigned capabilities() const override {
        return unsigned(DeviceCapability::Position3d) | unsigned(DeviceCapability::Buttons) |
               unsigned(DeviceCapability::Pressure) | unsigned(DeviceCapability::ForceFeedback);
    }
    int deviceCount() override { return initSdl() ? std::max(0, SDL_NumJoysticks()) : 0; }
    std::unique_ptr<InputDevice> createDevice(int index, const QString&) override {
        if (!initSdl()) {
            m_error = QString("SDL2 joystick subsystem: %1").arg(SDL_GetError());
            return nullptr;
        }
        if (index < 0 || index >= SDL_NumJoysticks()) {
            m_error = QString("no joystick or gamepad %1 (SDL2 sees %2)").arg(index).arg(SDL_NumJoysticks());
            return nullptr;
        }
        SDL_GameController* pad = SDL_IsGameController(index) ? SDL_GameControllerOpen(index) : nullptr;
        SDL_Joystick* joystick = pad ? SDL_GameControllerGetJoystick(pad) : SDL_JoystickOpen(index);
        if (!joystick) {
            m_error = QString("cannot open joystick %1: %2").arg(index).arg(SDL_GetError());
            return nullptr;
        }
        m_error.clear();
        return std::make_unique<Sdl2Device>(pad, joystick);
    }
    QString errorString() const override { return m_error; }

private:
    QString m_error;
};

}  // namespace softtouch

#include "sdl2_plugin.moc"
