#pragma once
/// Runs the document's scene interactively: play/pause/step/reset in real time, the user's drag
/// springs (mouse, tablet: two hands at once), and live figures for the status bar (cost per step,
/// the explicit stability bound). The scene is rebuilt when the document changes; the running state
/// is kept when the node count allows, so painting while the fish swims does not restart it.

#include "core/authoring/session.h"
#include "core/scene/scene.h"
#include "ui/document.h"

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>

#include <array>
#include <optional>

namespace softtouch::ui {

/// Live figures of the interactive simulation.
struct SimulationStats {
    double stepMicros = 0.0;       ///< Mean wall time of one fixed step over the last advance, µs.
    double stepsPerSecond = 0.0;   ///< Fixed steps simulated per wall-clock second while playing.
    double stableStepSeconds = 0.0;///< Explicit stability bound for the current forces, seconds; 0 under an
                                   ///< implicit scheme (Implicit Euler, XPBD), which it does not bound.
    int substeps = 0;              ///< Substeps the last step took (explicit schemes).
    double realtimeFactor = 0.0;   ///< Simulated seconds per wall second while playing (1 = real time).
    bool asleep = false;           ///< Every body slept through the last advance: nothing moved or was drawn.
};

/// A user's grab of an object: which object and the drag spring on it.
struct Grab {
    int object = 0;   ///< Object index.
    DragSpring drag;  ///< Material point, target and Ks/Kd.
};

/// Owns the interactive SceneSimulation of a document.
class SimulationController : public QObject {
    Q_OBJECT
public:
    /// Number of simultaneous grabs (two hands).
    static constexpr int kGrabSlots = 2;

    explicit SimulationController(Document* document, QObject* parent = nullptr);

    /// The running simulation; empty when the scene cannot be built (problem() says why).
    const SceneSimulation* simulation() const { return m_sim ? &*m_sim : nullptr; }
    /// Why the scene cannot be simulated; empty when it can.
    const QString& problem() const { return m_problem; }
    bool isPlaying() const { return m_timer.isActive(); }
    const SimulationStats& stats() const { return m_stats; }
    /// Whether the scene's drivers (swim, scripted drags) act; off lets the user sculpt alone.
    bool driversEnabled() const { return m_driversEnabled; }

    /// Sets or clears grab slot 0 or 1. Takes effect from the next step.
    void setGrab(int slot, std::optional<Grab> grab);
    const std::optional<Grab>& grab(int slot) const { return m_grabs[std::size_t(slot)]; }

    /// True while a session is being recorded.
    bool isRecording() const { return m_recorder.isRecording(); }
    /// Starts recording everything that drives the scene from now on (grabs, per step).
    void startRecording();
    /// Stops recording and returns the session (replays bit-exactly from its start snapshot).
    std::optional<Session> stopRecording();
    /// Pauses and shows the state of `session` at `seconds` (from its start), by replaying it.
    Status scrub(const Session& session, double seconds);

    /// Pauses and poses every object at the given node positions ([object][node], at rest velocity):
    /// previewing a clip frame. Play continues the simulation from that pose.
    /// `seconds` >= 0 also moves the scene's time there (a clip's frame: what a base animation shows).
    void showPose(const std::vector<std::vector<Vec3>>& nodes, double seconds = -1.0);

    /// Pauses and puts object i's lattice nodes at `nodes`, at rest (posing, ui/node_transform.h); the other
    /// objects stay as they are. Play continues the simulation from the pose. False (and nothing changes)
    /// when there is no such object or the node count differs (the lattice was replaced meanwhile).
    bool setObjectPose(int object, const std::vector<Vec3>& nodes);

    /// Advances the simulation by `seconds` now (what a timer tick does; tests call it directly).
    void advance(double seconds);

public slots:
    void play();
    void pause();
    void togglePlay();
    /// One step of dt.
    void stepOnce();
    /// Back to rest at time 0 (grabs released).
    void reset();
    void setDriversEnabled(bool enabled);

signals:
    /// New node positions are available. Not emitted by an advance during which every body slept:
    /// an unchanged frame is not drawn again.
    void stepped();
    /// The scene was rebuilt (object count or lattices may differ).
    void rebuilt();
    void playingChanged(bool playing);
    void recordingChanged(bool recording);
    /// A recording stopped (by stopRecording() or because the scene was rebuilt).
    void sessionRecorded(const softtouch::Session& session);
    /// A guard reported something (rolled-back step, refused substeps).
    void problemReported(const QString& message);

private:
    /// True when every body is asleep (its steps cost a comparison and move nothing).
    bool everyBodyAsleep() const;
    /// Fills the stats' stable explicit step and substeps from the current state and forces.
    void measureStepBound();
    void rebuild(bool keepState);
    void tick();
    void applyGrabs();

    Document* m_document;
    std::optional<SceneSimulation> m_sim;
    QString m_problem;
    QTimer m_timer;
    QElapsedTimer m_wall;
    std::array<std::optional<Grab>, kGrabSlots> m_grabs;
    bool m_driversEnabled = true;
    SimulationStats m_stats;
    SessionRecorder m_recorder;
};

}  // namespace softtouch::ui
