// Clips: each source evaluates to exactly what it plays; loop closure and the seam measure.
#include "core/authoring/clip.h"
#include "helpers/test_support.h"

#include <QtTest/QtTest>
#include <numbers>

using namespace softtouch;

namespace {

Scene swimmingBall() {
    Scene scene;
    SceneObject object;
    object.name = "ball";
    object.mesh = test::makeSphere(0.5, Vec3::Zero(), 12, 24);
    object.lattice = Lattice::create(LatticeShape{}, fitBox(object.mesh->positions).value()).value();
    object.material = uniformMaterial(object.lattice, 0.01, 80.0, 0.3);
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            object.material.anchor[std::size_t(object.lattice.index(3, j, k))] = AnchorMode::Pinned;
    SwimDriver swim;
    swim.point = Vec3(0.0, 0.5, 0.5);
    swim.amplitude = 0.1;
    swim.rampSeconds = 0.5;
    object.drivers.push_back(swim);
    scene.objects.push_back(std::move(object));
    return scene;
}

std::vector<Vec3> positions(const SceneSimulation& sim) { return sim.simulator(0).state().position; }

/// Synthetic frames of `points` points on circles, with a drift per frame (a cycle that does not repeat).
std::vector<std::vector<Vec3>> circling(int frames, int period, double drift, int first = 0) {
    std::vector<std::vector<Vec3>> out;
    for (int i = first; i < first + frames; ++i) {
        std::vector<Vec3> f;
        for (int p = 0; p < 5; ++p) {
            const double a = 2.0 * std::numbers::pi * double(i) / double(period) + p;
            f.push_back(Vec3(std::cos(a), std::sin(a), drift * i) * (1.0 + 0.1 * p));
        }
        out.push_back(std::move(f));
    }
    return out;
}

}  // namespace

class TestClip : public QObject {
    Q_OBJECT
private slots:
    void driversClipIsTheSimulation();
    void sessionClipIsTheReplay();
    void keyframeClipsPlayKeysOrGoals();
    void goalClipsStartInStride();
    void loopClosureByCrossFadeAndBySpreadingTheDrift();
    void seamMeasureOfAPerfectCycle();
    void badClipsAreRefused();
};

void TestClip::driversClipIsTheSimulation() {
    const Scene scene = swimmingBall();
    ClipLibrary lib;
    const Clip clip{"a", ClipSource::Drivers, "", 0.5, 12, 24.0, false, 0, std::nullopt};
    auto frames = evaluateClip(scene, lib, clip);
    QVERIFY2(frames.ok(), frames.message().c_str());
    QCOMPARE(frames->nodes.size(), std::size_t(12));
    auto sim = SceneSimulation::create(scene);
    QVERIFY(sim.ok());
    for (int i = 0; i < 12; ++i) {
        sim->advanceTo(0.5 + i / 24.0);
        QVERIFY2(frames->nodes[std::size_t(i)][0] == positions(sim.value()), qPrintable(QString("frame %1").arg(i)));
    }
}

void TestClip::sessionClipIsTheReplay() {
    const Scene scene = swimmingBall();
    auto sim = SceneSimulation::create(scene);
    QVERIFY(sim.ok());
    const Lattice& lattice = sim->object(0).lattice;
    sim->advanceTo(0.3);
    SessionRecorder recorder;
    recorder.begin(sim.value());
    std::vector<std::vector<Vec3>> live;
    for (int f = 1; f <= 24; ++f) {
        DragSpring d;
        d.support = lattice.weights(Vec3(0.5, 1.0, 0.5));
        d.target = lattice.evaluate(Vec3(0.5, 1.0, 0.5), lattice.restNodes()) + Vec3(0, 0.01 * (f % 7), 0);
        d.stiffness = 100.0;
        sim->setInteractiveDrags(0, {d});
        recorder.recordStep(sim.value());
        sim->advanceTo(0.3 + f / 24.0);
        live.push_back(positions(sim.value()));
    }
    ClipLibrary lib;
    lib.sessions.push_back({"s", recorder.finish(sim.value())});
    // Frames 0..11 of a clip starting 0.25 s into the session are the live frames 6..17 (frame f of
    // the recording was taken at session time f/24 s).
    const Clip clip{"c", ClipSource::Session, "s", 0.25, 12, 24.0, false, 0, std::nullopt};
    QVERIFY(lib.validate(scene).ok());
    auto frames = evaluateClip(scene, lib, clip);
    QVERIFY2(frames.ok(), frames.message().c_str());
    for (std::size_t i = 0; i < 12; ++i)
        QVERIFY2(frames->nodes[i][0] == live[i + 5], qPrintable(QString("frame %1").arg(i)));
    // Past the session's end is an error that says how long it is.
    const Clip tooLong{"c", ClipSource::Session, "s", 0.5, 24, 24.0, false, 0, std::nullopt};
    auto refused = evaluateClip(scene, lib, tooLong);
    QVERIFY(!refused.ok());
    QVERIFY2(refused.message().find("1.0000") != std::string::npos, refused.message().c_str());
}

void TestClip::keyframeClipsPlayKeysOrGoals() {
    const Scene scene = swimmingBall();
    const Lattice& lattice = scene.objects[0].lattice;
    const std::vector<Vec3> rest = lattice.restNodes();
    KeyframeAnimation anim(rest.size());
    std::vector<Vec3> bent = rest;
    for (int n = 0; n < lattice.nodeCount(); ++n)
        bent[std::size_t(n)].z() += 0.2 * (1.0 - lattice.restNodeParameters(n).x());
    QVERIFY(anim.setKey(0.0, rest, rest).ok());
    QVERIFY(anim.setKey(0.5, rest, bent).ok());
    QVERIFY(anim.setKey(1.0, rest, rest).ok());
    ClipLibrary lib;
    lib.keyframes.push_back({"bend", {anim}});
    Clip keyed{"k", ClipSource::Keyframes, "bend", 0.0, 24, 24.0, true, 0, std::nullopt};
    QVERIFY(lib.validate(scene).ok());
    auto played = evaluateClip(scene, lib, keyed);
    QVERIFY2(played.ok(), played.message().c_str());
    for (std::size_t i = 0; i < 24; ++i)  // a loop: the keys' tangents wrap round the 1 s cycle
        QVERIFY(played->nodes[i][0] == anim.pose(double(i) / 24.0, rest, 1.0));
    // Goals: physics follows the keys (and the driver) instead of copying them.
    keyed.goals = GoalSettings{50.0, 0.2, 1.0};
    auto simulated = evaluateClip(scene, lib, keyed);
    QVERIFY2(simulated.ok(), simulated.message().c_str());
    const std::size_t mid = 12;
    double keyedBend = 0.0, simBend = 0.0;
    const int tip = lattice.index(0, 2, 2);
    keyedBend = played->nodes[mid][0][std::size_t(tip)].z() - rest[std::size_t(tip)].z();
    simBend = simulated->nodes[mid][0][std::size_t(tip)].z() - rest[std::size_t(tip)].z();
    QVERIFY2(simBend > 0.3 * keyedBend && simBend != keyedBend, qPrintable(QString("%1 vs %2").arg(simBend).arg(keyedBend)));
    // A keyframe set for another lattice is refused.
    lib.keyframes[0].objects[0] = KeyframeAnimation(27);
    QVERIFY(!lib.validate(scene).ok());
    QVERIFY(!evaluateClip(scene, lib, keyed).ok());
}

// A goal clip's simulation starts before its first frame, so frame 0 shows the body already moving with the keys,
// not at rest snapping toward the first key: a one-shot clip of a bent first key opens settled in the bend, a
// looped one in the cycle's own stride, its seam an ordinary step.
void TestClip::goalClipsStartInStride() {
    Scene scene = swimmingBall();
    scene.objects[0].drivers.clear();  // the keys alone move it
    const Lattice& lattice = scene.objects[0].lattice;
    const std::vector<Vec3> rest = lattice.restNodes();
    const std::size_t tip = std::size_t(lattice.index(0, 2, 2));
    const auto bentBy = [&](double amount) {
        std::vector<Vec3> bent = rest;
        for (int n = 0; n < lattice.nodeCount(); ++n)
            bent[std::size_t(n)].z() += amount * (1.0 - lattice.restNodeParameters(n).x());
        return bent;
    };
    KeyframeAnimation oneShot(rest.size());
    QVERIFY(oneShot.setKey(0.0, rest, bentBy(0.2)).ok());
    QVERIFY(oneShot.setKey(1.0, rest, rest).ok());
    KeyframeAnimation cycle(rest.size());
    const double swing[] = {0.0, 0.2, 0.0, -0.2, 0.0};
    for (int k = 0; k < 5; ++k)
        QVERIFY(cycle.setKey(0.25 * k, rest, bentBy(swing[k])).ok());
    ClipLibrary lib;
    lib.keyframes.push_back({"once", {oneShot}});
    lib.keyframes.push_back({"cycle", {cycle}});
    const GoalSettings goals{200.0, 2.0, 1.0};
    const Clip once{"once", ClipSource::Keyframes, "once", 0.0, 12, 24.0, false, 0, goals};
    auto opened = evaluateClip(scene, lib, once);
    QVERIFY2(opened.ok(), opened.message().c_str());
    const double keyed = 0.2 * (1.0 - lattice.restNodeParameters(int(tip)).x());
    const double first = opened->nodes[0][0][tip].z() - rest[tip].z();
    const double step = (opened->nodes[1][0][tip] - opened->nodes[0][0][tip]).norm();
    QVERIFY2(first > 0.7 * keyed, qPrintable(QString("frame 0 at %1 of the keyed %2").arg(first).arg(keyed)));
    QVERIFY2(step < 0.1 * keyed, qPrintable(QString("first step %1").arg(step)));

    const Clip loop{"loop", ClipSource::Keyframes, "cycle", 0.0, 24, 24.0, true, 6, goals};
    auto looped = evaluateClip(scene, lib, loop);
    QVERIFY2(looped.ok(), looped.message().c_str());
    QCOMPARE(looped->nodes.size(), std::size_t(24));
    const SeamMeasure seam = measureSeam(looped.value());
    QVERIFY2(seam.ratio < 1.2 && seam.localRatio < 1.2, qPrintable(QString("%1 / %2").arg(seam.ratio).arg(seam.localRatio)));
    // Frame 0 is in stride: the tip is moving as it does a cycle later, not starting from rest.
    const double v0 = looped->nodes[1][0][tip].z() - looped->nodes[0][0][tip].z();
    const double vEnd = looped->nodes[0][0][tip].z() - looped->nodes[23][0][tip].z();
    QVERIFY2(std::abs(v0) > 0.5 * std::abs(vEnd) && v0 * vEnd > 0.0, qPrintable(QString("%1 vs %2").arg(v0).arg(vEnd)));
}

void TestClip::loopClosureByCrossFadeAndBySpreadingTheDrift() {
    const int n = 24, w = 6;
    // F_0..F_N of a drifting cycle, and the pre-roll G_{N-W}..G_N (the motion before F_0).
    std::vector<std::vector<Vec3>> open = circling(n + 1, n, 0.05);
    const std::vector<std::vector<Vec3>> preroll = [&] {
        auto g = circling(w, n, 0.05, -w);
        g.push_back(open.front());
        return g;
    }();
    auto unclosed = open;
    unclosed.pop_back();
    const double before = measureSeam(unclosed).ratio;
    QVERIFY2(before > 3.0, qPrintable(QString("%1").arg(before)));

    auto faded = open;
    closeLoop(faded, preroll, w);
    QCOMPARE(faded.size(), std::size_t(n));
    for (int i = 0; i <= n - w; ++i)
        QVERIFY(faded[std::size_t(i)] == open[std::size_t(i)]);
    // The blended frames run toward the pre-roll: the seam step is an ordinary step of the motion.
    const SeamMeasure fadedSeam = measureSeam(faded);
    QVERIFY2(fadedSeam.ratio < 1.2 && fadedSeam.localRatio < 1.2,
             qPrintable(QString("%1 / %2").arg(fadedSeam.ratio).arg(fadedSeam.localRatio)));

    auto spread = open;
    closeLoop(spread, {}, w);
    const SeamMeasure spreadSeam = measureSeam(spread);
    QVERIFY2(spreadSeam.ratio < 1.2, qPrintable(QString("%1").arg(spreadSeam.ratio)));
    // Window 0 only drops the repeated frame.
    auto none = open;
    closeLoop(none, {}, 0);
    QVERIFY(none == unclosed);
}

void TestClip::seamMeasureOfAPerfectCycle() {
    // Uniform circular motion: every step the same, the seam too.
    const auto cycle = circling(24, 24, 0.0);
    const SeamMeasure m = measureSeam(cycle);
    QVERIFY(std::abs(m.ratio - 1.0) < 1e-9);
    QVERIFY(std::abs(m.localRatio - 1.0) < 1e-9);
    QVERIFY(m.medianStep > 0.0);
}

void TestClip::badClipsAreRefused() {
    const Scene scene = swimmingBall();
    ClipLibrary lib;
    lib.clips.push_back(Clip{"a", ClipSource::Drivers, "", 0.0, 24, 24.0, false, 6, std::nullopt});
    QVERIFY(lib.validate(scene).message().find("blend window closes a loop") != std::string::npos);
    lib.clips[0] = Clip{"a", ClipSource::Session, "", 0.0, 24, 24.0, false, 0, std::nullopt};
    QVERIFY(lib.validate(scene).message().find("needs the name") != std::string::npos);
    lib.clips[0] = Clip{"a", ClipSource::Session, "missing", 0.0, 24, 24.0, false, 0, std::nullopt};
    QVERIFY(lib.validate(scene).message().find("no session named 'missing'") != std::string::npos);
    lib.clips[0] = Clip{"a", ClipSource::Drivers, "", 0.0, 24, 0.0, false, 0, std::nullopt};
    QVERIFY(lib.validate(scene).message().find("fps") != std::string::npos);
    lib.clips[0] = Clip{"a", ClipSource::Drivers, "", 0.0, 24, 24.0, false, 0, GoalSettings{}};
    QVERIFY(lib.validate(scene).message().find("keyframe clips only") != std::string::npos);
    lib.clips[0] = Clip{"a", ClipSource::Drivers, "", 0.0, 24, 24.0, true, 6, std::nullopt};
    lib.clips.push_back(lib.clips[0]);
    QVERIFY(lib.validate(scene).message().find("two clips are named 'a'") != std::string::npos);
    lib.clips.pop_back();
    QVERIFY(lib.validate(scene).ok());
}

QTEST_APPLESS_MAIN(TestClip)
#include "test_clip.moc"
