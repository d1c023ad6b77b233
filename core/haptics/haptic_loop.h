#pragma once
/// The haptic loop: a thread at 1 kHz that reads the device, steps the lattice body at the haptic
/// rate, computes the force the hand feels and sends it. The mesh never enters the loop (the body is
/// the lattice's few nodes), so its rate does not depend on the mesh.
///
///   UI thread ──post(command)──▶ [SPSC ring] ──▶ loop thread: tick()
///   UI thread ◀──readSnapshot()── [triple buffer] ◀── publish at the end of every tick
///
/// No mutex anywhere in the loop: commands arrive through a single-producer/single-consumer ring of
/// atomics (core/base/spsc_ring.h), results leave through a triple buffer (core/base/triple_buffer.h) whose
/// buffers are sized once at construction.
/// A manual clock mode runs the same tick() synchronously, without the thread, for tests and replays.

#include "core/base/spsc_ring.h"
#include "core/base/triple_buffer.h"
#include "core/haptics/haptic_coupling.h"
#include "core/solver/simulator.h"

#include <array>
#include <atomic>
#include <chrono>
#include <memory>
#include <thread>
#include <vector>

namespace softtouch {

/// Largest support of a grabbed material point: a degree-7 Bezier lattice (8 nodes per axis) has 8³.
inline constexpr std::size_t kMaxGrabSupport = 512;

/// A command from the UI to the loop. Fixed size, so the ring never allocates.
struct HapticCommand {
    /// What to do.
    enum class Kind : std::uint8_t {
        Grab,         ///< Tie the avatar to the material point `support` (replaces any grab).
        Release,      ///< Let go.
        SetStiffness, ///< Ks = value, N/m (capped by the device's stable stiffness).
        SetDamping,   ///< Kd = value, N·s/m.
    };
    Kind kind = Kind::Release;                          ///< What to do.
    std::array<NodeWeight, kMaxGrabSupport> support{};  ///< Grab: weights of the material point (Lattice::weights()).
    std::uint32_t supportSize = 0;                      ///< Grab: used entries of `support`, [1, kMaxGrabSupport].
    double value = 0.0;                                 ///< SetStiffness / SetDamping: the new value.

    /// A grab of the point with these weights (at most kMaxGrabSupport are kept).
    static HapticCommand grab(std::span<const NodeWeight> weights);
    /// A release.
    static HapticCommand release();
    /// A new Ks, N/m.
    static HapticCommand setStiffness(double stiffnessNPerM);
    /// A new Kd, N·s/m.
    static HapticCommand setDamping(double dampingNsPerM);
};

/// Settings of a loop.
struct HapticSettings {
    double rateHz = 1000.0;            ///< Ticks per second; the body steps 1/rateHz per tick. [1, 20000].
    CouplingSettings coupling;         ///< Drag spring, contact model, passivity.
    DeviceCalibration calibration;     ///< Device frame to scene.
    int statsWindow = 1000;            ///< Ticks in the sliding window of the rate/jitter figures, [10, 1e6].
    std::size_t recordCapacity = 0;    ///< Ticks to record (samples reserved up front); 0 records nothing.
    std::size_t commandCapacity = 256; ///< Commands kept in a recording, reserved up front.
    int realtimePriority = 0;          ///< 0: normal scheduling. 1..99: ask for SCHED_FIFO at this priority
                                       ///< (Linux; needs CAP_SYS_NICE or an rtprio limit, else ignored and
                                       ///< HapticStats::realtime stays false). [0, 99].
    /// Checks every field against its range.
    Status validate() const;
};

/// Rate and period jitter of the loop over its sliding window (threaded mode only; zero in manual mode).
struct HapticStats {
    long long ticks = 0;            ///< Ticks run since start.
    long long missedDeadlines = 0;  ///< Deadlines skipped because a tick ran past the next one.
    double rateHz = 0.0;            ///< Achieved ticks per second over the window.
    double periodP50Ms = 0.0;       ///< Median wake-to-wake period over the window, ms.
    double periodP99Ms = 0.0;       ///< 99th percentile period, ms.
    double periodMaxMs = 0.0;       ///< Longest period, ms.
    double tickP99Us = 0.0;         ///< 99th percentile of the work inside a tick (read, step, force), µs.
    double passiveEnergyJ = 0.0;    ///< The passivity observer's energy (≥ 0), joules.
    long long passivityActiveTicks = 0; ///< Ticks on which the passivity controller added damping.
    long long clampedTicks = 0;     ///< Ticks whose force was clamped to the device maximum.
    bool realtime = false;          ///< The thread runs under real-time scheduling (realtimePriority granted).
};

/// What the UI reads: the body and the coupling after one tick.
struct HapticSnapshot {
    long long tick = 0;                  ///< Ticks run when it was published.
    double time = 0.0;                   ///< Loop time, seconds.
    std::vector<Vec3> positions;         ///< Node positions, metres (sized once: the model's node count).
    DeviceSample sample;                 ///< The device reading of that tick (device frame).
    Vec3 avatar = Vec3::Zero();          ///< Device point in the scene, metres.
    Vec3 avatarShown = Vec3::Zero();     ///< Avatar held on the free side of the planes, metres.
    bool grabbed = false;                ///< A point is held.
    Vec3 grabPoint = Vec3::Zero();       ///< The held material point, metres.
    Vec3 forceOnBody = Vec3::Zero();     ///< Drag force on the body, N (scene).
    Vec3 deviceForce = Vec3::Zero();     ///< Force sent to the device, N (device frame).
    double stiffness = 0.0;              ///< Ks in use (after the device cap), N/m.
    HapticStats stats;                   ///< Rate and jitter.
};

/// A command as applied, with the tick it was applied on (relative to the recording's start).
struct RecordedCommand {
    long long tick = 0;        ///< Applied at the start of this tick.
    HapticCommand command;     ///< What was applied.
};

/// A loop session: every device sample at the full loop rate plus the commands, from a start state.
/// Replayed through a loop in manual mode (replayRecording()) it reproduces the body bit for bit.
struct HapticRecording {
    double rateHz = 1000.0;               ///< Loop rate it was recorded at.
    BodyState initialState;               ///< Body state before the first recorded tick.
    long long initialStep = 0;            ///< Simulator step count then.
    std::vector<DeviceSample> samples;    ///< One per tick.
    std::vector<RecordedCommand> commands; ///< In tick order.
    bool truncated = false;               ///< The capacity ran out; later ticks were not recorded.
};

/// A 1 kHz haptic loop around one body and one device.
class HapticLoop {
public:
    /// Builds the loop's own Simulator (dt = 1/rateHz) over `model`; `world` holds gravity and planes
    /// (its drags are ignored; the grab is the loop's). Errors name the bad setting.
    static Result<std::unique_ptr<HapticLoop>> create(std::shared_ptr<const BodyModel> model,
                                                      const SimulationSettings& simulation, const ExternalForces& world,
                                                      std::unique_ptr<InputDevice> device,
                                                      const HapticSettings& settings);
    ~HapticLoop();  ///< Stops the thread if it runs.
    HapticLoop(const HapticLoop&) = delete;
    HapticLoop& operator=(const HapticLoop&) = delete;

    /// Starts the thread (deadline scheduling on steady_clock). False when already running.
    bool start();
    /// Stops and joins the thread; the loop can then be read directly or ticked manually.
    void stop();
    /// True while the thread runs.
    bool isRunning() const { return m_thread.joinable(); }

    /// Manual clock: runs one tick now at loop time tickCount()/rateHz, on the caller's thread.
    /// Only while the thread is not running. Same code as the thread's ticks.
    void tick();
    /// Runs `count` manual ticks.
    void tickFor(long long count);

    /// Queues a command for the next tick (single producer: call from one thread). False when full.
    bool post(const HapticCommand& command);

    /// Copies the latest published snapshot into `out` if a newer one exists (single consumer: call
    /// from one thread). Returns true when `out` changed. Never blocks the loop.
    bool readSnapshot(HapticSnapshot& out);

    /// Ticks run so far (read it only while the thread is not running; snapshots carry it otherwise).
    long long tickCount() const { return m_tick; }
    /// The simulator (read it only while the thread is not running).
    const Simulator& simulator() const { return m_simulator; }
    /// Replaces the body state and step count (only while not running) and starts a fresh session from
    /// it: grab released, Ks and Kd back to the settings, passivity history and recording restarted.
    void restoreState(const BodyState& state, long long stepCount);
    /// The device (touch it only while the thread is not running).
    InputDevice& device() { return *m_device; }
    /// The recording so far (read it only while the thread is not running).
    const HapticRecording& recording() const { return m_recording; }
    /// Rate and jitter (read it only while the thread is not running; readSnapshot() otherwise).
    const HapticStats& stats() const { return m_stats; }
    /// Settings (constant).
    const HapticSettings& settings() const { return m_settings; }
    /// Passivity observer and controller (read it only while the thread is not running).
    const PassivityController& passivity() const { return m_passivity; }

private:
    HapticLoop(std::shared_ptr<const BodyModel> model, const SimulationSettings& simulation,
               const ExternalForces& world, std::unique_ptr<InputDevice> device, const HapticSettings& settings);
    void run();
    void runTick(double seconds);
    void apply(const HapticCommand& command);
    void recordPeriod(double periodSeconds, double workSeconds);
    void updateStats();
    void publish(double seconds);

    HapticSettings m_settings;
    Simulator m_simulator;
    std::unique_ptr<InputDevice> m_device;
    ExternalForces m_forces;             ///< World plus the grab (drags[0] while grabbed).
    std::vector<DragSpring> m_spareDrag; ///< The grab spring while released (support reserved once).
    bool m_grabbed = false;
    double m_stiffness = 0.0;            ///< Ks in use, capped for the device.
    double m_damping = 0.0;              ///< Kd in use.
    double m_wallStiffness = 0.0;        ///< Penalty stiffness in use, capped for the device.
    double m_maxForce = 0.0;             ///< Device clamp, N; 0 without force feedback.
    PassivityController m_passivity;
    Vec3 m_previousAvatar = Vec3::Zero();
    bool m_havePrevious = false;

    // Results of the last tick, published by publish().
    DeviceSample m_sample;
    Vec3 m_avatar = Vec3::Zero();
    Vec3 m_avatarShown = Vec3::Zero();
    Vec3 m_grabPoint = Vec3::Zero();
    Vec3 m_forceOnBody = Vec3::Zero();
    Vec3 m_deviceForce = Vec3::Zero();

    long long m_tick = 0;
    HapticRecording m_recording;
    bool m_recordStarted = false;

    SpscRing<HapticCommand, 64> m_commands;       ///< UI → loop.
    TripleBuffer<HapticSnapshot> m_snapshots;    ///< Loop → UI, the newest tick's.

    // Rate and jitter over a sliding window.
    std::vector<double> m_periods;       ///< Ring of wake-to-wake periods, seconds.
    std::vector<double> m_work;          ///< Ring of tick work times, seconds.
    std::vector<double> m_scratch;       ///< Sorting space (sized once).
    std::size_t m_periodCount = 0;       ///< Periods recorded so far (the ring holds the last window).
    HapticStats m_stats;

    std::thread m_thread;
    std::atomic<bool> m_stop{false};
};

/// Replays a recording through a loop in manual mode: the loop must be built on the same model,
/// simulation and haptic settings, with a SampleSequenceDevice over `recording.samples`. Restores
/// the recording's start state, then applies each command on its tick and runs every tick.
void replayRecording(HapticLoop& loop, const HapticRecording& recording);

}  // namespace softtouch
