// Colliders beyond planes (core/colliders.h): the shapes' signed distances, and a ball dropped on a sphere,
// a capsule and a box with every integrator: no mesh sample point ends a step inside by more than 1% of the
// body's size, and it comes to rest.

#include "physics_fixture.h"

#include "core/binding.h"
#include "core/colliders.h"
#include "core/mesh_surface.h"
#include "core/primitives.h"

#include <numbers>
#include <random>

#include <QtTest>

using namespace softtouch;
using namespace softtouch::test;

namespace {

/// A soft pancake (an ellipsoid of radii 0.15, 0.04, 0.15 m) at `centre` in a 4x4x4 Bezier lattice over a
/// box 10% larger. Flat enough to rest on a sphere's top (its centre of mass sits lower than the radius of
/// curvature of both surfaces allows: a ball there would roll off, as it should).
struct Ball {
    Mesh mesh;
    Lattice lattice;
    explicit Ball(const Vec3& centre) : mesh(makeUvEllipsoid(16, 32, Vec3(0.15, 0.04, 0.15), centre)) {
        OrientedBox box;
        box.origin = centre - Vec3(0.165, 0.044, 0.165);
        box.size = Vec3(0.33, 0.088, 0.33);
        lattice = Lattice::create({LatticeKind::Bezier, {4, 4, 4}}, box).value();
        mesh.computeNormals();
    }
    std::shared_ptr<const BodyModel> body() const {
        LatticeMaterial m = uniformMaterial(lattice, 0.02, 80.0, 0.9);
        return buildLatticeBody(lattice, m, &mesh).value();
    }
};

/// A closed box mesh of the given half extents, centred on the origin, 12 triangles wound outwards.
Mesh boxMesh(const Vec3& half) {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.emplace_back(float(i & 1 ? half.x() : -half.x()), float(i & 2 ? half.y() : -half.y()),
                                 float(i & 4 ? half.z() : -half.z()));
    const int quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    for (const auto& q : quads) {
        std::array<std::uint32_t, 4> v{std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2]), std::uint32_t(q[3])};
        const Vec3 a = m.positions[v[0]].cast<double>(), b = m.positions[v[1]].cast<double>(), c = m.positions[v[2]].cast<double>();
        if ((b - a).cross(c - a).dot(a + c) < 0.0)  // wind so the normal points away from the centre
            std::swap(v[1], v[3]);
        m.triangles.push_back({v[0], v[1], v[2]});
        m.triangles.push_back({v[0], v[2], v[3]});
    }
    return m;
}

}  // namespace

class TestColliders : public QObject {
    Q_OBJECT

private slots:
    void distancesAndNormals() {
        Vec3 n;
        Collider sphere;
        sphere.centre = Vec3(1, 0, 0);
        sphere.radius = 0.5;
        QCOMPARE(colliderDistance(sphere, Vec3(1, 2, 0), n), 1.5);
        QVERIFY((n - Vec3::UnitY()).norm() < 1e-12);
        QCOMPARE(colliderDistance(sphere, Vec3(1.2, 0, 0), n), -0.3);
        QVERIFY((n - Vec3::UnitX()).norm() < 1e-12);

        Collider capsule;
        capsule.shape = ColliderShape::Capsule;
        capsule.axis = Vec3(0, 0, 2);
        capsule.radius = 0.1;
        capsule.halfLength = 1.0;
        QVERIFY(capsule.validate().ok());
        QCOMPARE(capsule.axis, Vec3(0, 0, 1));
        QVERIFY(std::abs(colliderDistance(capsule, Vec3(0.3, 0, 0.5), n) - 0.2) < 1e-12);  // beside the segment
        QVERIFY((n - Vec3::UnitX()).norm() < 1e-12);
        QVERIFY(std::abs(colliderDistance(capsule, Vec3(0, 0, 1.5), n) - 0.4) < 1e-12);  // past an end
        QVERIFY((n - Vec3::UnitZ()).norm() < 1e-12);

        Collider box;
        box.shape = ColliderShape::Box;
        box.halfExtents = Vec3(1, 0.5, 0.25);
        box.axes = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix();  // x along world y
        QVERIFY(box.validate().ok());
        QVERIFY(std::abs(colliderDistance(box, Vec3(0, 1.5, 0), n) - 0.5) < 1e-12);  // off its long face... its x end
        QVERIFY((n - Vec3::UnitY()).norm() < 1e-12);
        QVERIFY(std::abs(colliderDistance(box, Vec3(0.4, 0, 0), n) + 0.1) < 1e-12);  // inside, nearest face
        QVERIFY((n - Vec3::UnitX()).norm() < 1e-12);
        QVERIFY(std::abs(colliderDistance(box, Vec3(0.5 + 3, 1 + 4, 0), n) - 5.0) < 1e-12);  // off a corner edge

        Collider bad;
        bad.radius = -1;
        QVERIFY(!bad.validate().ok() && bad.validate().message().find("radius") != std::string::npos);
        bad = Collider{};
        bad.shape = ColliderShape::Box;
        bad.axes(0, 0) = 2.0;
        QVERIFY(!bad.validate().ok() && bad.validate().message().find("orthonormal") != std::string::npos);
    }

    // A mesh collider's signed distance (FCL's nearest point, the pseudonormal's sign) equals the exact box's
    // at points all round faces, edges and corners, inside and out; a fine sphere mesh's is the sphere's to
    // within the facets' sag; bad meshes are refused with a reason.
    void meshSurfaceDistances() {
        const Vec3 half(0.5, 0.3, 0.4);
        const auto box = MeshSurface::create(boxMesh(half));
        QVERIFY2(box, box ? "" : box.message().c_str());
        Collider exact;
        exact.shape = ColliderShape::Box;
        exact.halfExtents = half;
        Collider asMesh;
        asMesh.shape = ColliderShape::Mesh;
        asMesh.surface = box.value();
        asMesh.centre = Vec3(0.2, -0.1, 0.3);
        asMesh.scale = 2.0;
        asMesh.axes = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
        QVERIFY(asMesh.validate().ok());
        std::mt19937 random(7);
        std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
        int inside = 0, signs = 0;
        double worst = 0.0;
        for (int i = 0; i < 4000; ++i) {
            const Vec3 local(coordinate(random), coordinate(random), coordinate(random));
            Vec3 n1, n2;
            const double d = colliderDistance(exact, local, n1);
            const double fromMesh = box.value()->signedDistance(local, n2);
            worst = std::max(worst, std::abs(d - fromMesh));
            inside += d < 0.0;
            signs += (d < 0.0) == (fromMesh < 0.0);
            // Placed, turned and scaled: the same distance, scaled, and the normal turned.
            Vec3 n3;
            const double placed = colliderDistance(asMesh, asMesh.centre + asMesh.axes * (2.0 * local), n3);
            QVERIFY(std::abs(placed - 2.0 * fromMesh) < 1e-9);
            QVERIFY((n3 - asMesh.axes * n2).norm() < 1e-9);
        }
        qInfo("box mesh: %d of 4000 points inside, largest distance difference %.1e m", inside, worst);
        QVERIFY(inside > 150);  // the box fills 6% of the cube the points are drawn from
        QCOMPARE(signs, 4000);
        QVERIFY(worst < 1e-7);  // the mesh keeps its corners in float

        const double radius = 0.3;
        const auto sphere = MeshSurface::create(makeUvEllipsoid(32, 64, Vec3::Constant(radius)));
        QVERIFY(sphere);
        const double sag = radius * (1.0 - std::cos(std::numbers::pi / 32.0));  // deepest chord below the sphere
        for (int i = 0; i < 2000; ++i) {
            const Vec3 p(coordinate(random), coordinate(random), coordinate(random));
            Vec3 n;
            const double d = sphere.value()->signedDistance(0.5 * p, n, 1.0);  // exact, not a bound, outside too
            const double truth = 0.5 * p.norm() - radius;
            QVERIFY2(std::abs(d - truth) <= sag * 1.01, qPrintable(QString("%1 against %2").arg(d).arg(truth)));
            if (std::abs(truth) > sag)
                QCOMPARE(d < 0.0, truth < 0.0);
        }

        // One surface per distinct mesh while it is held (the editor's rebuilds find it built).
        const Mesh ball = makeUvEllipsoid(8, 16, Vec3::Constant(radius));
        const auto a = MeshSurface::shared(ball), b = MeshSurface::shared(ball);
        QVERIFY(a && b && a.value() == b.value());
        Mesh moved = ball;
        moved.positions[3].x() += 1e-3f;
        QVERIFY(MeshSurface::shared(moved).value() != a.value());

        QVERIFY(!MeshSurface::create(Mesh{}));
        Mesh broken = boxMesh(half);
        broken.triangles[3][1] = 99;
        const auto refused = MeshSurface::create(broken);
        QVERIFY(!refused);
        QVERIFY2(refused.message().find("index") != std::string::npos, refused.message().c_str());
        Collider noMesh;
        noMesh.shape = ColliderShape::Mesh;
        QVERIFY(!noMesh.validate().ok());
    }

    void droppedBallRestsOnTheCollider_data() {
        QTest::addColumn<int>("integrator");
        QTest::addColumn<int>("shape");
        for (IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                                 IntegratorKind::Xpbd})
            for (ColliderShape s : {ColliderShape::Sphere, ColliderShape::Capsule, ColliderShape::Box, ColliderShape::Mesh}) {
                // A mesh collider answers through the same contact pass as the others, and each of its
                // queries costs FCL ~10 µs (a sphere's: nanoseconds): the two default integrators carry it.
                if (s == ColliderShape::Mesh && k != IntegratorKind::Verlet && k != IntegratorKind::ImplicitEuler)
                    continue;
                QTest::newRow(qPrintable(QString("%1 on a %2").arg(integratorName(k).data()).arg(colliderShapeName(s))))
                    << int(k) << int(s);
            }
    }

    // The must-show: dropped from 0.15 m above it, a soft pancake lands on the collider's top (draping over
    // a sphere or a log): no mesh sample point ends a step inside by more than 1% of the body's size (the
    // mesh's diagonal), and after 2 s it is at rest (every node slower than 5 mm/s) and stays so (4 s).
    void droppedBallRestsOnTheCollider() {
        QFETCH(int, integrator);
        QFETCH(int, shape);
        Collider c;
        c.shape = ColliderShape(shape);
        c.centre = Vec3(0, -0.45, 0);
        c.radius = 0.3;
        c.axis = Vec3::UnitX();  // a log lying across
        c.halfLength = 0.5;
        c.halfExtents = Vec3(0.5, 0.3, 0.5);
        if (c.shape == ColliderShape::Mesh)  // a rock: the sphere again, as 3,968 triangles
            c.surface = MeshSurface::create(makeUvEllipsoid(32, 64, Vec3::Constant(0.3))).value();
        c.friction = 1.0;
        QVERIFY(c.validate().ok());
        const Ball ball(Vec3(0, 0.04, 0));  // 0.15 m above the collider's top (y = -0.15)
        const auto body = ball.body();
        QVERIFY(body->contacts().size() > 100);
        const double size = (ball.mesh.bounds().max - ball.mesh.bounds().min).norm();
        SimulationSettings settings = settingsFor(IntegratorKind(integrator), 1.0 / 240.0);
        Simulator sim(body, settings);
        ExternalForces f;
        f.gravity = Vec3(0, -9.81, 0);
        f.colliders.push_back(c);
        // After each step: the deepest sample point inside, and every mesh vertex (not only the samples).
        const Binding binding = Binding::create(ball.lattice, ball.mesh.positions, ball.mesh.normals);
        std::vector<Vec3f> positions(ball.mesh.positions.size()), normals(positions.size());
        double deepestSample = 0.0, deepestVertex = 0.0;
        int contacts = 0, problems = 0;
        std::vector<double> fastestAt;  // each half second
        for (int i = 0; i < 960; ++i) {
            const StepReport r = sim.step(f);
            if ((i + 1) % 120 == 0) {
                double v = 0.0;
                for (std::size_t n = 0; n < body->nodeCount(); ++n)
                    v = std::max(v, sim.state().velocity[n].norm());
                fastestAt.push_back(v);
            }
            contacts += r.colliderContacts;
            problems += !r.problem.empty();
            const ContactPoints& points = body->contacts();
            for (std::size_t q = 0; q < points.size(); ++q) {
                Vec3 n;
                deepestSample = std::max(deepestSample, -colliderDistance(c, points.at(q, sim.state().position), n));
            }
            binding.evaluate(sim.state().position, positions, normals, 1);
            for (const Vec3f& p : positions) {
                Vec3 n;
                deepestVertex = std::max(deepestVertex, -colliderDistance(c, p.cast<double>(), n));
            }
        }
        const double fastest = fastestAt[3];  // at 2 s
        Vec3 centroid = Vec3::Zero();
        double lowest = 1e9;
        binding.evaluate(sim.state().position, positions, normals, 1);
        for (const Vec3f& p : positions) {
            lowest = std::min(lowest, double(p.y()));
            centroid += p.cast<double>() / double(positions.size());
        }
        QString trend;
        for (double v : fastestAt)
            trend += QString(" %1").arg(v, 0, 'e', 1);
        qInfo("%s: fastest node every 0.5 s:%s", QTest::currentDataTag(), qPrintable(trend));
        qInfo("%s: deepest sample %.2e m (%.3f%% of %.3f m), deepest vertex %.2e m; %d contacts; at 2 s fastest node "
              "%.2e m/s; at 4 s lowest vertex y = %.4f m, centroid (%.4f, %.4f, %.4f), %d reports",
              QTest::currentDataTag(), deepestSample, 100.0 * deepestSample / size, size, deepestVertex, contacts,
              fastest, lowest, centroid.x(), centroid.y(), centroid.z(), problems);
        QVERIFY(contacts > 0);
        QVERIFY2(deepestSample <= 0.01 * size, qPrintable(QString::number(deepestSample)));
        // At rest at 2 s, and still at 4 s (no jitter building up).
        QVERIFY2(fastest < 5e-3, qPrintable(QString("%1 m/s").arg(fastest)));
        QVERIFY2(fastestAt.back() < 5e-3, qPrintable(QString("%1 m/s at 4 s").arg(fastestAt.back())));
        // On top, not slid off: centred over the collider, within a few centimetres of its top (a soft pancake
        // drapes over a sphere: its centroid ends 1.3 cm below the top).
        QVERIFY2(std::hypot(centroid.x(), centroid.z()) < 0.01 && std::abs(centroid.y() + 0.15) < 0.03,
                 qPrintable(QString("centroid (%1, %2, %3)").arg(centroid.x()).arg(centroid.y()).arg(centroid.z())));
        QCOMPARE(problems, 0);
    }
};

QTEST_GUILESS_MAIN(TestColliders)
#include "test_colliders.moc"
