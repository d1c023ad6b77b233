// Volume preservation (core/volume_preservation.h): a ball squashed to half its height between two
// planes keeps its mesh's volume when preservation is 1 and loses it when 0, with every integrator; the
// sampled volume and its gradient against the mesh's exact volume and finite differences.

#include "physics_fixture.h"

#include "core/binding.h"
#include "core/primitives.h"
#include "core/volume_preservation.h"

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
        m.volumePreservation = preservation;
        return buildLatticeBody(lattice, m, &mesh).value();
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
        m.volumePreservation = 1.0;
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
            *boxVolume = sampledVolume(buildVolumeConstraint(ball.lattice, {}, 1.0, 1.0), x) / std::pow(0.44, 3);
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
};

QTEST_GUILESS_MAIN(TestVolumePreservation)
#include "test_volume_preservation.moc"
