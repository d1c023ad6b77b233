// Sessions: recording interactive drags and replaying them bit for bit.
#include "core/authoring/session.h"
#include "helpers/test_support.h"

#include <QtTest/QtTest>

using namespace softtouch;

namespace {

Scene ballScene() {
    Scene scene = test::anchoredBallScene();
    // A driver too: the session adds to the drivers, it does not replace them.
    SwimDriver swim;
    swim.point = Vec3(0.5, 0.9, 0.5);
    swim.direction = Vec3::UnitX();
    swim.amplitude = 0.05;
    scene.objects[0].drivers.push_back(swim);
    return scene;
}

/// A mouse drag whose target moves with time: the kind of input the viewport records.
DragSpring mouse(const SceneSimulation& sim, const Vec3& uvw, const Vec3& offset) {
    DragSpring drag;
    const Lattice& lattice = sim.object(0).lattice;
    drag.support = lattice.weights(uvw);
    drag.target = lattice.evaluate(uvw, lattice.restNodes()) + offset;
    drag.stiffness = 300.0;
    drag.damping = 0.5;
    return drag;
}

/// Runs a scripted "user" for `frames` frames at 24 fps: holds still, drags, moves, lets go, grabs
/// another point. Returns the node positions at the end of every frame.
std::vector<std::vector<Vec3>> performUser(SceneSimulation& sim, SessionRecorder& recorder, int frames) {
    std::vector<std::vector<Vec3>> states;
    const double fps = 24.0;
    for (int f = 1; f <= frames; ++f) {
        if (f == 3)
            sim.setInteractiveDrags(0, {mouse(sim, Vec3(0.5, 1.0, 0.5), Vec3(0, 0.1, 0))});
        else if (f > 3 && f < 12)
            sim.setInteractiveDrags(0, {mouse(sim, Vec3(0.5, 1.0, 0.5), Vec3(0.02 * f, 0.1, 0))});
        else if (f == 12)
            sim.setInteractiveDrags(0, {});
        else if (f == 16)
            sim.setInteractiveDrags(0, {mouse(sim, Vec3(0.2, 0.8, 0.7), Vec3(0, 0, 0.2)),
                                        mouse(sim, Vec3(0.8, 0.8, 0.3), Vec3(0, 0, -0.2))});
        // f 12..15 and 17.. hold: nothing to record.
        recorder.recordStep(sim);
        sim.advanceTo(f / fps);
        states.push_back(sim.simulator(0).state().position);
    }
    return states;
}

}  // namespace

class TestSession : public QObject {
    Q_OBJECT
private slots:
    void replayReproducesEveryStepBitExactly();
    void recordsOnlyChanges();
    void sessionStartingMidwayReplays();
    void sessionStartingOnASettlingBodyReplays();
    void mismatchedSceneIsRefused();
};

void TestSession::replayReproducesEveryStepBitExactly() {
    auto created = SceneSimulation::create(ballScene());
    QVERIFY2(created.ok(), created.message().c_str());
    SceneSimulation& sim = created.value();
    SessionRecorder recorder;
    recorder.begin(sim);
    QVERIFY(recorder.isRecording());
    const int frames = 24;
    const std::vector<std::vector<Vec3>> live = performUser(sim, recorder, frames);
    const Session session = recorder.finish(sim);
    const BodyState end = sim.simulator(0).state();
    QCOMPARE(session.endStep, sim.stepCount());
    QCOMPARE(session.endStep, 240LL);  // one second at the scene's 1/240 s step

    // Replay into a fresh simulation and into the same one (after a reset): both bit-exact, per frame
    // (10 steps) and at the end.
    auto fresh = SceneSimulation::create(ballScene());
    QVERIFY(fresh.ok());
    for (SceneSimulation* target : {&fresh.value(), &sim}) {
        target->reset();
        std::size_t checked = 0;
        Status s = replaySession(*target, session, [&](long long step) {
            if (step % 10 == 0) {
                const std::size_t f = std::size_t(step / 10) - 1;
                if (target->simulator(0).state().position != live[f])
                    return false;
                ++checked;
            }
            return true;
        });
        QVERIFY2(s.ok(), s.message().c_str());
        QCOMPARE(checked, std::size_t(frames));
        QCOMPARE(target->stepCount(), session.endStep);
        QVERIFY(target->simulator(0).state().position == end.position);
        QVERIFY(target->simulator(0).state().velocity == end.velocity);
    }
    // The interactive drags really acted: without them the end state differs.
    sim.reset();
    sim.advanceTo(1.0);
    QVERIFY(sim.simulator(0).state().position != end.position);
}

void TestSession::recordsOnlyChanges() {
    auto created = SceneSimulation::create(ballScene());
    QVERIFY(created.ok());
    SceneSimulation& sim = created.value();
    SessionRecorder recorder;
    recorder.begin(sim);
    performUser(sim, recorder, 24);
    const Session session = recorder.finish(sim);
    // Grab at 3, moves at 4..11 (8), release at 12, two-handed grab at 16: 11 changes in 24 frames.
    QCOMPARE(session.events.size(), std::size_t(11));
    QCOMPARE(session.events[9].drags.size(), std::size_t(0));
    QCOMPARE(session.events[10].drags.size(), std::size_t(2));
    for (std::size_t e = 1; e < session.events.size(); ++e)
        QVERIFY(session.events[e].step > session.events[e - 1].step);
}

void TestSession::sessionStartingMidwayReplays() {
    auto created = SceneSimulation::create(ballScene());
    QVERIFY(created.ok());
    SceneSimulation& sim = created.value();
    // Already dragging when recording starts: the start drags are part of the session.
    sim.setInteractiveDrags(0, {mouse(sim, Vec3(0.5, 1.0, 0.5), Vec3(0.1, 0.1, 0))});
    sim.advanceTo(0.3);
    SessionRecorder recorder;
    recorder.begin(sim);
    sim.advanceTo(0.5);
    recorder.recordStep(sim);
    sim.setInteractiveDrags(0, {});
    recorder.recordStep(sim);
    sim.advanceTo(0.8);
    const Session session = recorder.finish(sim);
    QCOMPARE(session.start.step, 72LL);
    QCOMPARE(session.events.size(), std::size_t(1));
    const BodyState end = sim.simulator(0).state();

    sim.reset();
    sim.advanceTo(2.0);  // anywhere else: the replay restores the start
    long long steps = 0;
    QVERIFY(replaySession(sim, session, [&](long long) { ++steps; return true; }).ok());
    QCOMPARE(steps, session.endStep - session.start.step);
    QVERIFY(sim.simulator(0).state().position == end.position);
    QVERIFY(sim.simulator(0).state().velocity == end.velocity);

    // A player can stop anywhere in between and go on: same end.
    SessionPlayer player;
    QVERIFY(player.start(sim, session).ok());
    player.advanceTo(sim, 0.55);
    QCOMPARE(sim.stepCount(), 132LL);
    player.advanceTo(sim, 5.0);  // clamped to the session's end
    QCOMPARE(sim.stepCount(), session.endStep);
    QVERIFY(sim.simulator(0).state().position == end.position);
}

void TestSession::sessionStartingOnASettlingBodyReplays() {
    // The hidden part of a running body (how long it has been quiet, whether it sleeps) is not in a
    // snapshot; recording starts from what a restore gives, so the replay sees the same thing.
    Scene scene = ballScene();
    scene.objects[0].drivers.clear();
    auto created = SceneSimulation::create(scene);
    QVERIFY(created.ok());
    SceneSimulation& sim = created.value();
    sim.setInteractiveDrags(0, {mouse(sim, Vec3(0.5, 1.0, 0.5), Vec3(0, 0.1, 0))});
    sim.advanceTo(0.5);
    sim.setInteractiveDrags(0, {});
    for (double t : {3.0, 12.0}) {  // still settling (counting quiet steps), then asleep
        sim.advanceTo(t);
        SessionRecorder recorder;
        recorder.begin(sim);
        sim.advanceTo(t + 0.5);
        recorder.recordStep(sim);
        sim.setInteractiveDrags(0, {mouse(sim, Vec3(0.5, 1.0, 0.5), Vec3(0.05, 0, 0))});
        recorder.recordStep(sim);
        sim.advanceTo(t + 0.7);
        sim.setInteractiveDrags(0, {});
        recorder.recordStep(sim);
        sim.advanceTo(t + 2.5);
        const Session session = recorder.finish(sim);
        const BodyState end = sim.simulator(0).state();
        auto fresh = SceneSimulation::create(scene);
        QVERIFY(fresh.ok());
        QVERIFY(replaySession(fresh.value(), session, {}).ok());
        QVERIFY2(fresh->simulator(0).state().position == end.position, qPrintable(QString("from t = %1 s").arg(t)));
        QVERIFY(fresh->simulator(0).state().velocity == end.velocity);
    }
}

void TestSession::mismatchedSceneIsRefused() {
    auto created = SceneSimulation::create(ballScene());
    QVERIFY(created.ok());
    SessionRecorder recorder;
    recorder.begin(created.value());
    created.value().advanceTo(0.1);
    const Session session = recorder.finish(created.value());

    Scene other = ballScene();
    other.objects[0].lattice = Lattice::create(LatticeShape{LatticeKind::Bezier, {3, 3, 3}},
                                               other.objects[0].lattice.box()).value();
    other.objects[0].material = uniformMaterial(other.objects[0].lattice, 0.01, 80.0, 0.5);
    auto otherSim = SceneSimulation::create(other);
    QVERIFY(otherSim.ok());
    const Status s = replaySession(otherSim.value(), session, {});
    QVERIFY(!s.ok());
    QVERIFY2(s.message().find("27") != std::string::npos, s.message().c_str());

    Session broken = session;
    broken.events.push_back(DragEvent{session.endStep + 5, 0, {}});
    QVERIFY(!broken.validateFor(created.value()).ok());
}

QTEST_APPLESS_MAIN(TestSession)
#include "test_session.moc"
