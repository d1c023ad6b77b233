// Lattice-pose keyframes: editing, Catmull-Rom interpolation, goal springs with follow-through.
#include "core/authoring/keyframes.h"
#include "helpers/test_support.h"

#include <QtTest/QtTest>

using namespace softtouch;

namespace {

Scene ballScene(bool pinBottom = true) {
    Scene scene;
    SceneObject object;
    object.name = "ball";
    object.mesh = test::makeSphere(0.5, Vec3::Zero(), 12, 24);
    object.lattice = Lattice::create(LatticeShape{}, fitBox(object.mesh->positions).value()).value();
    object.material = uniformMaterial(object.lattice, 0.01, 80.0, 0.1);
    for (int k = 0; k < object.lattice.count(2) && pinBottom; ++k)
        for (int i = 0; i < object.lattice.count(0); ++i)
            object.material.anchor[std::size_t(object.lattice.index(i, 0, k))] = AnchorMode::Pinned;
    scene.objects.push_back(std::move(object));
    return scene;
}

/// Nodes of layer j of a 4x4x4 lattice.
std::vector<std::uint32_t> layerNodes(const Lattice& lattice, int j) {
    std::vector<std::uint32_t> nodes;
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 4; ++i)
            nodes.push_back(std::uint32_t(lattice.index(i, j, k)));
    return nodes;
}

}  // namespace

class TestKeyframes : public QObject {
    Q_OBJECT
private slots:
    void interpolationPassesThroughKeysAndIsCubic();
    void subsetKeysMakePerNodeTracks();
    void eachKeySaysHowItMovesOnToTheNext();
    void aKeyedCycleWrapsItsTangents();
    void setMoveCopyDelete();
    void badKeysAreRefused();
    void goalSpringsFollowKeysWithFollowThrough();
};

void TestKeyframes::interpolationPassesThroughKeysAndIsCubic() {
    KeyframeAnimation anim(2);
    const std::vector<Vec3> rest{Vec3::Zero(), Vec3::UnitX()};
    // Node 0 moves at constant velocity (1, 2, 0) m/s through unevenly spaced keys; node 1 bends.
    const std::vector<double> times{0.0, 0.3, 1.0, 1.2};
    const std::vector<double> bend{0.0, 0.5, -0.2, 0.1};
    for (std::size_t k = 0; k < times.size(); ++k) {
        const std::vector<Vec3> pose{rest[0] + Vec3(1, 2, 0) * times[k], rest[1] + Vec3(0, 0, bend[k])};
        QVERIFY(anim.setKey(times[k], rest, pose).ok());
    }
    QCOMPARE(anim.keys().size(), times.size());
    std::vector<Vec3> d(2), v(2);
    for (std::size_t k = 0; k < times.size(); ++k) {
        anim.sample(times[k], d, v);
        QVERIFY((d[1] - Vec3(0, 0, bend[k])).norm() < 1e-12);
    }
    // Catmull-Rom reproduces constant velocity exactly (tangent = the common slope).
    for (double t = 0.0; t <= 1.2; t += 0.05) {
        anim.sample(t, d, v);
        QVERIFY2((d[0] - Vec3(1, 2, 0) * t).norm() < 1e-12, qPrintable(QString("t=%1").arg(t)));
        if (t > 1e-9 && t < 1.2 - 1e-9)  // held (zero velocity) outside the keys
            QVERIFY((v[0] - Vec3(1, 2, 0)).norm() < 1e-9);
    }
    // C1 at an inner key: derivative from both sides agree; value is continuous.
    Vec3 dl[2], vl[2], dr[2], vr[2];
    anim.sample(1.0 - 1e-7, dl, vl);
    anim.sample(1.0 + 1e-7, dr, vr);
    QVERIFY((vl[1] - vr[1]).norm() < 1e-4);
    // The velocity is the derivative of the value (finite difference inside a segment).
    anim.sample(0.6 - 1e-6, dl, vl);
    anim.sample(0.6 + 1e-6, dr, vr);
    anim.sample(0.6, d, v);
    QVERIFY(((dr[1] - dl[1]) / 2e-6 - v[1]).norm() < 1e-5);
    // Held outside the keys.
    anim.sample(-1.0, d, v);
    QVERIFY(d[0].norm() == 0.0 && v[0].norm() == 0.0);
    anim.sample(5.0, d, v);
    QVERIFY((d[1] - Vec3(0, 0, 0.1)).norm() < 1e-12 && v[1].norm() == 0.0);
}

void TestKeyframes::subsetKeysMakePerNodeTracks() {
    KeyframeAnimation anim(3);
    const std::vector<Vec3> rest(3, Vec3::Zero());
    const Vec3 up(0, 1, 0);
    QVERIFY(anim.setKey(0.0, rest, std::vector<Vec3>{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}, {0, 1}).ok());
    QVERIFY(anim.setKey(1.0, rest, std::vector<Vec3>{up, up, up}, {1}).ok());  // only node 1
    QVERIFY(anim.setKey(2.0, rest, std::vector<Vec3>{up * 2, up * 2, up * 2}, {0}).ok());  // only node 0
    std::vector<Vec3> d(3);
    std::vector<std::uint8_t> keyed;
    anim.sample(1.0, d, {}, &keyed);
    // Node 0's track has keys at 0 and 2 only: at t = 1 it is between them, not at node 1's key.
    QVERIFY(std::abs(d[0].y() - 1.0) < 1e-12);   // linear between two keys (one-sided tangents)
    QVERIFY(std::abs(d[1].y() - 1.0) < 1e-12);
    QVERIFY(d[2].norm() == 0.0);
    QCOMPARE(keyed, (std::vector<std::uint8_t>{1, 1, 0}));
    // Keying more nodes at an existing time merges into that key.
    QCOMPARE(anim.setKey(1.0, rest, std::vector<Vec3>{up * 5, up * 5, up * 5}, {2}).value(), std::size_t(1));
    QCOMPARE(anim.keys()[1].nodes, (std::vector<std::uint32_t>{1, 2}));
}

void TestKeyframes::eachKeySaysHowItMovesOnToTheNext() {
    // One node keyed at 0, 1, 2 and 3 s: heights 0, 1, 0, 1. Segment by segment: the first key constant (held, then
    // a snap at 1 s), the second linear, the third smooth.
    KeyframeAnimation anim(1);
    const std::vector<Vec3> rest{Vec3::Zero()};
    const std::vector<double> heights{0.0, 1.0, 0.0, 1.0};
    for (std::size_t k = 0; k < heights.size(); ++k)
        QVERIFY(anim.setKey(double(k), rest, std::vector<Vec3>{Vec3(0, heights[k], 0)}).ok());
    QCOMPARE(anim.keys()[0].interpolation, KeyInterpolation::Smooth);  // a new key is smooth
    QVERIFY(anim.setInterpolation(0, KeyInterpolation::Constant).ok());
    QVERIFY(anim.setInterpolation(1, KeyInterpolation::Linear).ok());
    QVERIFY(!anim.setInterpolation(4, KeyInterpolation::Linear).ok());
    std::vector<Vec3> d(1), v(1);
    for (double t : {0.0, 0.25, 0.5, 0.999}) {  // held at key 0's pose, not moving
        anim.sample(t, d, v);
        QCOMPARE(d[0].y(), 0.0);
        QCOMPARE(v[0].y(), 0.0);
    }
    anim.sample(1.0, d, v);
    QCOMPARE(d[0].y(), 1.0);  // the snap: key 1's pose on its time
    for (double t : {1.25, 1.5, 1.75}) {  // a straight line down at 1 m/s
        anim.sample(t, d, v);
        QVERIFY(std::abs(d[0].y() - (2.0 - t)) < 1e-12);
        QVERIFY(std::abs(v[0].y() + 1.0) < 1e-12);
    }
    // Smooth from key 2: through both ends, not the straight line (its tangent at key 2 comes from keys 1 and 3).
    anim.sample(2.5, d, v);
    QVERIFY2(std::abs(d[0].y() - 0.5) > 0.05, qPrintable(QString::number(d[0].y())));
    anim.sample(3.0, d, v);
    QCOMPARE(d[0].y(), 1.0);
    // Moving, copying and keying over a key keep its interpolation; the copy takes it along.
    QVERIFY(anim.moveKey(1, 1.1).ok());
    QCOMPARE(anim.keys()[1].interpolation, KeyInterpolation::Linear);
    QVERIFY(anim.copyKey(0, 5.0).ok());
    QCOMPARE(anim.keys().back().interpolation, KeyInterpolation::Constant);
    QVERIFY(anim.setKey(0.0, rest, std::vector<Vec3>{Vec3(0, 0.5, 0)}).ok());
    QCOMPARE(anim.keys()[0].interpolation, KeyInterpolation::Constant);
    // Names, both ways.
    for (KeyInterpolation k : {KeyInterpolation::Smooth, KeyInterpolation::Linear, KeyInterpolation::Constant})
        QCOMPARE(keyInterpolationNamed(keyInterpolationName(k)), std::optional<KeyInterpolation>(k));
    QVERIFY(!keyInterpolationNamed("bezier"));
}

// Keys that span exactly one cycle, the last the first pose again, as a looping clip plays them: given the cycle,
// the ends' tangents wrap round to the neighbouring pass, so the velocity carries across the loop's seam; without
// it they are one-sided and the velocity jumps there (here from 2.5 to 5 m/s).
void TestKeyframes::aKeyedCycleWrapsItsTangents() {
    KeyframeAnimation anim(1);
    const std::vector<Vec3> rest{Vec3::Zero()};
    const std::vector<std::pair<double, double>> keys{{0.0, 0.0}, {0.2, 1.0}, {0.6, -1.0}, {1.0, 0.0}};
    for (const auto& [t, height] : keys)
        QVERIFY(anim.setKey(t, rest, std::vector<Vec3>{Vec3(0, height, 0)}).ok());
    const auto velocity = [&](double t, double cycle) {
        std::vector<Vec3> d(1), v(1);
        anim.sample(t, d, v, nullptr, cycle);
        return v[0].y();
    };
    const double start = velocity(0.0, 1.0), end = velocity(1.0 - 1e-9, 1.0);
    QVERIFY2(std::abs(start - 2.0 / 0.6) < 1e-9, qPrintable(QString::number(start)));  // (1 - (-1)) / (0.2 + 0.4)
    QVERIFY2(std::abs(end - start) < 1e-6, qPrintable(QString("%1 vs %2").arg(end).arg(start)));
    QVERIFY(std::abs(velocity(0.0, 0.0) - 5.0) < 1e-9 && std::abs(velocity(1.0 - 1e-9, 0.0) - 2.5) < 1e-6);
    // Inside the cycle, and for keys that do not span it, nothing changes.
    QCOMPARE(velocity(0.4, 1.0), velocity(0.4, 0.0));
    QCOMPARE(velocity(0.0, 2.0), velocity(0.0, 0.0));
    // Every key is still passed through.
    for (const auto& [t, height] : keys)
        QCOMPARE(anim.pose(t, rest, 1.0)[0].y(), height);
}

void TestKeyframes::setMoveCopyDelete() {
    KeyframeAnimation anim(1);
    const std::vector<Vec3> rest{Vec3::Zero()};
    QVERIFY(anim.setKey(1.0, rest, std::vector<Vec3>{Vec3(1, 0, 0)}).ok());
    QVERIFY(anim.setKey(0.0, rest, std::vector<Vec3>{Vec3(0, 0, 0)}).ok());
    QCOMPARE(anim.keys().front().seconds, 0.0);  // kept in time order
    // Move the 1 s key to 2 s: the interpolation stretches.
    QCOMPARE(anim.moveKey(1, 2.0).value(), std::size_t(1));
    std::vector<Vec3> d(1);
    anim.sample(1.0, d);
    QVERIFY(std::abs(d[0].x() - 0.5) < 1e-12);
    // Moving onto another key is refused and changes nothing.
    QVERIFY(!anim.moveKey(0, 2.0).ok());
    QCOMPARE(anim.keys().size(), std::size_t(2));
    // Copy the 2 s key to 3 s, then the rest key to 4 s: a hold then a return.
    QCOMPARE(anim.copyKey(1, 3.0).value(), std::size_t(2));
    QCOMPARE(anim.copyKey(0, 4.0).value(), std::size_t(3));
    anim.sample(3.0, d);
    QCOMPARE(d[0].x(), 1.0);
    anim.sample(4.0, d);
    QCOMPARE(d[0].x(), 0.0);
    QVERIFY(anim.deleteKey(3).ok());
    QVERIFY(!anim.deleteKey(3).ok());
    QCOMPARE(anim.keys().size(), std::size_t(3));
    QCOMPARE(anim.keyAt(3.0), 2LL);
    QCOMPARE(anim.keyAt(3.5), -1LL);
}

void TestKeyframes::badKeysAreRefused() {
    KeyframeAnimation anim(4);
    const std::vector<Vec3> rest(4, Vec3::Zero());
    auto r = anim.setKey(0.0, rest, std::vector<Vec3>(3, Vec3::Zero()));
    QVERIFY(!r.ok());
    QVERIFY2(r.message().find("3 nodes") != std::string::npos, r.message().c_str());
    QVERIFY(!anim.setKey(0.0, rest, rest, {7}).ok());
    QVERIFY(!anim.insertKey(LatticeKey{std::nan(""), {0}, {Vec3::Zero()}}).ok());
    QVERIFY(!anim.insertKey(LatticeKey{0.0, {1, 1}, {Vec3::Zero(), Vec3::Zero()}}).ok());
    QVERIFY(!anim.insertKey(LatticeKey{0.0, {1}, {Vec3(std::numeric_limits<double>::infinity(), 0, 0)}}).ok());
    QVERIFY(anim.keys().empty());
}

void TestKeyframes::goalSpringsFollowKeysWithFollowThrough() {
    // A free ball whose top layer is keyed: the keys carry it 0.3 m sideways in 0.4 s and stop.
    auto created = SceneSimulation::create(ballScene(false));
    QVERIFY2(created.ok(), created.message().c_str());
    SceneSimulation& sim = created.value();
    const Lattice& lattice = sim.object(0).lattice;
    const std::vector<Vec3> rest = lattice.restNodes();
    const std::vector<std::uint32_t> top = layerNodes(lattice, 3), bottom = layerNodes(lattice, 0);
    KeyframeAnimation anim(rest.size());
    std::vector<Vec3> moved = rest;
    for (Vec3& p : moved)
        p += Vec3(0.3, 0, 0);
    QVERIFY(anim.setKey(0.0, rest, rest, top).ok());
    QVERIFY(anim.setKey(0.4, rest, moved, top).ok());

    auto player = GoalPlayer::create(sim, 0, anim, GoalSettings{40.0, 0.05, 1.0});
    QVERIFY2(player.ok(), player.message().c_str());
    auto shift = [&](const std::vector<std::uint32_t>& nodes) {
        double x = 0.0;
        for (std::uint32_t n : nodes)
            x += sim.simulator(0).state().position[n].x() - rest[n].x();
        return x / double(nodes.size());
    };
    double peak = 0.0, lag = 0.0;
    for (int f = 1; f <= 96; ++f) {
        player->advanceTo(sim, f / 48.0);
        if (f == 6)  // 0.125 s: the keys are moving
            lag = shift(top) - shift(bottom);
        peak = std::max(peak, shift(bottom));
    }
    // The unkeyed bottom lags behind the keyed top while the keys move, then swings past the stop: follow-through that
    // the keys alone (which hold at 0.3 m) cannot show.
    QVERIFY2(lag > 0.03, qPrintable(QString("bottom lag %1 m").arg(lag)));
    QVERIFY2(peak > 0.3 * 1.05, qPrintable(QString("bottom peak %1 m, key 0.3 m").arg(peak)));
    // ... and the body settles onto the keyed pose.
    player->advanceTo(sim, 8.0);
    QVERIFY2(std::abs(shift(top) - 0.3) < 0.01 && std::abs(shift(bottom) - 0.3) < 0.01,
             qPrintable(QString("settled at %1 / %2 m").arg(shift(top)).arg(shift(bottom))));

    // Weight 0: no goals, the body stays at rest.
    sim.reset();
    auto off = GoalPlayer::create(sim, 0, anim, GoalSettings{40.0, 0.05, 0.0});
    QVERIFY(off.ok());
    off->advanceTo(sim, 1.0);
    QVERIFY(std::abs(shift(top)) < 1e-9);
    // A mismatched lattice is refused.
    KeyframeAnimation wrong(27);
    QVERIFY(!GoalPlayer::create(sim, 0, wrong, GoalSettings{}).ok());
}

QTEST_APPLESS_MAIN(TestKeyframes)
#include "test_keyframes.moc"
