// Stretch and squash limits (core/body/strain_limits.h): held under a yank by every integrator at the default
// step, never a source of energy, momentum kept.

#include "helpers/physics_fixture.h"

#include "core/body/strain_limits.h"

#include <QtTest>

#include <random>

using namespace softtouch;
using namespace softtouch::test;

namespace {

/// Longest and shortest spring, as multiples of their rest lengths.
std::pair<double, double> strainRange(const BodyModel& model, const BodyState& state) {
    double longest = 0.0, shortest = 1e300;
    for (const Spring& s : model.springs) {
        const double ratio = (state.position[s.b] - state.position[s.a]).norm() / s.restLength;
        longest = std::max(longest, ratio);
        shortest = std::min(shortest, ratio);
    }
    return {longest, shortest};
}

/// The undamped bar of the stability suite (0.1 x 0.1 x 1 m, pinned at w = 0) with the given limits.
std::shared_ptr<const BodyModel> bar(StrainLimits limits) {
    OrientedBox box;
    box.size = Vec3(0.1, 0.1, 1.0);
    return latticeBody({2, 2, 7}, 0.01, 400.0, 0.0,
                       [&](const Lattice& lattice, LatticeMaterial& m) {
                           for (int j = 0; j < 2; ++j)
                               for (int i = 0; i < 2; ++i)
                                   m.anchor[std::size_t(lattice.index(i, j, 0))] = AnchorMode::Pinned;
                           m.strainLimits = limits;
                       },
                       box);
}

/// A stiff drag (2000 N/m) that suddenly pulls the bar's tip 1 m further along it and holds there.
ExternalForces yank(const BodyModel& body) {
    ExternalForces f;
    DragSpring drag;
    Vec3 tip = Vec3::Zero();
    for (std::uint32_t node : {24u, 25u, 26u, 27u}) {  // the four nodes at w = 1
        drag.support.push_back({node, 0.25});
        tip += 0.25 * body.restPositions[node];
    }
    drag.target = tip + Vec3(0.0, 0.0, 1.0);
    drag.stiffness = 2000.0;
    drag.damping = 0.0;
    f.drags.push_back(drag);
    return f;
}

}  // namespace

class TestStrainLimits : public QObject {
    Q_OBJECT

private slots:
    void yankStaysWithinTheLimits_data() { addIntegratorRows(); }

    // The must-show: strain never exceeds the limit by more than 1% under a yank at the default step
    // (1/240 s), for every integrator; the same yank without limits goes well past them.
    void yankStaysWithinTheLimits() {
        QFETCH(int, integrator);
        const StrainLimits limits{1.5, 0.5};
        auto free = bar({});
        auto limited = bar(limits);
        const ExternalForces pull = yank(*limited);
        const SimulationSettings settings = settingsFor(IntegratorKind(integrator), 1.0 / 240.0);
        Simulator unlimited(free, settings), sim(limited, settings);
        double unlimitedLongest = 0.0, longest = 0.0, shortest = 1e300;
        int corrections = 0, problems = 0;
        for (int i = 0; i < 240; ++i) {
            unlimited.step(pull);
            unlimitedLongest = std::max(unlimitedLongest, strainRange(*free, unlimited.state()).first);
            const StepReport r = sim.step(pull);
            corrections += r.strainCorrections;
            problems += !r.problem.empty();
            const auto [l, s] = strainRange(*limited, sim.state());
            longest = std::max(longest, l);
            shortest = std::min(shortest, s);
        }
        qInfo("%s: longest spring %.4fx (%.4fx without limits), shortest %.4fx; %d corrections, %d problems; "
              "energy the limits changed %.3g J",
              QTest::currentDataTag(), longest, unlimitedLongest, shortest, corrections, problems,
              sim.energyAccount().limits);
        QVERIFY2(unlimitedLongest > 1.6, "the yank must go past the limit for the test to mean anything");
        QVERIFY(corrections > 0);
        QVERIFY2(longest <= limits.stretch * 1.01, qPrintable(QString::number(longest)));
        QVERIFY2(shortest >= limits.squash * 0.99, qPrintable(QString::number(shortest)));
        QCOMPARE(problems, 0);
        QVERIFY(sim.state().isFinite());
        // Never a source of energy (the energy account of the explicit schemes and XPBD books what the limits do).
        QVERIFY2(sim.energyAccount().limits <= 1e-9, qPrintable(QString::number(sim.energyAccount().limits)));
    }

    // One pass on a state with springs stretched, squashed and moving: every spring ends within its
    // bounds, the kinetic energy does not grow, and a pinned node does not move.
    void onePassHoldsEveryBoundAndAddsNoMotion() {
        auto body = latticeBody({3, 3, 3}, 0.02, 100.0, 0.0, [](const Lattice& lattice, LatticeMaterial& m) {
            m.anchor[std::size_t(lattice.index(0, 0, 0))] = AnchorMode::Pinned;
            m.strainLimits = {1.2, 0.8};
        });
        BodyState state = restState(*body);
        std::mt19937 random(7);
        std::uniform_real_distribution<double> offset(-0.25, 0.25), speed(-2.0, 2.0);
        for (std::size_t i = 0; i < body->nodeCount(); ++i) {
            if (body->inverseMass[i] == 0.0)
                continue;
            state.position[i] += Vec3(offset(random), offset(random), offset(random));
            state.velocity[i] = Vec3(speed(random), speed(random), speed(random));
        }
        auto kinetic = [&](const BodyState& st) {
            double e = 0.0;
            for (std::size_t i = 0; i < body->nodeCount(); ++i)
                e += 0.5 * body->mass[i] * st.velocity[i].squaredNorm();
            return e;
        };
        const auto before = strainRange(*body, state);
        QVERIFY(before.first > 1.2 && before.second < 0.8);
        QVERIFY(strainLimitsViolated(*body, body->strainLimits, state));
        const Vec3 pinned = state.position[0];
        const double kinetic0 = kinetic(state);
        const StrainLimitPass pass = enforceStrainLimits(*body, body->strainLimits, state);
        const double kinetic1 = kinetic(state);
        const auto after = strainRange(*body, state);
        qInfo("before %.3fx..%.3fx, after %.5fx..%.5fx in %d sweeps (%d corrections); kinetic %.4f -> %.4f J",
              before.second, before.first, after.second, after.first, pass.sweeps, pass.corrections, kinetic0, kinetic1);
        QVERIFY(after.first <= 1.2 * (1 + 2e-4) && after.second >= 0.8 * (1 - 2e-4));
        QVERIFY(!strainLimitsViolated(*body, {1.2 * (1 + 2e-4), 0.8 * (1 - 2e-4)}, state));
        QCOMPARE(state.position[0], pinned);
        QVERIFY(kinetic1 <= kinetic0);
    }

    // Without a pinned node every correction is internal: centre and momentum are exact.
    void freeBodyKeepsCentreAndMomentum() {
        auto body = latticeBody({3, 3, 3}, 0.02, 100.0, 0.0, [](const Lattice&, LatticeMaterial& m) {
            m.strainLimits = {1.1, 0.9};
            for (std::size_t i = 0; i < m.mass.size(); ++i)
                m.mass[i] = 0.01 * double(1 + i % 5);  // unequal masses: shares by inverse mass matter
        });
        BodyState state = restState(*body);
        std::mt19937 random(11);
        std::uniform_real_distribution<double> offset(-0.2, 0.2), speed(-1.0, 1.0);
        for (std::size_t i = 0; i < body->nodeCount(); ++i) {
            state.position[i] += Vec3(offset(random), offset(random), offset(random));
            state.velocity[i] = Vec3(speed(random), speed(random), speed(random));
        }
        auto weighted = [&](const std::vector<Vec3>& values) {
            Vec3 sum = Vec3::Zero();
            for (std::size_t i = 0; i < body->nodeCount(); ++i)
                sum += body->mass[i] * values[i];
            return sum;
        };
        const Vec3 centre = weighted(state.position), momentum = weighted(state.velocity);
        const StrainLimitPass pass = enforceStrainLimits(*body, body->strainLimits, state);
        QVERIFY(pass.corrections > 0);
        QVERIFY2((weighted(state.position) - centre).norm() < 1e-12, "the centre moved");
        QVERIFY2((weighted(state.velocity) - momentum).norm() < 1e-12, "momentum changed");
        const auto after = strainRange(*body, state);
        QVERIFY(after.first <= 1.1 * (1 + 2e-4) && after.second >= 0.9 * (1 - 2e-4));
    }

    void outOfRangeLimitsAreRefusedByName() {
        QVERIFY(validateStrainLimits({}).ok());
        QVERIFY(validateStrainLimits({1.5, 0.5}).ok());
        const Status stretch = validateStrainLimits({1.0, 0.0});
        QVERIFY(!stretch.ok() && stretch.message().find("stretch limit") != std::string::npos);
        const Status squash = validateStrainLimits({0.0, 1.0});
        QVERIFY(!squash.ok() && squash.message().find("squash limit") != std::string::npos);
        BodyDescription d;
        d.restPositions = {Vec3::Zero(), Vec3::UnitX()};
        d.mass = {1.0, 1.0};
        d.strainLimits = {0.0, -0.5};
        const auto built = buildBodyModel(d);
        QVERIFY(!built.ok() && built.message().find("squash limit") != std::string::npos);
    }
};

QTEST_GUILESS_MAIN(TestStrainLimits)
#include "test_strain_limits.moc"
