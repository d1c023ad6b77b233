// softtouch-cli haptic: the haptic loop headless, on a scene's first object, with any device plugin.
#include "app/cli_commands.h"
#include "app/cli_support.h"
#include "core/haptic_session.h"
#include "io/project_file.h"
#include "io/trajectory_file.h"
#include "plugins/device_registry.h"

#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <cstring>
#include <thread>

namespace softtouch::cli {
namespace {

constexpr const char* kHelp = R"(Usage: softtouch-cli haptic SCENE [options]

Runs the 1 kHz haptic loop (docs/haptics.md) on the first object of SCENE with an input device from
the plugins: grabs a material point at the start and lets the device pull it, then prints the loop's
rate and jitter, the largest force sent and a hash of the final lattice state.
  --device NAME        plugin to use: null, scripted, sdl2, openhaptics (default: the first connected
                       device, else null)
  --device-arg ARG     the device's argument (the scripted device's trajectory file, *.sttraj)
  --plugins DIR        plugin folder (default: $SOFTTOUCH_PLUGIN_PATH, else <bin>/../lib/softtouch/devices)
  --seconds S          how long to run (default 2)
  --grab U,V,W         material point grabbed, lattice parameters in [0,1] (default 0.5,1,0.5)
  --identity           use device coordinates as scene coordinates (default: fit the device
                       workspace onto the lattice box)
  --manual             run the ticks on the manual clock, as fast as possible and deterministic
  --record FILE        save every device sample of the session as a trajectory file
)";

int hapticUsage(const std::string& message) { return usageError(message, "haptic"); }

bool parseDouble(const std::string& text, double& value) {
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc() && end == text.data() + text.size() && std::isfinite(value);
}

/// FNV-1a over the bytes of the positions and velocities: equal hashes mean bit-identical states.
std::uint64_t stateHash(const BodyState& state) {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](const std::vector<Vec3>& values) {
        const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
        for (std::size_t i = 0; i < values.size() * sizeof(Vec3); ++i) h = (h ^ bytes[i]) * 1099511628211ull;
    };
    mix(state.position);
    mix(state.velocity);
    return h;
}

}  // namespace

int runHaptic(const std::vector<std::string>& args) {
    std::string scenePath, deviceName, deviceArg, pluginDir, recordPath;
    double seconds = 2.0;
    Vec3 grab(0.5, 1.0, 0.5);
    bool manual = false, identity = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string* { return i + 1 < args.size() ? &args[++i] : nullptr; };
        if (a == "--help" || a == "-h") {
            std::fputs(kHelp, stdout);
            return 0;
        } else if (a == "--manual") {
            manual = true;
        } else if (a == "--identity") {
            identity = true;
        } else if (a == "--device" || a == "--device-arg" || a == "--plugins" || a == "--record" || a == "--seconds" ||
                   a == "--grab") {
            const std::string* v = value();
            if (!v) return hapticUsage(a + " needs a value");
            if (a == "--device") deviceName = *v;
            else if (a == "--device-arg") deviceArg = *v;
            else if (a == "--plugins") pluginDir = *v;
            else if (a == "--record") recordPath = *v;
            else if (a == "--seconds") {
                if (!parseDouble(*v, seconds) || seconds <= 0.0 || seconds > 3600.0)
                    return hapticUsage("--seconds expects a number in (0, 3600], got '" + *v + "'");
            } else {
                double uvw[3];
                std::size_t start = 0;
                for (int c = 0; c < 3; ++c) {
                    const std::size_t comma = c < 2 ? v->find(',', start) : v->size();
                    if (comma == std::string::npos || !parseDouble(v->substr(start, comma - start), uvw[c]) ||
                        uvw[c] < 0.0 || uvw[c] > 1.0)
                        return hapticUsage("--grab expects U,V,W in [0,1], got '" + *v + "'");
                    start = comma + 1;
                }
                grab = Vec3(uvw[0], uvw[1], uvw[2]);
            }
        } else if (!a.empty() && a[0] == '-') {
            return hapticUsage("unknown option '" + a + "'");
        } else if (scenePath.empty()) {
            scenePath = a;
        } else {
            return hapticUsage("unexpected argument '" + a + "'");
        }
    }
    if (scenePath.empty()) return hapticUsage("haptic needs a SCENE file");

    auto project = io::loadProject(scenePath);
    if (!project) return fail(project.message());
    const SceneObject& object = project->scene.objects.front();

    // A folder that was asked for must exist: silently falling back to the null device hid typos.
    if (!pluginDir.empty() && !std::filesystem::is_directory(pluginDir))
        return fail("--plugins '" + pluginDir + "' is not a folder of device plugins");
    DeviceRegistry registry(pluginDir.empty() ? DeviceRegistry::defaultFolder() : QString::fromStdString(pluginDir));
    QString chosen, error;
    std::unique_ptr<InputDevice> device =
        registry.open(QString::fromStdString(deviceName), 0, QString::fromStdString(deviceArg), &chosen, &error);
    if (!device) return fail(error.toStdString());
    const DeviceInfo info = device->info();

    HapticSessionOptions options;
    options.fitWorkspace = !identity;
    options.recordCapacity = recordPath.empty() ? 0 : std::size_t(seconds * HapticSettings{}.rateHz * 1.5) + 1000;
    auto created = createHapticSession(project->scene, 0, std::move(device), options);
    if (!created) return fail(scenePath + ": " + created.message());
    HapticLoop& loop = *created.value();
    const HapticSettings& settings = loop.settings();

    std::printf("device: %s (plugin %s), %d DoF, max force %.3g N, stable stiffness %.4g N/m%s\n", info.name.c_str(),
                chosen.toStdString().c_str(), info.degreesOfFreedom, info.maxForceN, info.stableStiffnessNPerM,
                info.forceFeedback ? "" : ", no force feedback");
    loop.post(HapticCommand::grab(object.lattice.weights(grab)));
    double largest = 0.0;
    HapticSnapshot snapshot;
    if (manual) {
        const long long ticks = std::llround(seconds * settings.rateHz);
        for (long long t = 0; t < ticks; ++t) {
            loop.tick();
            if (loop.readSnapshot(snapshot)) largest = std::max(largest, snapshot.deviceForce.norm());
        }
    } else {
        loop.start();
        const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (std::chrono::steady_clock::now() < end) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
            if (loop.readSnapshot(snapshot)) largest = std::max(largest, snapshot.deviceForce.norm());
        }
        loop.stop();
        const HapticStats& s = loop.stats();
        std::printf("rate %.1f Hz, period p50 %.3f ms, p99 %.3f ms, max %.3f ms, missed deadlines %lld%s\n", s.rateHz,
                    s.periodP50Ms, s.periodP99Ms, s.periodMaxMs, s.missedDeadlines,
                    s.realtime ? " (SCHED_FIFO)" : "");
    }
    std::printf("ticks %lld, largest force sent %.4f N, passivity controller active on %lld ticks\n",
                loop.tickCount(), largest, loop.passivity().activeTicks());
    std::printf("state hash %016llx\n", static_cast<unsigned long long>(stateHash(loop.simulator().state())));
    if (!recordPath.empty()) {
        io::Trajectory trajectory;
        trajectory.device = info;
        trajectory.samples = loop.recording().samples;
        if (Status s = io::saveTrajectory(recordPath, trajectory); !s) return fail(s.message());
        std::printf("recorded %zu samples to %s%s\n", trajectory.samples.size(), recordPath.c_str(),
                    loop.recording().truncated ? " (truncated: capacity reached)" : "");
    }
    return 0;
}

}  // namespace softtouch::cli
