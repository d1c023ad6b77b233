// softtouch-cli haptic: the haptic loop headless, on a scene's first object, with any device plugin.
#include "app/cli_commands.h"
#include "app/cli_options.h"
#include "app/cli_support.h"
#include "core/haptics/haptic_session.h"
#include "io/documents/project_file.h"
#include "io/documents/trajectory_file.h"
#include "plugins/device_registry.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <cstring>
#include <thread>

namespace softtouch::cli {
namespace {

constexpr const char* kHapticAbout = R"(Runs the 1 kHz haptic loop (docs/haptics.md) on the first object of SCENE with an input device from
the plugins: grabs a material point at the start and lets the device pull it, then prints the loop's
rate and jitter, the largest force sent and a hash of the final lattice state.
)";

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
    std::optional<double> seconds;
    Vec3 grab(0.5, 1.0, 0.5);
    bool manual = false, identity = false;
    CommandLine line("haptic", kHapticAbout);
    line.positional("SCENE", scenePath, "The project (*.softtouch).");
    line.text("--device", deviceName,
              {"NAME", "Plugin to use: null, scripted, sdl2, openhaptics (default: the first connected device, else null)."});
    line.text("--device-arg", deviceArg, {"ARG", "The device's argument (the scripted device's trajectory file, *.sttraj)."});
    line.text("--plugins", pluginDir,
              {"DIR", "Plugin folder (default: $SOFTTOUCH_PLUGIN_PATH, else <bin>/../lib/softtouch/devices)."});
    line.number("--seconds", seconds, {0, 3600, false, false}, {"S", "How long to run (default 2)."});
    line.value("--grab", [&grab](const std::string& text) {
        Vec3 uvw;
        std::size_t start = 0;
        for (int c = 0; c < 3; ++c) {
            const std::size_t comma = c < 2 ? text.find(',', start) : text.size();
            double value = 0.0;
            if (comma == std::string::npos || !readNumber(text.substr(start, comma - start), {0, 1}, value).empty())
                return "expects U,V,W in [0,1], got '" + text + "'";
            uvw[c] = value;
            start = comma + 1;
        }
        grab = uvw;
        return std::string();
    }, {"U,V,W", "Material point grabbed, lattice parameters in [0,1] (default 0.5,1,0.5)."});
    line.flag("--identity", identity,
              "Use device coordinates as scene coordinates (default: fit the device workspace onto the lattice box).");
    line.flag("--manual", manual, "Run the ticks on the manual clock, as fast as possible and deterministic.");
    line.text("--record", recordPath, {"FILE", "Save every device sample of the session as a trajectory file."});
    if (const auto exit = line.parse(args))
        return *exit;
    const double duration = seconds.value_or(2.0);

    auto project = io::loadProjectToRun(scenePath);
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
    options.recordCapacity = recordPath.empty() ? 0 : std::size_t(duration * HapticSettings{}.rateHz * 1.5) + 1000;
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
        const long long ticks = std::llround(duration * settings.rateHz);
        for (long long t = 0; t < ticks; ++t) {
            loop.tick();
            if (loop.readSnapshot(snapshot)) largest = std::max(largest, snapshot.deviceForce.norm());
        }
    } else {
        loop.start();
        const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(duration);
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
