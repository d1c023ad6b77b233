// Volume preservation (core/body/volume_preservation.h): a ball squashed to half its height between two
// planes keeps its mesh's volume when preservation is 1 and loses it when 0, with every integrator; the
// sampled volume and its gradient against the mesh's exact volume and finite differences.

#include "helpers/physics_fixture.h"

#include "core/body/volume_preservation.h"
#include "core/geometry/binding.h"
#include "core/geometry/primitives.h"

#include <QtTest>

#include <random>

using namespace softtouch;
using namespace softtouch::test;

namespace {

/// A ball of radius 0.2 m in a 4x4x4 Bezier lattice over [-0.22, 0.22]³.
struct Ball {
    Mesh mesh = makeUvEllipsoid(24, 48, Vec3(0.2, 0.2, 0.2));
    Lattice lattice;
    Ball() {
        OrientedBox box;
        box.origin = Vec3::Constant(-0.22);
        box.size = Vec3::Constant(0.44);
        lattice = Lattice::create({LatticeKind::Bezier, {4, 4, 4}}, box).value();
        mesh.computeNormals();
    }
    std::shared_ptr<const BodyModel> body(double preservation) const {
        LatticeMaterial m = uniformMaterial(lattice, 0.02, 80.0, 0.9);
        setVolumePreservation(m, preservation);
        return buildLatticeBody(lattice, m, &mesh).value();
    }
    /// Preservation 1 painted on the nodes of the half x > 0 (u node index 2 and 3), 0 on the other half.
    std::shared_ptr<const BodyModel> halfPaintedBody() const {
        LatticeMaterial m = uniformMaterial(lattice, 0.02, 80.0, 0.9);
        m.volumePreservation.assign(m.mass.size(), 0.0);
        for (int node = 0; node < lattice.nodeCount(); ++node)
            if (lattice.coords(node)[0] >= 2)
                m.volumePreservation[std::size_t(node)] = 1.0;
        return buildLatticeBody(lattice, m, &mesh).value();
    }
    /// The volume of the mesh's material on each side of x = 0 at rest (u < 1/2, u > 1/2), deformed by `nodes`:
    /// ∫ det J over the mesh's samples of that half of the parameter box.
    std::array<double, 2> halfVolumes(const std::vector<Vec3>& nodes) const {
        VolumeConstraint whole = body(1.0)->volume;
        const int G = whole.cells;
        std::array<double, 2> out{};
        for (int side = 0; side < 2; ++side) {
            VolumeConstraint half = whole;
            for (int q = 0; q < G * G * G; ++q)
                if ((q % G < G / 2) != (side == 0))
                    half.weight[std::size_t(q)] = 0.0;
            out[std::size_t(side)] = sampledVolume(half, nodes) / sampledVolume(half, lattice.restNodes());
        }
        return out;
    }
    /// The deformed mesh's enclosed volume for node positions `nodes`.
    double meshVolume(const std::vector<Vec3>& nodes) const {
        const Binding binding = Binding::create(lattice, mesh.positions, mesh.normals);
        std::vector<Vec3f> positions(mesh.positions.size()), normals(mesh.positions.size());
        binding.evaluate(nodes, positions, normals, 1);
        return enclosedVolume(positions, mesh.triangles);
    }
};

}  // namespace

class TestVolumePreservation : public QObject {
    Q_OBJECT

private slots:
    // V0 is the mesh's volume (sampled occupancy), the whole box's without a mesh; the gradient is exact.
    void sampledVolumeFollowsTheMesh() {
        const Ball ball;
        const auto body = ball.body(1.0);
        const VolumeConstraint& c = body->volume;
        QVERIFY(c.active());
        const double exact = enclosedVolume(ball.mesh.positions, ball.mesh.triangles);
        qInfo("rest: sampled %.6f m³, mesh %.6f m³ (sphere %.6f)", c.restVolume, exact, 4.0 / 3.0 * M_PI * 0.008);
        QVERIFY(std::abs(c.restVolume / exact - 1.0) < 0.01);
        // A deformed state: sampled against the deformed mesh, and the gradient against finite differences.
        std::vector<Vec3> x = ball.lattice.restNodes();
        std::mt19937 random(3);
        std::uniform_real_distribution<double> offset(-0.04, 0.04);
        for (Vec3& p : x)
            p += Vec3(offset(random), offset(random), offset(random));
        std::vector<Vec3> gradient(x.size());
        const double v = sampledVolume(c, x, gradient);
        const double mesh = ball.meshVolume(x);
        qInfo("deformed: sampled %.6f m³, mesh %.6f m³", v, mesh);
        QVERIFY(std::abs(v / mesh - 1.0) < 0.02);
        for (std::size_t i : {0ul, 21ul, 42ul, 63ul})
            for (int a = 0; a < 3; ++a) {
                const double step = 1e-6;
                std::vector<Vec3> plus = x, minus = x;
                plus[i][a] += step;
                minus[i][a] -= step;
                const double numeric = (sampledVolume(c, plus) - sampledVolume(c, minus)) / (2 * step);
                QVERIFY2(std::abs(numeric - gradient[i][a]) < 1e-6 * (1.0 + std::abs(numeric)),
                         qPrintable(QString("node %1 axis %2: %3 vs %4").arg(i).arg(a).arg(numeric).arg(gradient[i][a])));
            }
        // Without a mesh the whole box is kept.
        LatticeMaterial m = uniformMaterial(ball.lattice, 0.02, 80.0, 0.9);
        setVolumePreservation(m, 1.0);
        const auto boxBody = buildLatticeBody(ball.lattice, m).value();
        QVERIFY(std::abs(boxBody->volume.restVolume - std::pow(0.44, 3)) < 1e-12);
        // Off costs nothing: no samples at all.
        QVERIFY(!ball.body(0.0)->volume.active() && ball.body(0.0)->volume.weight.empty());
    }

    void squashedBallKeepsItsVolume_data() { addIntegratorRows(); }

    // The must-show: squashed to half its height between two frictionless planes (the upper one lowered
    // over 1 s, then held 1 s), the ball's mesh keeps its volume within 3% at preservation 1 and loses at
    // least 20% at 0.
    void squashedBallKeepsItsVolume() {
        QFETCH(int, integrator);
        const Ball ball;
        const double restMesh = enclosedVolume(ball.mesh.positions, ball.mesh.triangles);
        auto squash = [&](double preservation, double* boxVolume) {
            const auto body = ball.body(preservation);
            Simulator sim(body, settingsFor(IntegratorKind(integrator), 1.0 / 240.0));
            ExternalForces f;
            f.planes.push_back(CollisionPlane{Vec3(0, -0.22, 0), Vec3::UnitY(), 0.0, 0.0});
            f.planes.push_back(CollisionPlane{Vec3(0, 0.22, 0), -Vec3::UnitY(), 0.0, 0.0});
            int problems = 0;
            for (int i = 0; i < 480; ++i) {
                const double t = std::min(1.0, (i + 1) / 240.0);
                f.planes[1].point.y() = 0.22 - 0.22 * t;  // down to y = 0: half the box's height
                problems += !sim.step(f).problem.empty();
            }
            const std::vector<Vec3>& x = sim.state().position;
            double top = -1e9;
            for (const Vec3& p : x)
                top = std::max(top, p.y());
            *boxVolume = sampledVolume(buildVolumeConstraint(ball.lattice, {}, std::vector<double>(64, 1.0), 1.0), x) / std::pow(0.44, 3);
            const double sampled = body->volume.active() ? sampledVolume(body->volume, x) / body->volume.restVolume : 0.0;
            qInfo("%s, preservation %.0f: mesh volume %.1f%% of rest (the constraint's samples %.1f%%), lattice box %.1f%%, "
                  "top node at y = %.4f m, %d reports",
                  QTest::currentDataTag(), preservation, 100.0 * ball.meshVolume(x) / restMesh, 100.0 * sampled,
                  100.0 * *boxVolume, top, problems);
            if (top > 0.002)
                qWarning("the upper plane did not squash the ball");
            return ball.meshVolume(x) / restMesh;
        };
        double boxKept = 0.0, boxLost = 0.0;
        const double kept = squash(1.0, &boxKept);
        const double lost = squash(0.0, &boxLost);
        QVERIFY2(std::abs(kept - 1.0) <= 0.03, qPrintable(QString("kept %1").arg(kept)));
        QVERIFY2(lost <= 0.8, qPrintable(QString("lost to %1").arg(lost)));
    }

    void paintedHalfKeepsItsVolume_data() { addIntegratorRows(); }

    // Painted per node: preservation 1 on the half x > 0 of the ball and 0 on the other. Squashed as above,
    // the painted half keeps its material's volume and bulges; the unpainted half loses volume (less than
    // with preservation off, since the map is blended across the middle). A uniform map keeps both halves.
    void paintedHalfKeepsItsVolume() {
        QFETCH(int, integrator);
        const Ball ball;
        auto squash = [&](const std::shared_ptr<const BodyModel>& body) {
            Simulator sim(body, settingsFor(IntegratorKind(integrator), 1.0 / 240.0));
            ExternalForces f;
            f.planes.push_back(CollisionPlane{Vec3(0, -0.22, 0), Vec3::UnitY(), 0.0, 0.0});
            f.planes.push_back(CollisionPlane{Vec3(0, 0.22, 0), -Vec3::UnitY(), 0.0, 0.0});
            for (int i = 0; i < 480; ++i) {
                f.planes[1].point.y() = 0.22 - 0.22 * std::min(1.0, (i + 1) / 240.0);
                (void)sim.step(f);
            }
            return ball.halfVolumes(sim.state().position);
        };
        const auto painted = squash(ball.halfPaintedBody());
        const auto uniform = squash(ball.body(1.0));
        const auto off = squash(ball.body(0.0));
        qInfo("%s: half x < 0 / x > 0 keeps %.1f%% / %.1f%% painted on x > 0, %.1f%% / %.1f%% painted everywhere, "
              "%.1f%% / %.1f%% off", QTest::currentDataTag(), 100 * painted[0], 100 * painted[1], 100 * uniform[0],
              100 * uniform[1], 100 * off[0], 100 * off[1]);
        // The map reaches the samples through the cubic basis, so the unpainted half near the middle still
        // counts a little (p(u) = 0.16 at u = 1/4, 0.35 at u = 0.4): it loses a third of what 'off' loses.
        // The painted half keeps its volume, and takes up a little of what the blended middle loses.
        QVERIFY2(painted[1] >= 0.97 && painted[1] <= 1.05, "the painted half keeps its volume");
        QVERIFY2(painted[0] <= uniform[0] - 0.1, "the unpainted half loses volume");
        QVERIFY2(painted[0] >= off[0], "and not more than with preservation off");
        QVERIFY(std::abs(uniform[0] - 1.0) <= 0.03 && std::abs(uniform[1] - 1.0) <= 0.03);
    }

    // The correction of a painted map keeps momentum: a free body (no anchors, gravity or planes) released
    // squashed on one side keeps its total momentum at zero while the painted side springs back.
    void paintedCorrectionKeepsMomentum() {
        const Ball ball;
        const auto body = ball.halfPaintedBody();
        Simulator sim(body, settingsFor(IntegratorKind::Verlet, 1.0 / 240.0));
        BodyState start = sim.state();
        for (int node = 0; node < ball.lattice.nodeCount(); ++node)
            if (ball.lattice.coords(node)[0] >= 2)
                start.position[std::size_t(node)].y() *= 0.6;
        sim.restoreState(start);
        const double before = sampledVolume(body->volume, start.position) / body->volume.restVolume;
        double worst = 0.0, scale = 0.0;
        for (int i = 0; i < 240; ++i) {
            (void)sim.step({});
            Vec3 momentum = Vec3::Zero();
            double speed = 0.0;
            for (std::size_t n = 0; n < body->nodeCount(); ++n) {
                momentum += body->mass[n] * sim.state().velocity[n];
                speed += body->mass[n] * sim.state().velocity[n].norm();
            }
            worst = std::max(worst, momentum.norm());
            scale = std::max(scale, speed);
        }
        const double after = sampledVolume(body->volume, sim.state().position) / body->volume.restVolume;
        qInfo("painted volume %.1f%% squashed, %.1f%% after 1 s; largest |momentum| %.3g against Σ m|v| up to %.3g",
              100 * before, 100 * after, worst, scale);
        QVERIFY(before < 0.9 && std::abs(after - 1.0) < 0.01);
        QVERIFY(scale > 0.0 && worst <= 1e-9 * scale);
    }

    // A painted map is validated per node and carried to another lattice as it is.
    void paintedMapIsValidatedAndResampled() {
        const Ball ball;
        LatticeMaterial m = uniformMaterial(ball.lattice, 0.02, 80.0, 0.9);
        m.volumePreservation.assign(m.mass.size(), 0.5);
        m.volumePreservation[5] = 1.5;
        const auto bad = buildLatticeBody(ball.lattice, m, &ball.mesh);
        QVERIFY(!bad);
        qInfo("%s", bad.message().c_str());
        QVERIFY(QString::fromStdString(bad.message()).contains("node (1,1,0) volume preservation (volumePreservation) 1.5 is outside [0, 1]"));
        m.volumePreservation[5] = 0.5;
        m.volumePreservation.resize(3);
        QVERIFY(!buildLatticeBody(ball.lattice, m, &ball.mesh));
        LatticeMaterial painted = uniformMaterial(ball.lattice, 0.02, 80.0, 0.9);
        painted.volumePreservation.assign(painted.mass.size(), 0.0);
        for (int node = 0; node < ball.lattice.nodeCount(); ++node)
            painted.volumePreservation[std::size_t(node)] = ball.lattice.coords(node)[0] >= 2 ? 0.8 : 0.2;
        const Lattice fine = Lattice::create({LatticeKind::Bezier, {7, 7, 7}}, ball.lattice.box()).value();
        const LatticeMaterial there = resampleMaterial(ball.lattice, painted, fine, true);
        const LatticeMaterial back = resampleMaterial(fine, there, ball.lattice, true);
        QCOMPARE(back.volumePreservation, painted.volumePreservation);
        QCOMPARE(largestVolumePreservation(there), 0.8);
        LatticeMaterial unpainted = uniformMaterial(ball.lattice, 0.02, 80.0, 0.9);
        unpainted.volumePreservation.clear();  // a material made before painting: 0 everywhere
        QCOMPARE(largestVolumePreservation(resampleMaterial(ball.lattice, unpainted, fine, true)), 0.0);
        QVERIFY(buildLatticeBody(ball.lattice, unpainted, &ball.mesh));
    }
};

QTEST_GUILESS_MAIN(TestVolumePreservation)
#include "test_volume_preservation.moc"
