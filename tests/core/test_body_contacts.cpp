// Bodies against bodies (core/body/body_contacts.h): the lattice map's inverse, and two soft fish-shaped bodies
// thrown at each other with every integrator. They must collide and separate; no sample point of either may
// end a step inside the other's deformed mesh by more than 1% of the body's size, measured here without the
// code under test (winding number and triangle distance on the deformed meshes); momentum is kept; and with
// body collisions off the same throw passes one through the other (so the check can fail).

#include "helpers/physics_fixture.h"

#include "core/body/body_contacts.h"
#include "core/geometry/binding.h"
#include "core/geometry/primitives.h"
#include "core/scene/scene.h"

#include <QtTest>

#include <numbers>
#include <numeric>

using namespace softtouch;
using namespace softtouch::test;

namespace {

/// A fish-shaped ellipsoid (radii 0.15, 0.06, 0.04 m) at `centre` in a 4x4x4 Bezier lattice 10% larger.
SceneObject fish(const std::string& name, const Vec3& centre) {
    SceneObject o;
    o.name = name;
    const Vec3 radii(0.15, 0.06, 0.04);
    Mesh mesh = makeUvEllipsoid(16, 32, radii, centre);
    mesh.computeNormals();
    o.mesh = std::move(mesh);
    OrientedBox box;
    box.origin = centre - 1.1 * radii;
    box.size = 2.2 * radii;
    o.lattice = Lattice::create({LatticeKind::Bezier, {4, 4, 4}}, box).value();
    o.material = uniformMaterial(o.lattice, 0.01, 60.0, 0.05);
    return o;
}

/// Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom & Strackee, 1983).
double solidAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    return 2.0 * std::atan2(numerator, denominator);
}

/// Distance from p to triangle (a, b, c) (Ericson, "Real-Time Collision Detection", 5.1.5).
double triangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return (p - a).norm();
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return (p - b).norm();
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return (p - c).norm();
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
    const double denom = 1.0 / (va + vb + vc);
    return (p - (a + ab * vb * denom + ac * vc * denom)).norm();
}

/// How deep p lies inside the closed mesh (positions, triangles): 0 outside (winding number below 1/2).
double depthInside(const Vec3& p, const std::vector<Vec3f>& positions, const Mesh& topology) {
    double winding = 0.0;
    for (const auto& t : topology.triangles)
        winding += solidAngle(positions[t[0]].cast<double>() - p, positions[t[1]].cast<double>() - p,
                              positions[t[2]].cast<double>() - p);
    if (std::abs(winding) < 2.0 * std::numbers::pi)
        return 0.0;
    double nearest = 1e300;
    for (const auto& t : topology.triangles)
        nearest = std::min(nearest, triangleDistance(p, positions[t[0]].cast<double>(), positions[t[1]].cast<double>(),
                                                     positions[t[2]].cast<double>()));
    return nearest;
}

Vec3 momentum(const Simulator& sim) {
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0; i < sim.model().nodeCount(); ++i)
        sum += sim.model().mass[i] * sim.state().velocity[i];
    return sum;
}

Vec3 meanVelocity(const Simulator& sim) { return momentum(sim) / std::accumulate(sim.model().mass.begin(), sim.model().mass.end(), 0.0); }

}  // namespace

class TestBodyContacts : public QObject {
    Q_OBJECT

private slots:
    // Newton on X(u) = p finds the material point of a bent, moved lattice: X(found) = p.
    void latticeParametersInvertTheMap() {
        const SceneObject o = fish("a", Vec3::Zero());
        std::vector<Vec3> nodes = o.lattice.restNodes();
        for (std::size_t i = 0; i < nodes.size(); ++i) {  // bend, twist and carry the lattice away
            const Vec3 r = nodes[i];
            nodes[i] = Vec3(r.x() + 1.0, r.y() + 0.5 * r.x() * r.x() + 0.02 * std::sin(40.0 * r.z()), r.z() + 0.3 * r.y());
        }
        int found = 0;
        for (double u : {0.1, 0.5, 0.9})
            for (double v : {0.0, 0.3, 1.0})
                for (double w : {0.2, 0.7}) {
                    const Vec3 truth(u, v, w);
                    const Vec3 p = o.lattice.evaluate(truth, nodes);
                    Vec3 uvw(0.5, 0.5, 0.5);
                    Mat3 jacobian;
                    QVERIFY(latticeParameters(o.lattice, nodes, p, uvw, jacobian));
                    QVERIFY2((uvw - truth).norm() < 1e-8, qPrintable(QString("(%1 %2 %3)").arg(u).arg(v).arg(w)));
                    // The Jacobian is the map's: a small step in u moves p by J du.
                    const Vec3 du(1e-6, -2e-6, 1.5e-6);
                    const Vec3 moved = o.lattice.evaluate(truth + du, nodes);
                    QVERIFY(((moved - p) - jacobian * du).norm() < 1e-9);
                    ++found;
                }
        QCOMPARE(found, 18);
    }

    void fishCollideAndSeparate_data() {
        QTest::addColumn<int>("integrator");
        QTest::addColumn<double>("speed");
        for (double speed : {0.5, 1.0})  // each, m/s: a brisk swim, and 8 mm closing a step
            for (IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                                     IntegratorKind::Xpbd})
                QTest::newRow(qPrintable(QString("%1 at %2 m/s").arg(integratorName(k).data()).arg(speed))) << int(k) << speed;
    }

    // The must-show: thrown flank to flank (slightly off-centre, so they also turn), they touch, push apart
    // and fly off; no sample point ends a step inside the other by more than 1% of the body's size.
    void fishCollideAndSeparate() {
        QFETCH(int, integrator);
        QFETCH(double, speed);
        for (bool collide : {true, false}) {
            Scene scene;
            scene.objects.push_back(fish("left", Vec3(0.0, 0.0, -0.1)));
            scene.objects.push_back(fish("right", Vec3(0.03, 0.01, 0.1)));
            scene.world.simulation = settingsFor(IntegratorKind(integrator), 1.0 / 240.0);
            scene.world.bodyCollisions.enabled = collide;
            scene.world.bodyCollisions.restitution = 0.5;
            auto created = SceneSimulation::create(scene);
            QVERIFY2(created, created ? "" : created.message().c_str());
            SceneSimulation sim = std::move(created.value());
            SceneSimulation::Snapshot start = sim.saveSnapshot();
            for (Vec3& v : start.bodies[0].velocity) v = Vec3(0.0, 0.0, speed);
            for (Vec3& v : start.bodies[1].velocity) v = Vec3(0.0, 0.0, -speed);
            sim.restoreSnapshot(start);
            const Vec3 momentumBefore = momentum(sim.simulator(0)) + momentum(sim.simulator(1));

            const Mesh& mesh = scene.objects[0].mesh;
            const double size = (mesh.bounds().max - mesh.bounds().min).norm();
            std::vector<std::vector<Vec3f>> deformed(2, std::vector<Vec3f>(mesh.positions.size()));
            std::vector<Vec3f> normals(mesh.positions.size());
            double deepest = 0.0;
            int contacts = 0;
            std::vector<std::string> problems;
            for (int step = 1; step <= 240; ++step) {
                sim.advanceTo(step / 240.0, &problems);
                contacts += sim.lastBodyContacts().contacts;
                for (int b = 0; b < 2; ++b)
                    sim.evaluate(std::size_t(b), deformed[std::size_t(b)], normals, 1);
                for (int b = 0; b < 2; ++b) {
                    const ContactPoints& points = sim.simulator(std::size_t(b)).model().contacts();
                    // Only a point inside the other mesh's bounding box can be inside the mesh.
                    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
                    for (const Vec3f& v : deformed[std::size_t(1 - b)]) {
                        lo = lo.cwiseMin(v.cast<double>());
                        hi = hi.cwiseMax(v.cast<double>());
                    }
                    for (std::size_t q = 0; q < points.size(); ++q) {
                        const Vec3 p = points.at(q, sim.simulator(std::size_t(b)).state().position);
                        if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all())
                            deepest = std::max(deepest, depthInside(p, deformed[std::size_t(1 - b)], mesh));
                    }
                }
                if (!collide && deepest > 0.1 * size)
                    break;  // passing through, as it should without collisions
            }
            if (!collide) {
                qInfo("%s, collisions off: a sample point reached %.3f m inside the other (%.0f%% of %.3f m)",
                      QTest::currentDataTag(), deepest, 100.0 * deepest / size, size);
                QVERIFY(deepest > 0.1 * size);
                continue;
            }
            const Vec3 momentumAfter = momentum(sim.simulator(0)) + momentum(sim.simulator(1));
            const Vec3 left = meanVelocity(sim.simulator(0)), right = meanVelocity(sim.simulator(1));
            qInfo("%s: %d contacts, deepest sample %.2e m (%.2f%% of %.3f m); after 1 s mean z velocities %.3f, %.3f "
                  "m/s; momentum change %.1e kg m/s; %zu reports",
                  QTest::currentDataTag(), contacts, deepest, 100.0 * deepest / size, size, left.z(), right.z(),
                  (momentumAfter - momentumBefore).norm(), problems.size());
            QVERIFY(contacts > 0);
            QVERIFY2(deepest <= 0.01 * size, qPrintable(QString::number(deepest)));
            // Separated: each moves back the way it came, at 5% or more of its speed (restitution 0.5 at the
            // touching points; how much of the bounce the whole body keeps depends on how it wobbles).
            QVERIFY2(left.z() < -0.05 * speed && right.z() > 0.05 * speed, qPrintable(QString("%1 %2").arg(left.z()).arg(right.z())));
            // Equal and opposite impulses: the pair's momentum is what it was (0.64 kg m/s each way before).
            QVERIFY2((momentumAfter - momentumBefore).norm() < 1e-9, qPrintable(QString::number((momentumAfter - momentumBefore).norm())));
            for (const std::string& p : problems)
                qWarning("%s", p.c_str());
            QVERIFY(problems.empty());
        }
    }
};

QTEST_GUILESS_MAIN(TestBodyContacts)
#include "test_body_contacts.moc"
