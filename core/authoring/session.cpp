#include "core/authoring/session.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace softtouch {
namespace {

double sceneDt(const SceneSimulation& sim) { return sim.simulator(0).settings().dt; }

bool sameDrag(const DragSpring& a, const DragSpring& b) {
    if (a.support.size() != b.support.size() || a.target != b.target || a.targetVelocity != b.targetVelocity ||
        a.stiffness != b.stiffness || a.damping != b.damping)
        return false;
    for (std::size_t i = 0; i < a.support.size(); ++i) {
        if (a.support[i].node != b.support[i].node || a.support[i].weight != b.support[i].weight)
            return false;
    }
    return true;
}

Status validateDrags(const std::vector<DragSpring>& drags, std::size_t nodes, const std::string& where) {
    for (std::size_t d = 0; d < drags.size(); ++d) {
        const DragSpring& drag = drags[d];
        const std::string name = where + "drag " + std::to_string(d) + ": ";
        if (drag.support.empty())
            return Status::error(name + "empty support");
        for (const NodeWeight& w : drag.support) {
            if (w.node >= nodes || !std::isfinite(w.weight))
                return Status::error(name + "support node " + std::to_string(w.node) + " out of range or weight not finite");
        }
        if (!isFinite(drag.target) || !isFinite(drag.targetVelocity) || !std::isfinite(drag.stiffness) ||
            !std::isfinite(drag.damping) || drag.stiffness < 0.0 || drag.damping < 0.0)
            return Status::error(name + "target, velocity, stiffness and damping must be finite (and not negative)");
    }
    return Status::success();
}

}  // namespace

bool sameDrags(const std::vector<DragSpring>& a, const std::vector<DragSpring>& b) {
    if (a.size() != b.size())
        return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (!sameDrag(a[i], b[i]))
            return false;
    }
    return true;
}

Status Session::validateFor(const SceneSimulation& sim) const {
    const std::size_t objects = sim.objectCount();
    if (start.bodies.size() != objects)
        return Status::error("the session has " + std::to_string(start.bodies.size()) + " objects, the scene " +
                             std::to_string(objects));
    if (dt != sceneDt(sim))
        return Status::error("the session was recorded with dt " + std::to_string(dt) + " s, the scene steps " +
                             std::to_string(sceneDt(sim)) + " s");
    if (start.step < 0 || endStep < start.step)
        return Status::error("the session ends (step " + std::to_string(endStep) + ") before it starts (step " +
                             std::to_string(start.step) + ")");
    for (std::size_t i = 0; i < objects; ++i) {
        const std::size_t nodes = sim.simulator(i).state().position.size();
        const BodyState& b = start.bodies[i];
        if (b.position.size() != nodes || b.velocity.size() != nodes)
            return Status::error("object " + std::to_string(i) + ": the session's start state has " +
                                 std::to_string(b.position.size()) + " nodes, the scene's lattice " + std::to_string(nodes));
        if (!b.isFinite())
            return Status::error("object " + std::to_string(i) + ": the session's start state is not finite");
    }
    if (!startDrags.empty() && startDrags.size() != objects)
        return Status::error("the session's start drags list " + std::to_string(startDrags.size()) +
                             " objects, the scene has " + std::to_string(objects));
    for (std::size_t i = 0; i < startDrags.size(); ++i) {
        const std::size_t nodes = sim.simulator(i).state().position.size();
        if (Status s = validateDrags(startDrags[i], nodes, "object " + std::to_string(i) + " start: "); !s)
            return s;
    }
    long long last = start.step;
    for (std::size_t e = 0; e < events.size(); ++e) {
        const DragEvent& ev = events[e];
        const std::string where = "event " + std::to_string(e) + ": ";
        if (ev.step < last || ev.step > endStep)
            return Status::error(where + "step " + std::to_string(ev.step) + " is out of order or outside [" +
                                 std::to_string(start.step) + ", " + std::to_string(endStep) + "]");
        if (ev.object >= objects)
            return Status::error(where + "object " + std::to_string(ev.object) + " does not exist");
        last = ev.step;
        if (Status s = validateDrags(ev.drags, sim.simulator(ev.object).state().position.size(), where); !s)
            return s;
    }
    return Status::success();
}

void SessionRecorder::begin(SceneSimulation& sim) {
    m_session = Session{};
    m_session.start = sim.saveSnapshot();
    sim.restoreSnapshot(m_session.start);
    m_session.dt = sceneDt(sim);
    m_session.endStep = m_session.start.step;
    m_current.clear();
    for (std::size_t i = 0; i < sim.objectCount(); ++i)
        m_current.push_back(sim.interactiveDrags(i));
    m_session.startDrags = m_current;
    m_recording = true;
}

void SessionRecorder::recordStep(const SceneSimulation& sim) {
    assert(m_recording && sim.objectCount() == m_current.size());
    const long long step = sim.stepCount();
    for (std::size_t i = 0; i < m_current.size(); ++i) {
        const std::vector<DragSpring>& now = sim.interactiveDrags(i);
        if (sameDrags(now, m_current[i]))
            continue;
        m_current[i] = now;
        // Two changes before the same step: the later one wins (the earlier never acted).
        auto& events = m_session.events;
        if (!events.empty() && events.back().step == step && events.back().object == i) {
            events.back().drags = now;
            continue;
        }
        events.push_back(DragEvent{step, std::uint32_t(i), now});
    }
    m_session.endStep = std::max(m_session.endStep, step);
}

Session SessionRecorder::finish(const SceneSimulation& sim) {
    m_session.endStep = std::max(m_session.endStep, sim.stepCount());
    m_recording = false;
    return std::move(m_session);
}

Status SessionPlayer::start(SceneSimulation& sim, const Session& session) {
    if (Status s = session.validateFor(sim); !s)
        return s;
    m_session = &session;
    m_eventsOf.assign(sim.objectCount(), {});
    for (std::size_t e = 0; e < session.events.size(); ++e)
        m_eventsOf[session.events[e].object].push_back(e);
    sim.restoreSnapshot(session.start);
    m_applied.assign(sim.objectCount(), nullptr);
    for (std::size_t i = 0; i < sim.objectCount(); ++i) {
        m_applied[i] = &dragsAt(i, session.start.step);
        sim.setInteractiveDrags(i, *m_applied[i]);
    }
    return Status::success();
}

const std::vector<DragSpring>& SessionPlayer::dragsAt(std::size_t object, long long step) const {
    static const std::vector<DragSpring> kNone;
    const std::vector<std::size_t>& mine = m_eventsOf[object];
    const auto& events = m_session->events;
    // The first event after `step`; the one before it is in force.
    const auto after = std::upper_bound(mine.begin(), mine.end(), step,
                                        [&](long long s, std::size_t e) { return s < events[e].step; });
    if (after != mine.begin())
        return events[*(after - 1)].drags;
    return m_session->startDrags.empty() ? kNone : m_session->startDrags[object];
}

SceneSimulation::StepInputs SessionPlayer::inputs() {
    assert(m_session);
    return [this](SceneSimulation& sim, std::size_t object, long long step) {
        const std::vector<DragSpring>& drags = dragsAt(object, step);
        if (&drags == m_applied[object])
            return;
        m_applied[object] = &drags;
        sim.setInteractiveDrags(object, drags);
    };
}

void SessionPlayer::advanceTo(SceneSimulation& sim, double seconds, std::vector<std::string>* problems) {
    assert(m_session);
    sim.advanceTo(std::min(seconds, m_session->endSeconds()), problems, inputs());
}

Status replaySession(SceneSimulation& sim, const Session& session, const std::function<bool(long long)>& onStep,
                     std::vector<std::string>* problems) {
    SessionPlayer player;
    if (Status s = player.start(sim, session); !s)
        return s;
    for (long long step = session.start.step; step < session.endStep; ++step) {
        player.advanceTo(sim, double(step + 1) * session.dt, problems);
        if (onStep && !onStep(sim.stepCount()))
            break;
    }
    return Status::success();
}

}  // namespace softtouch
