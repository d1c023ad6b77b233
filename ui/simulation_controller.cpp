#include "ui/simulation_controller.h"

#include <algorithm>

namespace softtouch::ui {

SimulationController::SimulationController(Document* document, QObject* parent)
    : QObject(parent), m_document(document) {
    m_timer.setInterval(16);
    m_timer.setTimerType(Qt::PreciseTimer);
    connect(&m_timer, &QTimer::timeout, this, &SimulationController::tick);
    connect(document, &Document::sceneReplaced, this, [this] { rebuild(false); });
    connect(document, &Document::latticeChanged, this, [this] { rebuild(false); });
    connect(document, &Document::materialChanged, this, [this] { rebuild(true); });
    connect(document, &Document::worldChanged, this, [this] { rebuild(true); });
    rebuild(false);
}

void SimulationController::rebuild(bool keepState) {
    if (m_recorder.isRecording())
        stopRecording();  // a session replays only on the scene it was recorded on
    std::optional<SceneSimulation::Snapshot> snapshot;
    if (keepState && m_sim)
        snapshot = m_sim->saveSnapshot();
    Scene scene = m_document->scene();
    if (!m_driversEnabled) {
        for (SceneObject& o : scene.objects)
            o.drivers.clear();
    }
    m_problem.clear();
    if (scene.objects.empty()) {
        m_sim.reset();
        m_problem = tr("The scene has no objects.");
    } else if (auto created = SceneSimulation::create(std::move(scene), m_sim ? &*m_sim : nullptr)) {
        // Built beside the current one, whose bindings and samples it keeps where mesh and lattice are
        // unchanged: a paint dab or a world edit rebuilds only the bodies.
        m_sim.emplace(std::move(created.value()));
        bool sameShape = snapshot && snapshot->bodies.size() == m_sim->objectCount();
        for (std::size_t i = 0; sameShape && i < m_sim->objectCount(); ++i)
            sameShape = snapshot->bodies[i].position.size() == m_sim->simulator(i).state().position.size();
        if (sameShape)
            m_sim->restoreSnapshot(*snapshot);
    } else {
        m_sim.reset();
        m_problem = QString::fromStdString(created.message());
    }
    for (auto& g : m_grabs) {
        if (g && (!m_sim || g->object >= int(m_sim->objectCount())))
            g.reset();
    }
    // The bound and substeps are known before the first step: a paused scene shows them too.
    m_stats.stepMicros = 0.0;
    if (m_sim)
        measureStepBound();
    if (!m_problem.isEmpty())
        emit problemReported(m_problem);
    emit rebuilt();
    emit stepped();
}

void SimulationController::setGrab(int slot, std::optional<Grab> grab) {
    m_grabs[std::size_t(slot)] = std::move(grab);
}

void SimulationController::applyGrabs() {
    for (std::size_t i = 0; i < m_sim->objectCount(); ++i) {
        std::vector<DragSpring> drags;
        for (const auto& g : m_grabs) {
            if (g && g->object == int(i))
                drags.push_back(g->drag);
        }
        m_sim->setInteractiveDrags(i, std::move(drags));
    }
}

void SimulationController::advance(double seconds) {
    if (!m_sim || seconds <= 0.0)
        return;
    applyGrabs();
    if (m_recorder.isRecording())
        m_recorder.recordStep(*m_sim);  // grabs are constant within one advance
    const bool wasAsleep = everyBodyAsleep();
    const long long before = m_sim->stepCount();
    std::vector<std::string> problems;
    QElapsedTimer cost;
    cost.start();
    m_sim->advanceTo(m_sim->time() + seconds, &problems);
    const long long steps = m_sim->stepCount() - before;
    if (steps > 0)
        m_stats.stepMicros = double(cost.nsecsElapsed()) * 1e-3 / double(steps);
    measureStepBound();
    m_stats.asleep = everyBodyAsleep();
    for (const std::string& p : problems)
        emit problemReported(QString::fromStdString(p));
    if (!(wasAsleep && m_stats.asleep))  // asleep before and after: no node moved, nothing to redraw
        emit stepped();
}

void SimulationController::measureStepBound() {
    // The first body's: explicit schemes cut their steps to this bound (0 for the others), into this many substeps.
    const Simulator& first = m_sim->simulator(0);
    const ExternalForces forces = m_sim->forcesAt(0, m_sim->time());
    m_stats.stableStepSeconds = first.isExplicit() ? first.stableStep(forces) : 0.0;
    m_stats.substeps = first.substepsFor(forces);
}

bool SimulationController::everyBodyAsleep() const {
    for (std::size_t i = 0; i < m_sim->objectCount(); ++i) {
        if (!m_sim->simulator(i).isSleeping())
            return false;
    }
    return true;
}

void SimulationController::tick() {
    const double wall = std::min(double(m_wall.restart()) * 1e-3, 0.1);  // a stalled UI never causes a burst
    const long long before = m_sim ? m_sim->stepCount() : 0;
    advance(wall);
    if (m_sim && wall > 0.0) {
        const double simulated = double(m_sim->stepCount() - before) * m_sim->simulator(0).settings().dt;
        m_stats.stepsPerSecond = double(m_sim->stepCount() - before) / wall;
        m_stats.realtimeFactor = simulated / wall;
    }
}

void SimulationController::play() {
    if (isPlaying() || !m_sim)
        return;
    m_wall.start();
    m_timer.start();
    emit playingChanged(true);
}

void SimulationController::pause() {
    if (!isPlaying())
        return;
    m_timer.stop();
    m_stats.stepsPerSecond = 0.0;
    m_stats.realtimeFactor = 0.0;
    emit playingChanged(false);
}

void SimulationController::togglePlay() {
    isPlaying() ? pause() : play();
}

void SimulationController::stepOnce() {
    if (m_sim)
        advance(m_sim->simulator(0).settings().dt);
}

void SimulationController::reset() {
    for (auto& g : m_grabs)
        g.reset();
    if (m_sim)
        m_sim->reset();
    emit stepped();
}

void SimulationController::startRecording() {
    if (!m_sim || m_recorder.isRecording())
        return;
    applyGrabs();
    m_recorder.begin(*m_sim);
    emit recordingChanged(true);
}

std::optional<Session> SimulationController::stopRecording() {
    if (!m_recorder.isRecording() || !m_sim)
        return std::nullopt;
    Session session = m_recorder.finish(*m_sim);
    emit recordingChanged(false);
    emit sessionRecorded(session);
    return session;
}

Status SimulationController::scrub(const Session& session, double seconds) {
    if (!m_sim)
        return Status::error(m_problem.toStdString());
    pause();
    if (m_recorder.isRecording())
        stopRecording();
    SessionPlayer player;
    if (Status s = player.start(*m_sim, session); !s)
        return s;
    player.advanceTo(*m_sim, session.startSeconds() + seconds);
    emit stepped();
    return Status::success();
}

void SimulationController::showPose(const std::vector<std::vector<Vec3>>& nodes, double seconds) {
    if (!m_sim || nodes.size() != m_sim->objectCount())
        return;
    pause();
    SceneSimulation::Snapshot pose = m_sim->saveSnapshot();
    if (seconds >= 0.0)
        pose.step = std::llround(seconds / m_sim->simulator(0).settings().dt);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        if (nodes[i].size() != pose.bodies[i].position.size())
            return;
        pose.bodies[i].position = nodes[i];
        std::fill(pose.bodies[i].velocity.begin(), pose.bodies[i].velocity.end(), Vec3::Zero());
    }
    m_sim->restoreSnapshot(pose);
    emit stepped();
}

bool SimulationController::setObjectPose(int object, const std::vector<Vec3>& nodes) {
    if (!m_sim || object < 0 || std::size_t(object) >= m_sim->objectCount())
        return false;
    SceneSimulation::Snapshot pose = m_sim->saveSnapshot();
    BodyState& body = pose.bodies[std::size_t(object)];
    if (nodes.size() != body.position.size())
        return false;
    pause();
    body.position = nodes;
    std::fill(body.velocity.begin(), body.velocity.end(), Vec3::Zero());
    m_sim->restoreSnapshot(pose);
    emit stepped();
    return true;
}

void SimulationController::setDriversEnabled(bool enabled) {
    if (enabled == m_driversEnabled)
        return;
    m_driversEnabled = enabled;
    rebuild(true);
}

}  // namespace softtouch::ui
