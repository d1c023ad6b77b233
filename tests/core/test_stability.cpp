// Guards at the extremes: stiff springs, tiny masses, big steps, injected NaN, sleeping.
#include "physics_fixture.h"

using namespace softtouch;
using namespace softtouch::test;

namespace {

/// Largest node distance from rest.
double maxExcursion(const BodyModel& model, const BodyState& state) {
    double worst = 0.0;
    for (std::size_t i = 0; i < model.nodeCount(); ++i) {
        const double d = (state.position[i] - model.restPositions[i]).norm();
        if (!std::isfinite(d))
            return std::numeric_limits<double>::infinity();
        worst = std::max(worst, d);
    }
    return worst;
}

/// Gravity plus a drag on the body's far corner (so the stiff body is really loaded).
ExternalForces loadFor(const BodyModel& model) {
    ExternalForces f;
    f.gravity = Vec3(0, -9.81, 0);
    DragSpring drag;
    const auto last = std::uint32_t(model.nodeCount() - 1);
    drag.support = {{last, 1.0}};
    drag.target = model.restPositions[last] + Vec3(0.2, 0.3, 0.0);
    drag.stiffness = 50.0;
    drag.damping = 0.5;
    f.drags.push_back(drag);
    return f;
}

std::shared_ptr<const BodyModel> anchoredBody(double mass, double stiffness) {
    return latticeBody({4, 4, 4}, mass, stiffness, 0.0, [](const Lattice& l, LatticeMaterial& m) {
        for (int k = 0; k < 4; ++k)
            for (int j = 0; j < 4; ++j)
                m.anchor[std::size_t(l.index(0, j, k))] = AnchorMode::Pinned;
    });
}

}  // namespace

class TestStability : public QObject {
    Q_OBJECT
private slots:
    void energyGuardKeepsUndampedBodiesBounded_data();
    void energyGuardKeepsUndampedBodiesBounded();
    void implicitEulerStiffAndLight_data();
    void implicitEulerStiffAndLight();
    void explicitSchemesSubstep_data();
    void explicitSchemesSubstep();
    void stableStepMatchesLatticeTheory();
    void injectedNaNIsRolledBack();
    void tooManySubstepsIsRefusedWithAFix();
    void sleepingBodyCostsNothingUntilTouched();
    void saveRestoreRoundTrip();
};

void TestStability::implicitEulerStiffAndLight_data() {
    QTest::addColumn<double>("stiffness");
    QTest::addColumn<double>("mass");
    for (double k : {1e2, 1e4, 1e6})
        for (double m : {1e-4, 1e-2, 1.0})
            QTest::newRow(qPrintable(QString("k=%1 m=%2").arg(k).arg(m))) << k << m;
}

void TestStability::implicitEulerStiffAndLight() {
    QFETCH(double, stiffness);
    QFETCH(double, mass);
    auto body = anchoredBody(mass, stiffness);
    Simulator sim(body, settingsFor(IntegratorKind::ImplicitEuler, 1.0 / 24.0));
    const ExternalForces f = loadFor(*body);
    for (int i = 0; i < 96; ++i) {
        const StepReport r = sim.step(f);
        QVERIFY2(r.problem.empty(), r.problem.c_str());
        QCOMPARE(r.substeps, 1);
        QVERIFY(sim.state().isFinite());
        QVERIFY2(maxExcursion(*body, sim.state()) < 10.0, qPrintable(QString::number(maxExcursion(*body, sim.state()))));
    }
}

void TestStability::explicitSchemesSubstep_data() {
    QTest::addColumn<int>("integrator");
    QTest::addColumn<double>("stiffness");
    for (IntegratorKind kind : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::Xpbd})
        for (double k : {1e2, 1e6})
            QTest::newRow(qPrintable(QString("%1 k=%2").arg(QString::fromLatin1(integratorName(kind).data())).arg(k)))
                << int(kind) << k;
}

void TestStability::explicitSchemesSubstep() {
    QFETCH(int, integrator);
    QFETCH(double, stiffness);
    const double mass = 1e-4;
    auto body = anchoredBody(mass, stiffness);
    Simulator sim(body, settingsFor(IntegratorKind(integrator), 1.0 / 24.0));
    const ExternalForces f = loadFor(*body);
    const int substeps = sim.substepsFor(f);
    if (IntegratorKind(integrator) != IntegratorKind::Xpbd) {
        // The guard picks h below 2/omega_max: at least dt / (0.54 sqrt(m/k)) substeps.
        QVERIFY(substeps >= int((1.0 / 24.0) / (0.6 * std::sqrt(mass / stiffness))));
    }
    for (int i = 0; i < 24; ++i) {
        const StepReport r = sim.step(f);
        QVERIFY2(r.problem.empty(), r.problem.c_str());
        QVERIFY(sim.state().isFinite());
        QVERIFY2(maxExcursion(*body, sim.state()) < 10.0, qPrintable(QString::number(maxExcursion(*body, sim.state()))));
    }
}

void TestStability::stableStepMatchesLatticeTheory() {
    // The rule of thumb for a 4x4x4 lattice with equal k and m: about 0.54 sqrt(m/k).
    const double k = 80.0, m = 0.0002;
    auto body = latticeBody({4, 4, 4}, m, k, 0.0);
    SimulationSettings s = settingsFor(IntegratorKind::SymplecticEuler, 1.0 / 60.0);
    s.stabilitySafety = 1.0;
    Simulator sim(body, s);
    const double bound = sim.stableStep({});
    const double rule = 0.54 * std::sqrt(m / k);
    QVERIFY2(std::abs(bound - rule) < 0.1 * rule, qPrintable(QString("bound %1 vs %2").arg(bound).arg(rule)));
    // And it is a real bound: at 0.9x the body stays bounded, at 1.3x it blows up.
    for (double factor : {0.9, 1.3}) {
        SimulationSettings t = settingsFor(IntegratorKind::SymplecticEuler, factor * bound);
        t.maxSubsteps = 1;  // no substepping: test the raw scheme
        t.stabilitySafety = 1.0;
        Simulator raw(body, t);
        BodyState st = raw.saveState();
        for (std::size_t i = 0; i < st.position.size(); ++i)
            st.position[i] += 1e-3 * Vec3(std::sin(1.0 * i), std::cos(2.0 * i), std::sin(3.0 * i));
        raw.restoreState(st);
        // Bypass the guard by stepping the integrator directly.
        auto integrator = makeIntegrator(IntegratorKind::SymplecticEuler);
        BodyState state = raw.saveState();
        for (int i = 0; i < 4000; ++i)
            integrator->step(*body, {}, state, factor * bound);
        const double excursion = maxExcursion(*body, state);
        if (factor < 1.0)
            QVERIFY2(excursion < 0.1, qPrintable(QString("stable run moved %1").arg(excursion)));
        else
            QVERIFY2(!(excursion < 1.0), qPrintable(QString("unstable run only moved %1").arg(excursion)));
    }
}

void TestStability::energyGuardKeepsUndampedBodiesBounded_data() {
    QTest::addColumn<int>("integrator");
    for (IntegratorKind kind : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet})
        QTest::newRow(integratorName(kind).data()) << int(kind);
}

// No damping, every node displaced at random by up to 5% of the body's size, the default step, ten
// simulated minutes. The schemes nearly conserve the modified energy H̃ = E + (h/2) vᵀf (the guard's
// account; exactly for linear springs): it stays within the guard's 5% tolerance, so the guard does
// not fire on a body that gains nothing. The
// plain energy E swings (bounded) in the stiffest modes; its worst swing is printed for the docs.
void TestStability::energyGuardKeepsUndampedBodiesBounded() {
    QFETCH(int, integrator);
    auto body = latticeBody({4, 4, 4}, 0.02, 80, 0.0);
    const SimulationSettings settings = settingsFor(IntegratorKind(integrator), 1.0 / 240.0);
    Simulator sim(body, settings);
    BodyState s = sim.saveState();
    unsigned seed = 7;
    auto random = [&] { seed = seed * 1664525u + 1013904223u; return double(seed >> 8) / double(1u << 24) - 0.5; };
    for (Vec3& p : s.position)
        p += 2.0 * 0.05 * Vec3(random(), random(), random());  // unit cube: ±5% of its size
    sim.restoreState(s);
    const double h = settings.dt / sim.substepsFor({});
    std::vector<Vec3> force(body->nodeCount());
    const std::vector<Vec3> still(body->nodeCount(), Vec3::Zero());
    SpringScratch scratch;
    auto modified = [&] {
        accumulateForces(*body, {}, sim.state().position, still, force, scratch);
        double vf = 0.0;
        for (std::size_t i = 0; i < force.size(); ++i)
            vf += body->inverseMass[i] > 0.0 ? sim.state().velocity[i].dot(force[i]) : 0.0;
        return kineticEnergy(*body, sim.state()) + springEnergy(*body, sim.state()) + 0.5 * h * vf;
    };
    const double e0 = kineticEnergy(*body, sim.state()) + springEnergy(*body, sim.state());
    const double m0 = modified();
    double worstPlain = 0.0, worstModified = 0.0;
    for (int i = 0; i < 240 * 600; ++i) {
        const StepReport r = sim.step({});
        QVERIFY2(r.problem.empty(), r.problem.c_str());
        worstPlain = std::max(worstPlain, std::abs((kineticEnergy(*body, sim.state()) + springEnergy(*body, sim.state())) / e0 - 1.0));
        worstModified = std::max(worstModified, std::abs(modified() / m0 - 1.0));
    }
    qInfo("%s: modified energy within %.3g%%, plain energy swings up to %.3g%% over 10 min", QTest::currentDataTag(),
          100.0 * worstModified, 100.0 * worstPlain);
    QVERIFY(worstModified < settings.energyTolerance);
    QVERIFY(worstPlain < 0.5);  // bounded: no growth
}

void TestStability::injectedNaNIsRolledBack() {
    for (IntegratorKind kind : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                                IntegratorKind::Xpbd}) {
        auto body = latticeBody({3, 3, 3}, 0.01, 80, 0.1);
        SimulationSettings settings = settingsFor(kind, 1.0 / 60.0);
        settings.energyCheckSteps = 1;  // every step is checked, so the step before is the known-good state
        Simulator sim(body, settings);
        ExternalForces f = loadFor(*body);
        for (int i = 0; i < 10; ++i)
            QVERIFY(sim.step(f).problem.empty());
        const BodyState before = sim.saveState();
        f.drags[0].target.x() = std::numeric_limits<double>::quiet_NaN();
        const StepReport r = sim.step(f);
        QVERIFY(r.rolledBack);
        QVERIFY2(r.problem.find("drag 0") != std::string::npos, r.problem.c_str());
        QVERIFY(sim.state().isFinite());
        QCOMPARE(sim.state().position, before.position);
        QCOMPARE(sim.state().velocity, before.velocity);
        // And it carries on once the input is sane again.
        f.drags[0].target.x() = 1.0;
        QVERIFY(sim.step(f).problem.empty());
    }
}

void TestStability::tooManySubstepsIsRefusedWithAFix() {
    auto body = latticeBody({4, 4, 4}, 1e-6, 1e7, 0.0);
    SimulationSettings s = settingsFor(IntegratorKind::SymplecticEuler, 1.0 / 24.0);
    s.maxSubsteps = 1000;
    Simulator sim(body, s);
    const StepReport r = sim.step(loadFor(*body));
    QCOMPARE(r.substeps, 0);
    QVERIFY2(r.problem.find("implicit-euler") != std::string::npos, r.problem.c_str());
    QVERIFY(sim.state().isFinite());
}

void TestStability::sleepingBodyCostsNothingUntilTouched() {
    auto body = latticeBody({4, 4, 4}, 0.01, 80, 0.5);
    SimulationSettings s = settingsFor(IntegratorKind::ImplicitEuler, 1.0 / 60.0);
    s.sleep = true;
    Simulator sim(body, s);
    ExternalForces none;
    int asleepAt = -1;
    for (int i = 0; i < 200 && asleepAt < 0; ++i) {
        if (sim.step(none).sleeping)
            asleepAt = i;
    }
    QVERIFY(asleepAt >= 0);
    const StepReport quiet = sim.step(none);
    QVERIFY(quiet.sleeping);
    QCOMPARE(quiet.substeps, 0);
    // A drag wakes it and it moves.
    ExternalForces touch = loadFor(*body);
    touch.gravity.setZero();
    const StepReport woken = sim.step(touch);
    QVERIFY(!woken.sleeping);
    QCOMPARE(woken.substeps, 1);
    QVERIFY(maxExcursion(*body, sim.state()) > 0.0);
}

void TestStability::saveRestoreRoundTrip() {
    // Restoring a saved state and replaying the same inputs reproduces the run bit for bit.
    auto body = latticeBody({4, 4, 4}, 0.01, 80, 0.5);
    Simulator a(body, settingsFor(IntegratorKind::ImplicitEuler, 1.0 / 120.0));
    const ExternalForces f = loadFor(*body);
    for (int i = 0; i < 30; ++i)
        a.step(f);
    const BodyState mid = a.saveState();
    for (int i = 0; i < 30; ++i)
        a.step(f);
    Simulator b(body, settingsFor(IntegratorKind::ImplicitEuler, 1.0 / 120.0));
    b.restoreState(mid);
    for (int i = 0; i < 30; ++i)
        b.step(f);
    QCOMPARE(b.state().position, a.state().position);
}

QTEST_GUILESS_MAIN(TestStability)
#include "test_stability.moc"
