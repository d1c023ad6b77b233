#pragma once
// A fixture for physics facts: build a small body, run it N seconds, compare with an analytic answer.

#include "core/body/lattice_body.h"
#include "core/solver/simulator.h"

#include <QtTest>
#include <functional>

namespace softtouch::test {

/// Every integrator, as Qt Test rows (column "integrator").
inline void addIntegratorRows() {
    QTest::addColumn<int>("integrator");
    for (IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                             IntegratorKind::Xpbd})
        QTest::newRow(std::string(integratorName(k)).c_str()) << int(k);
}

/// A lattice body over the unit cube (or the given box) with uniform material.
inline std::shared_ptr<const BodyModel> latticeBody(std::array<int, 3> nodes, double mass, double stiffness,
                                                    double damping,
                                                    const std::function<void(const Lattice&, LatticeMaterial&)>& edit = {},
                                                    OrientedBox box = {}) {
    const Lattice lattice = Lattice::create({LatticeKind::BSpline, nodes}, box).value();
    LatticeMaterial m = uniformMaterial(lattice, mass, stiffness, damping);
    if (edit)
        edit(lattice, m);
    auto body = buildLatticeBody(lattice, m);
    if (!body)
        qFatal("%s", body.message().c_str());
    return body.value();
}

/// Settings with the given integrator and step, sleeping off (tests watch every step).
inline SimulationSettings settingsFor(IntegratorKind kind, double dt, int xpbdSubsteps = 8) {
    SimulationSettings s;
    s.integrator = kind;
    s.dt = dt;
    s.xpbdSubsteps = xpbdSubsteps;
    s.sleep = false;
    return s;
}

/// Mean position of the simulated nodes.
inline Vec3 centroid(const BodyModel& model, const BodyState& state) {
    Vec3 c = Vec3::Zero();
    int n = 0;
    for (std::size_t i = 0; i < model.nodeCount(); ++i) {
        if (model.simulated[i]) {
            c += state.position[i];
            ++n;
        }
    }
    return c / n;
}

}  // namespace softtouch::test
