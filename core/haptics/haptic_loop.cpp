#include "core/haptics/haptic_loop.h"

#include "core/base/ranges.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>
#endif

namespace softtouch {

using ranges::finiteIn;

namespace {

double percentile(std::vector<double>& values, std::size_t count, double p) {
    // Nearest-rank percentile of the first `count` values (reorders them).
    const std::size_t rank = std::min(count - 1, std::size_t(std::ceil(p * double(count))) - (p > 0.0 ? 1 : 0));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(rank), values.begin() + std::ptrdiff_t(count));
    return values[rank];
}

}  // namespace

HapticCommand HapticCommand::grab(std::span<const NodeWeight> weights) {
    HapticCommand c;
    c.kind = Kind::Grab;
    c.supportSize = std::uint32_t(std::min(weights.size(), kMaxGrabSupport));
    std::copy_n(weights.begin(), c.supportSize, c.support.begin());
    return c;
}

HapticCommand HapticCommand::release() { return HapticCommand{}; }

HapticCommand HapticCommand::setStiffness(double stiffnessNPerM) {
    HapticCommand c;
    c.kind = Kind::SetStiffness;
    c.value = stiffnessNPerM;
    return c;
}

HapticCommand HapticCommand::setDamping(double dampingNsPerM) {
    HapticCommand c;
    c.kind = Kind::SetDamping;
    c.value = dampingNsPerM;
    return c;
}

Status HapticSettings::validate() const {
    if (!finiteIn(rateHz, 1.0, 20000.0)) return Status::error("haptic rate must be in [1, 20000] Hz");
    if (statsWindow < 10 || statsWindow > 1000000) return Status::error("stats window must be in [10, 1e6] ticks");
    if (realtimePriority < 0 || realtimePriority > 99) return Status::error("real-time priority must be in [0, 99]");
    if (!finiteIn(calibration.scale, 1e-12, 1e6)) return Status::error("calibration scale must be in (0, 1e6]");
    if (!calibration.origin.allFinite() || !calibration.rotation.allFinite())
        return Status::error("calibration origin and rotation must be finite");
    return coupling.validate();
}

Result<std::unique_ptr<HapticLoop>> HapticLoop::create(std::shared_ptr<const BodyModel> model,
                                                       const SimulationSettings& simulation,
                                                       const ExternalForces& world, std::unique_ptr<InputDevice> device,
                                                       const HapticSettings& settings) {
    if (!model) return Status::error("haptic loop: no body");
    if (!device) return Status::error("haptic loop: no device (use NullDevice when nothing is connected)");
    if (Status s = settings.validate(); !s) return Status::error("haptic loop: " + s.message());
    SimulationSettings sim = simulation;
    sim.dt = 1.0 / settings.rateHz;
    if (Status s = sim.validate(); !s) return Status::error("haptic loop: " + s.message());
    if (std::string bad = world.firstNonFinite(); !bad.empty()) return Status::error("haptic loop: " + bad);
    return std::unique_ptr<HapticLoop>(new HapticLoop(std::move(model), sim, world, std::move(device), settings));
}

HapticLoop::HapticLoop(std::shared_ptr<const BodyModel> model, const SimulationSettings& simulation,
                       const ExternalForces& world, std::unique_ptr<InputDevice> device, const HapticSettings& settings)
    : m_settings(settings), m_simulator(std::move(model), simulation), m_device(std::move(device)), m_forces(world) {
    m_forces.drags.clear();
    m_spareDrag.resize(1);
    m_spareDrag.front().support.reserve(kMaxGrabSupport);
    m_damping = settings.coupling.damping;
    const DeviceInfo& info = m_device->info();
    m_stiffness = renderableStiffness(settings.coupling.stiffness, info, settings.calibration);
    m_wallStiffness = renderableStiffness(settings.coupling.wallStiffness, info, settings.calibration);
    m_maxForce = info.forceFeedback ? info.maxForceN : 0.0;
    for (HapticSnapshot& s : m_snapshots.buffers()) s.positions.resize(m_simulator.model().nodeCount());
    const auto window = std::size_t(settings.statsWindow);
    m_periods.resize(window);
    m_work.resize(window);
    m_scratch.resize(window);
    m_recording.rateHz = settings.rateHz;
    m_recording.samples.reserve(settings.recordCapacity);
    m_recording.commands.reserve(settings.recordCapacity > 0 ? settings.commandCapacity : 0);
}

HapticLoop::~HapticLoop() { stop(); }

bool HapticLoop::start() {
    if (m_thread.joinable()) return false;
    m_stop.store(false, std::memory_order_relaxed);
    m_thread = std::thread([this] { run(); });
    return true;
}

void HapticLoop::stop() {
    if (!m_thread.joinable()) return;
    m_stop.store(true, std::memory_order_release);
    m_thread.join();
    updateStats();
}

void HapticLoop::tick() {
    assert(!m_thread.joinable() && "manual ticks only while the thread is stopped");
    runTick(double(m_tick) / m_settings.rateHz);
}

void HapticLoop::tickFor(long long count) {
    for (long long i = 0; i < count; ++i) tick();
}

void HapticLoop::restoreState(const BodyState& state, long long stepCount) {
    assert(!m_thread.joinable());
    m_simulator.restoreState(state, stepCount);
    m_recording.samples.clear();
    m_recording.commands.clear();
    m_recording.truncated = false;
    m_recordStarted = false;
    m_tick = 0;
    m_havePrevious = false;
    apply(HapticCommand::release());
    m_stiffness = renderableStiffness(m_settings.coupling.stiffness, m_device->info(), m_settings.calibration);
    m_damping = m_settings.coupling.damping;
    m_passivity.reset();
}

bool HapticLoop::post(const HapticCommand& command) { return m_commands.push(command); }

bool HapticLoop::readSnapshot(HapticSnapshot& out) {
    if (!m_snapshots.take()) return false;
    const HapticSnapshot& s = m_snapshots.front();
    out.positions.resize(s.positions.size());
    std::copy(s.positions.begin(), s.positions.end(), out.positions.begin());
    out.tick = s.tick;
    out.time = s.time;
    out.sample = s.sample;
    out.avatar = s.avatar;
    out.avatarShown = s.avatarShown;
    out.grabbed = s.grabbed;
    out.grabPoint = s.grabPoint;
    out.forceOnBody = s.forceOnBody;
    out.deviceForce = s.deviceForce;
    out.stiffness = s.stiffness;
    out.stats = s.stats;
    return true;
}

void HapticLoop::apply(const HapticCommand& command) {
    switch (command.kind) {
    case HapticCommand::Kind::Grab: {
        if (command.supportSize == 0) break;
        if (m_forces.drags.empty()) m_forces.drags.swap(m_spareDrag);
        DragSpring& drag = m_forces.drags.front();
        drag.support.assign(command.support.begin(), command.support.begin() + command.supportSize);
        drag.stiffness = m_stiffness;
        drag.damping = m_damping;
        m_grabbed = true;
        m_passivity.reset();
        break;
    }
    case HapticCommand::Kind::Release:
        // The spring (and its reserved support) waits in m_spareDrag for the next grab, so neither
        // grab nor release allocates; the simulator sees an empty drag list.
        if (!m_forces.drags.empty()) m_forces.drags.swap(m_spareDrag);
        m_grabbed = false;
        break;
    case HapticCommand::Kind::SetStiffness:
        if (std::isfinite(command.value) && command.value > 0.0)
            m_stiffness = renderableStiffness(std::min(command.value, 1e9), m_device->info(), m_settings.calibration);
        if (!m_forces.drags.empty()) m_forces.drags.front().stiffness = m_stiffness;
        break;
    case HapticCommand::Kind::SetDamping:
        if (std::isfinite(command.value) && command.value >= 0.0) m_damping = std::min(command.value, 1e6);
        if (!m_forces.drags.empty()) m_forces.drags.front().damping = m_damping;
        break;
    }
}

void HapticLoop::runTick(double seconds) {
    const double h = 1.0 / m_settings.rateHz;
    const bool recording = m_settings.recordCapacity > 0 && !m_recording.truncated;
    if (recording && !m_recordStarted) {
        m_recording.initialState = m_simulator.saveState();  // reserved storage is reused after the first tick
        m_recording.initialStep = m_simulator.stepCount();
        m_recordStarted = true;
    }
    const long long recordTick = m_tick;

    // 1. Commands (lock-free ring).
    while (const HapticCommand* next = m_commands.front()) {
        const HapticCommand& command = *next;
        apply(command);
        if (recording) {
            if (m_recording.commands.size() < m_recording.commands.capacity())
                m_recording.commands.push_back(RecordedCommand{recordTick, command});
            else
                m_recording.truncated = true;
        }
        m_commands.pop();
    }

    // 2. Device.
    m_sample = m_device->read(seconds);
    if (recording && !m_recording.truncated) {
        if (m_recording.samples.size() < m_recording.samples.capacity())
            m_recording.samples.push_back(m_sample);
        else
            m_recording.truncated = true;
    }
    const DeviceCalibration& cal = m_settings.calibration;
    m_avatar = cal.positionToScene(m_sample.position);
    const Vec3 avatarVelocity = cal.velocityToScene(m_sample.velocity);
    if (!m_havePrevious) m_previousAvatar = m_avatar;

    // 3. Body: the avatar is the target of the drag spring; the simulator substeps as it needs.
    if (m_grabbed) {
        m_forces.drags.front().target = m_avatar;
        m_forces.drags.front().targetVelocity = avatarVelocity;
    }
    m_simulator.step(m_forces);

    // 4. Reaction on the hand: drag coupling plus the point-to-plane model, in the scene.
    Vec3 force = Vec3::Zero();
    m_forceOnBody.setZero();
    if (m_grabbed) {
        const BodyState& state = m_simulator.state();
        const DragCoupling c = dragCoupling(m_forces.drags.front(), state.position, state.velocity);
        force += c.reaction;
        m_forceOnBody = c.forceOnBody;
        m_grabPoint = c.point;
    }
    m_avatarShown = m_avatar;
    for (const CollisionPlane& plane : m_forces.planes) {
        const AvatarContact contact = avatarPlaneContact(plane, m_previousAvatar, m_avatar, avatarVelocity,
                                                         m_settings.coupling, m_wallStiffness, h);
        force += contact.force;
        if (contact.kind != ContactCase::None) m_avatarShown += contact.proxyPosition - m_avatar;
    }
    m_previousAvatar = m_avatar;
    m_havePrevious = true;

    // 5. Passivity, clamp, send.
    const Vec3 wanted = cal.forceToDevice(force);
    m_deviceForce = m_passivity.apply(wanted, m_sample.velocity, h, m_maxForce, m_settings.coupling.passivityControl);
    if (m_maxForce <= 0.0) m_deviceForce.setZero();
    m_device->sendForce(m_deviceForce);

    ++m_tick;
    publish(seconds);
}

void HapticLoop::publish(double seconds) {
    HapticSnapshot& s = m_snapshots.back();
    const std::vector<Vec3>& position = m_simulator.state().position;
    std::copy(position.begin(), position.end(), s.positions.begin());
    s.tick = m_tick;
    s.time = seconds;
    s.sample = m_sample;
    s.avatar = m_avatar;
    s.avatarShown = m_avatarShown;
    s.grabbed = m_grabbed;
    s.grabPoint = m_grabPoint;
    s.forceOnBody = m_forceOnBody;
    s.deviceForce = m_deviceForce;
    s.stiffness = m_stiffness;
    m_stats.ticks = m_tick;
    m_stats.passiveEnergyJ = m_passivity.energy();
    m_stats.passivityActiveTicks = m_passivity.activeTicks();
    m_stats.clampedTicks = m_passivity.clampedTicks();
    s.stats = m_stats;
    m_snapshots.publish();
}

void HapticLoop::recordPeriod(double periodSeconds, double workSeconds) {
    const std::size_t i = m_periodCount % m_periods.size();
    m_periods[i] = periodSeconds;
    m_work[i] = workSeconds;
    ++m_periodCount;
}

void HapticLoop::updateStats() {
    const std::size_t n = std::min(m_periodCount, m_periods.size());
    if (n == 0) return;
    std::copy_n(m_periods.begin(), n, m_scratch.begin());
    double sum = 0.0;
    double longest = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        sum += m_scratch[i];
        longest = std::max(longest, m_scratch[i]);
    }
    m_stats.rateHz = double(n) / sum;
    m_stats.periodMaxMs = 1e3 * longest;
    m_stats.periodP99Ms = 1e3 * percentile(m_scratch, n, 0.99);
    m_stats.periodP50Ms = 1e3 * percentile(m_scratch, n, 0.50);
    std::copy_n(m_work.begin(), n, m_scratch.begin());
    m_stats.tickP99Us = 1e6 * percentile(m_scratch, n, 0.99);
}

void HapticLoop::run() {
#if defined(__linux__)
    // The default 50 µs timer slack alone would be 5% of the period: ask for 1 µs on this thread.
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    if (m_settings.realtimePriority > 0) {
        sched_param param{};
        param.sched_priority = m_settings.realtimePriority;
        m_stats.realtime = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
    }
#endif
    using Clock = std::chrono::steady_clock;
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / m_settings.rateHz));
    const Clock::time_point start = Clock::now();
    const long long firstTick = m_tick;
    long long k = 0;  // deadline index: deadline k = start + k·period, never accumulated, so no drift
    Clock::time_point lastWake{};
    bool haveLast = false;
    const long long statsEvery = std::max(10, m_settings.statsWindow / 10);
    while (!m_stop.load(std::memory_order_acquire)) {
        std::this_thread::sleep_until(start + k * period);
        const Clock::time_point wake = Clock::now();
        runTick(std::chrono::duration<double>(wake - start).count());
        const Clock::time_point done = Clock::now();
        if (haveLast)
            recordPeriod(std::chrono::duration<double>(wake - lastWake).count(),
                         std::chrono::duration<double>(done - wake).count());
        lastWake = wake;
        haveLast = true;
        if ((m_tick - firstTick) % statsEvery == 0) updateStats();
        ++k;
        if (done > start + k * period) {
            // Overran the next deadline: skip the ones already past instead of bursting to catch up.
            const long long now = (done - start) / period;
            m_stats.missedDeadlines += now + 1 - k;
            k = now + 1;
        }
    }
}

void replayRecording(HapticLoop& loop, const HapticRecording& recording) {
    loop.restoreState(recording.initialState, recording.initialStep);
    std::size_t next = 0;
    for (long long t = 0; t < (long long)recording.samples.size(); ++t) {
        while (next < recording.commands.size() && recording.commands[next].tick == t)
            loop.post(recording.commands[next++].command);
        loop.tick();
    }
}

}  // namespace softtouch
