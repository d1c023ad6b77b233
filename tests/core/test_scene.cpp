// SceneSimulation as the editor and replays use it: interactive drags, snapshots, reset.
#include "core/scene.h"
#include "test_support.h"

#include <QtTest/QtTest>

using namespace softtouch;

namespace {

DragSpring pullUp(const SceneSimulation& sim, double height) {
    DragSpring drag;
    const Lattice& lattice = sim.object(0).lattice;
    drag.support = lattice.weights(Vec3(0.5, 1.0, 0.5));
    drag.target = lattice.evaluate(Vec3(0.5, 1.0, 0.5), lattice.restNodes()) + Vec3(0, height, 0);
    drag.stiffness = 500.0;
    return drag;
}

double topHeight(const SceneSimulation& sim) {
    const Lattice& lattice = sim.object(0).lattice;
    return lattice.evaluate(Vec3(0.5, 1.0, 0.5), sim.simulator(0).state().position).y();
}

}  // namespace

class TestScene : public QObject {
    Q_OBJECT
private slots:
    void interactiveDragMovesAndReleaseSwingsBack();
    void snapshotRestoreReplaysBitExactly();
    void resetReturnsToRest();
};

void TestScene::interactiveDragMovesAndReleaseSwingsBack() {
    auto created = SceneSimulation::create(test::anchoredBallScene());
    QVERIFY2(created.ok(), created.message().c_str());
    SceneSimulation& sim = created.value();
    const double rest = topHeight(sim);
    sim.setInteractiveDrags(0, {pullUp(sim, 0.3)});
    QCOMPARE(sim.forcesAt(0, 0.0).drags.size(), std::size_t(1));
    sim.advanceTo(1.0);
    const double pulled = topHeight(sim);
    QVERIFY2(pulled > rest + 0.05, qPrintable(QString("top moved %1 m").arg(pulled - rest)));
    sim.setInteractiveDrags(0, {});
    QVERIFY(sim.forcesAt(0, 1.0).drags.empty());
    sim.advanceTo(6.0);
    QVERIFY2(std::abs(topHeight(sim) - rest) < 0.2 * (pulled - rest),
             qPrintable(QString("still %1 m off rest").arg(topHeight(sim) - rest)));
}

void TestScene::snapshotRestoreReplaysBitExactly() {
    auto created = SceneSimulation::create(test::anchoredBallScene());
    QVERIFY(created.ok());
    SceneSimulation& sim = created.value();
    sim.setInteractiveDrags(0, {pullUp(sim, 0.2)});
    sim.advanceTo(0.25);
    const SceneSimulation::Snapshot mid = sim.saveSnapshot();
    QCOMPARE(mid.step, sim.stepCount());
    sim.advanceTo(0.75);
    const BodyState first = sim.simulator(0).state();
    const long long steps = sim.stepCount();
    sim.restoreSnapshot(mid);
    QCOMPARE(sim.stepCount(), mid.step);
    QCOMPARE(sim.time(), 0.25);
    sim.advanceTo(0.75);
    QCOMPARE(sim.stepCount(), steps);
    const BodyState& second = sim.simulator(0).state();
    for (std::size_t n = 0; n < first.position.size(); ++n) {
        QVERIFY(first.position[n] == second.position[n]);
        QVERIFY(first.velocity[n] == second.velocity[n]);
    }
}

void TestScene::resetReturnsToRest() {
    auto created = SceneSimulation::create(test::anchoredBallScene());
    QVERIFY(created.ok());
    SceneSimulation& sim = created.value();
    const std::vector<Vec3> rest = sim.object(0).lattice.restNodes();
    sim.setInteractiveDrags(0, {pullUp(sim, 0.2)});
    sim.advanceTo(0.5);
    QVERIFY(sim.simulator(0).state().position != rest);
    sim.reset();
    QCOMPARE(sim.stepCount(), 0LL);
    QVERIFY(sim.interactiveDrags(0).empty());
    QVERIFY(sim.simulator(0).state().position == rest);
}

QTEST_APPLESS_MAIN(TestScene)
#include "test_scene.moc"
