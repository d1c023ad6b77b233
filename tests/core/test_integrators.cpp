// The integrator table (core/solver/integrator.h, kIntegrators): every list of schemes in the program iterates it, so
// each row must say what its scheme does. A kind added to the enum without a row does not build (integrator.cpp);
// a row that says the wrong thing about its scheme fails here.

#include "core/body/lattice_body.h"
#include "core/geometry/primitives.h"
#include "core/scene/scene.h"
#include "core/solver/integrator.h"
#include "core/solver/simulator.h"

#include <QtTest>

#include <set>

using namespace softtouch;

class TestIntegrators : public QObject {
    Q_OBJECT
private slots:
    void everyRowNamesItsScheme();
    void explicitRowsAreTheOnesThatSubstep();
    void elementRowsAreTheOnesASceneRuns();
};

// Names, labels and short labels are unique and not empty; a name parses back to its kind; the scheme a row
// makes is that kind and says it is explicit exactly when the row does.
void TestIntegrators::everyRowNamesItsScheme() {
    std::set<std::string_view> names, labels, shortLabels;
    for (const IntegratorInfo& row : kIntegrators) {
        QVERIFY(!row.name.empty() && !row.label.empty() && !row.shortLabel.empty());
        QVERIFY2(names.insert(row.name).second && labels.insert(row.label).second && shortLabels.insert(row.shortLabel).second,
                 row.name.data());
        QCOMPARE(parseIntegratorKind(row.name), std::optional(row.kind));
        QCOMPARE(&integratorInfo(row.kind), &row);
        QCOMPARE(integratorName(row.kind), row.name);
        const auto scheme = makeIntegrator(row.kind);
        QCOMPARE(scheme->kind(), row.kind);
        QCOMPARE(scheme->isExplicit(), row.isExplicit);
    }
    QCOMPARE(parseIntegratorKind("euler"), std::nullopt);
}

// A stiff body at a coarse step: the explicit schemes take many substeps a step under their bound, implicit
// Euler one, and XPBD its own fixed count whatever the stiffness.
void TestIntegrators::explicitRowsAreTheOnesThatSubstep() {
    const Lattice lattice = Lattice::create({}, OrientedBox{}).value();
    LatticeMaterial material = uniformMaterial(lattice, 0.01, 1e5, 0.0);
    material.anchor[0] = AnchorMode::Pinned;
    const auto body = buildLatticeBody(lattice, material).value();
    for (const IntegratorInfo& row : kIntegrators) {
        SimulationSettings settings;
        settings.integrator = row.kind;
        settings.dt = 1.0 / 24;
        const Simulator sim(body, settings);
        const int substeps = sim.substepsFor({});
        if (row.isExplicit)
            QVERIFY2(substeps > 10, qPrintable(QString("%1: %2 substeps").arg(row.name.data()).arg(substeps)));
        else
            QVERIFY2(substeps == (row.kind == IntegratorKind::Xpbd ? settings.xpbdSubsteps : 1),
                     qPrintable(QString("%1: %2 substeps").arg(row.name.data()).arg(substeps)));
    }
}

// A scene whose object runs the solid element starts with every scheme whose row says it runs the element and
// is refused with every other, naming the schemes that would.
void TestIntegrators::elementRowsAreTheOnesASceneRuns() {
    Scene scene = newScene("ellipsoid", makeUvEllipsoid(12, 16, Vec3(0.3, 0.2, 0.06))).value();
    const Lattice& lattice = scene.objects[0].lattice;
    LatticeMaterial material = continuumMaterial(lattice, 1.0, 1000.0, 0.0);
    for (int i = 0; i < lattice.nodeCount(); ++i)
        if (lattice.restNodeParameters(i).x() >= 0.9)
            material.anchor[std::size_t(i)] = AnchorMode::Pinned;
    material.element = BodyElement::Solid;
    scene.objects[0].material = material;
    int running = 0;
    for (const IntegratorInfo& row : kIntegrators) {
        scene.world.simulation.integrator = row.kind;
        const auto sim = SceneSimulation::create(scene);
        QCOMPARE(bool(sim), row.runsElement);
        running += row.runsElement;
        if (!row.runsElement)
            for (const IntegratorInfo& other : kIntegrators) {
                const QString quoted = QString("\"%1\"").arg(other.name.data());
                QVERIFY2(QString::fromStdString(sim.message()).contains(quoted) == other.runsElement, sim.message().c_str());
            }
    }
    QVERIFY(running > 0);
}

QTEST_GUILESS_MAIN(TestIntegrators)
#include "test_integrators.moc"
