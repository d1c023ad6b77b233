#pragma once
/// Sessions: everything that drives a scene interactively, recorded so that it replays exactly.
///
/// A session is the start snapshot plus, per fixed step, each object's interactive drags, stored
/// only when they change (a held mouse costs nothing). Replaying restores the snapshot and steps the
/// same SceneSimulation with the same drags at the same steps, so every state is reproduced bit for
/// bit (the solver is history-free; see SceneSimulation::Snapshot).
///
/// Recording from an editor:
///
///     SessionRecorder recorder;
///     recorder.begin(sim);                 // snapshot now
///     ...                                  // each frame:
///     sim.setInteractiveDrags(0, drags);   //   whatever the mouse does
///     recorder.recordStep(sim);            //   before advancing
///     sim.advanceTo(t);
///     Session session = recorder.finish(sim);
///
/// Replaying: replaySession(sim, session, [](long long step) { ...; return true; }).

#include "core/scene/scene.h"

#include <functional>
#include <vector>

namespace softtouch {

/// From `step` on, object `object` is driven by `drags` (on top of its drivers) until the next event
/// for that object.
struct DragEvent {
    long long step = 0;              ///< Absolute step index (time = step × dt) the drags first act in. >= start step.
    std::uint32_t object = 0;        ///< Scene object index.
    std::vector<DragSpring> drags;   ///< The object's interactive drags; empty releases them.
};

/// A recorded interactive session over one scene.
struct Session {
    SceneSimulation::Snapshot start;  ///< State when recording began (its step is the session's first).
    std::vector<std::vector<DragSpring>> startDrags; ///< Interactive drags per object at the start.
    std::vector<DragEvent> events;    ///< Changes, in increasing step order (ties: object order).
    long long endStep = 0;            ///< Step count when recording stopped, >= start.step.
    double dt = 0.0;                  ///< Fixed step of the scene it was recorded in, seconds.

    /// First simulated time of the session, seconds.
    double startSeconds() const { return double(start.step) * dt; }
    /// Last simulated time of the session, seconds.
    double endSeconds() const { return double(endStep) * dt; }
    /// Checks that the session fits `sim` (object and node counts, dt, ordered events, finite values).
    Status validateFor(const SceneSimulation& sim) const;
};

/// Records interactive drags as they change.
class SessionRecorder {
public:
    /// Starts a session from the current state of `sim` (snapshot and current interactive drags).
    /// A snapshot does not hold how long a body has been quiet or whether it sleeps, and a replay
    /// starts from a restored (awake, not yet quiet) body; so begin() restores `sim` from its own
    /// snapshot first, and the live run and every replay go on from the same full state. (A sleeping
    /// body wakes, and falls asleep again after the same quiet steps in both.)
    void begin(SceneSimulation& sim);
    /// Call before advancing `sim`: records each object's interactive drags that differ from the last
    /// recorded ones, as acting from the current step on. Cheap when nothing changed.
    void recordStep(const SceneSimulation& sim);
    /// Stops recording at the current step of `sim` and hands the session over.
    Session finish(const SceneSimulation& sim);
    /// True between begin() and finish().
    bool isRecording() const { return m_recording; }

private:
    Session m_session;
    std::vector<std::vector<DragSpring>> m_current;
    bool m_recording = false;
};

/// Plays a session back step by step through a SceneSimulation (the replay counterpart of the
/// recorder; also used to bake clips of a session).
class SessionPlayer {
public:
    /// Validates the session against `sim`, restores its start snapshot and drags.
    Status start(SceneSimulation& sim, const Session& session);
    /// Steps `sim`, applying the recorded drags, until its time reaches `seconds` (same rule as
    /// SceneSimulation::advanceTo); never past the session's end.
    void advanceTo(SceneSimulation& sim, double seconds, std::vector<std::string>* problems = nullptr);
    /// The recorded drags as per-step inputs (SceneSimulation::StepInputs): what advanceTo steps with,
    /// for a caller that samples between steps (advanceToSample). Past the end the last drags hold. The
    /// player must outlive them.
    SceneSimulation::StepInputs inputs();

private:
    /// Object o's drags in force at `step`: its last event at or before it, or its start drags.
    const std::vector<DragSpring>& dragsAt(std::size_t object, long long step) const;

    const Session* m_session = nullptr;
    std::vector<std::vector<std::size_t>> m_eventsOf;  ///< Per object, its events' indices in step order.
    /// Per object, the drags last handed to the simulation (one of the session's lists): a step whose drags
    /// are the same list sets nothing, as when the player applied events only.
    std::vector<const std::vector<DragSpring>*> m_applied;
};

/// Replays the whole session: restores its start and calls `onStep(step)` after every step (the
/// absolute step count); returning false stops early. Errors when the session does not fit `sim`.
Status replaySession(SceneSimulation& sim, const Session& session, const std::function<bool(long long)>& onStep,
                     std::vector<std::string>* problems = nullptr);

/// True when two drag lists are identical (bit for bit).
bool sameDrags(const std::vector<DragSpring>& a, const std::vector<DragSpring>& b);

}  // namespace softtouch
