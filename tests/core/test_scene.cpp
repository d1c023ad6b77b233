// SceneSimulation as the editor and replays use it: interactive drags, snapshots, reset; and the
// settings a new scene starts with.
#include "core/geometry/primitives.h"
#include "core/modes/mode_accuracy.h"
#include "core/modes/modes.h"
#include "core/scene/scene.h"
#include "helpers/test_support.h"

#include <QtTest/QtTest>

#include <numbers>

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

/// A paint stroke: every other node three times stiffer.
void stiffenEveryOtherNode(LatticeMaterial& m) {
    for (std::size_t n = 0; n < m.stiffness.size(); n += 2)
        m.stiffness[n] *= 3.0;
}

}  // namespace

class TestScene : public QObject {
    Q_OBJECT
private slots:
    void interactiveDragMovesAndReleaseSwingsBack();
    void snapshotRestoreReplaysBitExactly();
    void resetReturnsToRest();
    void editsKeepTheBindingAndMoveAsAFreshBuild();
    void editOfOneObjectRebuildsThatOneAlone();
    void newSceneKeepsItsWobble_data();
    void newSceneKeepsItsWobble();
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

// The editor's incremental rebuild: a material or world edit keeps the binding and the mesh's samples (the
// same objects, not copies), and the body it builds moves bit for bit as one built from nothing; a lattice
// edit makes a new binding.
void TestScene::editsKeepTheBindingAndMoveAsAFreshBuild() {
    Scene scene = test::anchoredBallScene();
    std::fill(scene.objects[0].material.volumePreservation.begin(), scene.objects[0].material.volumePreservation.end(), 0.5);
    auto first = SceneSimulation::create(scene);
    QVERIFY2(first.ok(), first.message().c_str());

    // A paint stroke: a stiffer half; and a world edit: gravity.
    Scene edited = scene;
    stiffenEveryOtherNode(edited.objects[0].material);
    edited.world.gravity = Vec3(0, -9.81, 0);
    auto kept = SceneSimulation::create(edited, &first.value());
    auto fresh = SceneSimulation::create(edited);
    QVERIFY(kept.ok() && fresh.ok());
    QCOMPARE(&kept.value().binding(0), &first.value().binding(0));
    QVERIFY(&fresh.value().binding(0) != &first.value().binding(0));
    // The copies share one mesh (a pointer, not its vertices), and the rebuilt body the contact samples.
    QVERIFY(edited.objects[0].mesh.sameAs(scene.objects[0].mesh));
    QVERIFY(kept.value().object(0).mesh.sameAs(scene.objects[0].mesh));
    QVERIFY(kept.value().simulator(0).model().contactPoints != nullptr);
    QCOMPARE(kept.value().simulator(0).model().contactPoints, first.value().simulator(0).model().contactPoints);
    // A mesh made again with the same values (a reload) is the same geometry: compared by value.
    Scene reloaded = edited;
    reloaded.objects[0].mesh = Mesh(*scene.objects[0].mesh);
    QVERIFY(!reloaded.objects[0].mesh.sameAs(scene.objects[0].mesh));
    auto again = SceneSimulation::create(reloaded, &first.value());
    QVERIFY(again.ok());
    QCOMPARE(&again.value().binding(0), &first.value().binding(0));
    for (SceneSimulation* sim : {&kept.value(), &fresh.value()}) {
        sim->setInteractiveDrags(0, {pullUp(*sim, 0.2)});
        sim->advanceTo(0.5);
    }
    const BodyState& a = kept.value().simulator(0).state();
    const BodyState& b = fresh.value().simulator(0).state();
    QVERIFY(a.position != first.value().simulator(0).state().position);  // it moved
    for (std::size_t n = 0; n < a.position.size(); ++n)
        QVERIFY2(a.position[n] == b.position[n] && a.velocity[n] == b.velocity[n], qPrintable(QString("node %1").arg(n)));

    // Another lattice: a binding of its own.
    Scene refined = edited;
    SceneObject& o = refined.objects[0];
    const Lattice finer = Lattice::create({LatticeKind::Bezier, {5, 5, 5}}, o.lattice.box()).value();
    o.material = resampleMaterial(o.lattice, o.material, finer, true);
    o.lattice = finer;
    auto rebuilt = SceneSimulation::create(refined, &kept.value());
    QVERIFY2(rebuilt.ok(), rebuilt.message().c_str());
    QVERIFY(&rebuilt.value().binding(0) != &kept.value().binding(0));
    QCOMPARE(rebuilt.value().simulator(0).state().position.size(), std::size_t(125));
}

// A paint dab on one object of two rebuilds that object alone: the other keeps its body (the same model, not a
// copy). The edited one here follows a base animation, whose lattice fit of the mesh depends on mesh and lattice
// only and is kept too; both move bit for bit as a simulation built from nothing.
void TestScene::editOfOneObjectRebuildsThatOneAlone() {
    Scene scene = test::anchoredBallScene();
    scene.world.bodyCollisions.enabled = false;
    SceneObject swaying = scene.objects[0];
    swaying.name = "swaying";
    auto animation = std::make_shared<BaseAnimation>();
    animation->rate = 60.0;
    for (int k = 0; k < 30; ++k) {
        std::vector<Vec3f> sample = swaying.mesh->positions;
        const float dx = float(0.05 * std::sin(2.0 * std::numbers::pi * k / 30.0));
        for (Vec3f& p : sample)
            p.x() += dx;
        animation->samples.push_back(std::move(sample));
    }
    swaying.baseAnimation = animation;
    swaying.material.goalWeight.assign(swaying.material.mass.size(), 0.5);
    scene.objects.push_back(swaying);
    auto first = SceneSimulation::create(scene);
    QVERIFY2(first.ok(), first.message().c_str());

    Scene edited = scene;
    stiffenEveryOtherNode(edited.objects[1].material);
    auto kept = SceneSimulation::create(edited, &first.value());
    auto fresh = SceneSimulation::create(edited);
    QVERIFY(kept.ok() && fresh.ok());
    QCOMPARE(kept->simulator(0).sharedModel(), first->simulator(0).sharedModel());  // untouched: kept
    QVERIFY(kept->simulator(1).sharedModel() != first->simulator(1).sharedModel());  // painted: rebuilt
    QVERIFY(fresh->simulator(0).sharedModel() != first->simulator(0).sharedModel());
    for (SceneSimulation* sim : {&kept.value(), &fresh.value()}) {
        sim->setInteractiveDrags(0, {pullUp(*sim, 0.2)});
        sim->advanceTo(0.5);
    }
    for (std::size_t i = 0; i < 2; ++i) {
        const BodyState& a = kept->simulator(i).state();
        const BodyState& b = fresh->simulator(i).state();
        QVERIFY(a.position != first->simulator(i).state().position);  // it moved
        for (std::size_t n = 0; n < a.position.size(); ++n)
            QVERIFY2(a.position[n] == b.position[n] && a.velocity[n] == b.velocity[n],
                     qPrintable(QString("object %1, node %2").arg(i).arg(n)));
    }
    // A world edit keeps both bodies and builds their simulators anew.
    Scene gravity = edited;
    gravity.world.gravity = Vec3(0, -9.81, 0);
    auto again = SceneSimulation::create(gravity, &kept.value());
    QVERIFY(again.ok());
    for (std::size_t i = 0; i < 2; ++i)
        QCOMPARE(again->simulator(i).sharedModel(), kept->simulator(i).sharedModel());
}

void TestScene::newSceneKeepsItsWobble_data() {
    QTest::addColumn<Vec3>("radii");  // of the imported mesh, an ellipsoid, metres
    QTest::addColumn<int>("integrator");
    QTest::addColumn<double>("minKept");  // of the material's own per-period amplitude
    QTest::newRow("fish-sized, 30 cm") << Vec3(0.15, 0.10, 0.03) << int(IntegratorKind::Verlet) << 0.99;
    QTest::newRow("1 m ball") << Vec3(0.5, 0.5, 0.5) << int(IntegratorKind::Verlet) << 0.99;
    // Small bodies of the same material are heavily damped (spring viscosity's ζ grows with ω): the
    // 10 cm ball's lowest mode (ζ 0.57) keeps only 1.2% a period itself, and Verlet, whose spring damping
    // takes the backward velocity (first order in h), keeps 85% of that; implicit Euler 55%.
    QTest::newRow("10 cm ball") << Vec3(0.05, 0.05, 0.05) << int(IntegratorKind::Verlet) << 0.8;
    // Stability demands otherwise: a 2 cm pebble would need more than kNewSceneMaxSubsteps Verlet
    // substeps a step (its lowest mode is overdamped anyway).
    QTest::newRow("2 cm pebble") << Vec3(0.01, 0.008, 0.006) << int(IntegratorKind::ImplicitEuler) << 0.0;
}

// A new scene (the editor's Import Mesh) starts on the scheme that keeps its wobble: at its default step
// the lowest mode keeps >= 99% of what the material alone keeps per period (core/modes/mode_accuracy), where
// implicit Euler at the same step keeps visibly less; only a body too stiff for an explicit step falls
// back to implicit Euler. (test_io_project newProjectKeepsItsWobble does the same on the angelfish mesh.)
void TestScene::newSceneKeepsItsWobble() {
    QFETCH(Vec3, radii);
    QFETCH(int, integrator);
    QFETCH(double, minKept);
    auto scene = newScene("blob", makeUvEllipsoid(12, 24, radii));
    QVERIFY2(scene.ok(), scene.message().c_str());
    const SimulationSettings& settings = scene->world.simulation;
    QCOMPARE(settings.dt, 1.0 / 240.0);
    auto body = buildLatticeBody(scene->objects[0].lattice, scene->objects[0].material);
    QVERIFY(body.ok());
    const VibrationMode mode = analyseModes(*body.value(), 1).value().modes.front();
    const ModeAccuracy accuracy = schemeAccuracy(body.value(), settings, mode);
    SimulationSettings implicit = settings;
    implicit.integrator = IntegratorKind::ImplicitEuler;
    const ModeAccuracy implicitAccuracy = schemeAccuracy(body.value(), implicit, mode);
    const double kept = accuracy.amplitudePerPeriod / accuracy.exactAmplitudePerPeriod;
    const double implicitKept = implicitAccuracy.amplitudePerPeriod / implicitAccuracy.exactAmplitudePerPeriod;
    SimulationSettings verlet = settings;
    verlet.integrator = IntegratorKind::Verlet;
    const int substeps = Simulator(body.value(), verlet).substepsFor({});
    qInfo("%s: %s; Verlet takes %d substeps a step; the lowest mode (%.3f Hz, ζ %.3f) keeps %.2f%% of the "
          "material's per-period amplitude (%.1f%% of %.1f%%), implicit Euler would keep %.2f%%",
          QTest::currentDataTag(), std::string(integratorName(settings.integrator)).c_str(), substeps,
          mode.frequencyHz, mode.dampingRatio, 100.0 * kept, 100.0 * accuracy.amplitudePerPeriod,
          100.0 * accuracy.exactAmplitudePerPeriod, 100.0 * implicitKept);
    QCOMPARE(int(settings.integrator), integrator);
    QCOMPARE(substeps > kNewSceneMaxSubsteps, settings.integrator == IntegratorKind::ImplicitEuler);
    if (settings.integrator == IntegratorKind::Verlet) {
        QVERIFY(kept >= minKept);
        QVERIFY(implicitKept < kept - 0.05);
        QVERIFY(kept <= 1.0 + 1e-3);  // and adds no energy
    }
}

QTEST_APPLESS_MAIN(TestScene)
#include "test_scene.moc"
