// Colliders beyond planes (core/body/colliders.h): the shapes' signed distances, and a ball dropped on a sphere,
// a capsule and a box with every integrator: no mesh sample point ends a step inside by more than 1% of the
// body's size, and it comes to rest.

#include "helpers/physics_fixture.h"

#include "core/body/colliders.h"
#include "core/geometry/binding.h"
#include "core/geometry/mesh_surface.h"
#include "core/geometry/primitives.h"

#include "core/base/ranges.h"

#include <chrono>
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

/// A square of two triangles, `half` wide each way, at height y, facing +y: the simplest open mesh.
Mesh planeMesh(double half, double y) {
    Mesh m;
    for (const auto& [x, z] : {std::pair{-half, -half}, std::pair{-half, half}, std::pair{half, half}, std::pair{half, -half}})
        m.positions.emplace_back(float(x), float(y), float(z));
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

/// What a pancake dropped on a collider did in 4 s (droppedBallRestsOnTheCollider's must-show).
struct Drop {
    double size = 0.0;            ///< The pancake's diagonal, metres.
    double deepestSample = 0.0;   ///< Deepest contact point inside after any step, metres.
    double deepestVertex = 0.0;   ///< Deepest mesh vertex inside after any step, metres.
    std::vector<double> fastestAt;  ///< Fastest node every half second, m/s.
    Vec3 centroid = Vec3::Zero();   ///< Of the vertices at 4 s.
    int contacts = 0;
    int problems = 0;
};

/// Drops the pancake from 0.15 m above the top of `c` (at y = -0.15) and simulates 4 s at 240 Hz; `label` names
/// the run in the log.
Drop dropPancakeOn(const Collider& c, IntegratorKind integrator, const char* label) {
    const Ball ball(Vec3(0, 0.04, 0));
    const auto body = ball.body();
    Drop drop;
    drop.size = (ball.mesh.bounds().max - ball.mesh.bounds().min).norm();
    Simulator sim(body, settingsFor(integrator, 1.0 / 240.0));
    ExternalForces f;
    f.gravity = Vec3(0, -9.81, 0);
    f.colliders.push_back(c);
    // After each step: the deepest sample point inside, and every mesh vertex (not only the samples).
    const Binding binding = Binding::create(ball.lattice, ball.mesh.positions, ball.mesh.normals);
    std::vector<Vec3f> positions(ball.mesh.positions.size()), normals(positions.size());
    for (int i = 0; i < 960; ++i) {
        const StepReport r = sim.step(f);
        if ((i + 1) % 120 == 0) {
            double v = 0.0;
            for (std::size_t n = 0; n < body->nodeCount(); ++n)
                v = std::max(v, sim.state().velocity[n].norm());
            drop.fastestAt.push_back(v);
        }
        drop.contacts += r.colliderContacts;
        drop.problems += !r.problem.empty();
        const ContactPoints& points = body->contacts();
        for (std::size_t q = 0; q < points.size(); ++q) {
            Vec3 n;
            drop.deepestSample = std::max(drop.deepestSample, -colliderDistance(c, points.at(q, sim.state().position), n));
        }
        binding.evaluate(sim.state().position, positions, normals, 1);
        for (const Vec3f& p : positions) {
            Vec3 n;
            drop.deepestVertex = std::max(drop.deepestVertex, -colliderDistance(c, p.cast<double>(), n));
        }
    }
    double lowest = 1e9;
    binding.evaluate(sim.state().position, positions, normals, 1);
    for (const Vec3f& p : positions) {
        lowest = std::min(lowest, double(p.y()));
        drop.centroid += p.cast<double>() / double(positions.size());
    }
    QString trend;
    for (double v : drop.fastestAt)
        trend += QString(" %1").arg(v, 0, 'e', 1);
    qInfo("%s: fastest node every 0.5 s:%s", label, qPrintable(trend));
    qInfo("%s: deepest sample %.2e m (%.3f%% of %.3f m), deepest vertex %.2e m; %d contacts; at 2 s fastest node "
          "%.2e m/s; at 4 s lowest vertex y = %.4f m, centroid (%.4f, %.4f, %.4f), %d reports",
          label, drop.deepestSample, 100.0 * drop.deepestSample / drop.size, drop.size, drop.deepestVertex,
          drop.contacts, drop.fastestAt[3], lowest, drop.centroid.x(), drop.centroid.y(), drop.centroid.z(), drop.problems);
    return drop;
}

/// The must-show's checks: no sample point ends a step inside by more than 1% of the body's size; at rest at
/// 2 s and still at 4 s (every node slower than 5 mm/s: no jitter building up); on top, not slid off or
/// through (centred over the collider, within a few centimetres of its top: a soft pancake drapes over a
/// sphere, its centroid 1.3 cm below the top).
void checkRestsOnTop(const Drop& drop) {
    QVERIFY(drop.contacts > 0);
    QVERIFY2(drop.deepestSample <= 0.01 * drop.size, qPrintable(QString::number(drop.deepestSample)));
    QVERIFY2(drop.fastestAt[3] < 5e-3, qPrintable(QString("%1 m/s").arg(drop.fastestAt[3])));
    QVERIFY2(drop.fastestAt.back() < 5e-3, qPrintable(QString("%1 m/s at 4 s").arg(drop.fastestAt.back())));
    const Vec3& c = drop.centroid;
    QVERIFY2(std::hypot(c.x(), c.z()) < 0.01 && std::abs(c.y() + 0.15) < 0.03,
             qPrintable(QString("centroid (%1, %2, %3)").arg(c.x()).arg(c.y()).arg(c.z())));
    QCOMPARE(drop.problems, 0);
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

    // A collider's mesh is what its sign needs (core/geometry/mesh_surface.h): closed and wound outwards, or said to be a
    // one-sided sheet. An open box, a lone plane, a triangle doubled back on itself, an inside-out box, a box
    // with a face turned over and one with a fin are refused, each with its counts (before, every one was
    // accepted, and a body fell through the open ones). Corners split by their normals still join, and a
    // body's own surface (body contacts) is read as given.
    void colliderMeshesMustBeClosed() {
        const Vec3 half(0.5, 0.3, 0.4);
        auto refusal = [](const Mesh& mesh, SurfaceSides sides) {
            const auto made = MeshSurface::create(mesh, "rock.obj", sides);
            return made ? std::string("accepted") : made.message();
        };
        const std::string mustBeClosed = ": a collider mesh must be closed, or set \"oneSided\": true to use it as a "
                                         "surface that pushes along its normals";
        const std::string mend = ": a collider mesh must be closed, each edge joining exactly two triangles wound the same "
                                 "way round; mend it in your modelling tool";

        Mesh openBox = boxMesh(half);  // without its bottom's two triangles
        std::erase_if(openBox.triangles, [&](const auto& t) {
            return openBox.positions[t[0]].y() < 0.0f && openBox.positions[t[1]].y() < 0.0f && openBox.positions[t[2]].y() < 0.0f;
        });
        QCOMPARE(openBox.triangles.size(), std::size_t(10));
        QCOMPARE(refusal(openBox, SurfaceSides::Closed), "the collider mesh rock.obj has 4 open edges" + mustBeClosed);
        QCOMPARE(refusal(openBox, SurfaceSides::OneSided), std::string("accepted"));

        const Mesh plane = planeMesh(0.5, 0.0);
        QCOMPARE(refusal(plane, SurfaceSides::Closed), "the collider mesh rock.obj has 4 open edges" + mustBeClosed);
        const auto sheet = MeshSurface::create(plane, "rock.obj", SurfaceSides::OneSided);
        QVERIFY(sheet);
        QCOMPARE(sheet.value()->topology().openEdges, std::size_t(4));
        QCOMPARE(sheet.value()->sides(), SurfaceSides::OneSided);
        QVERIFY(MeshSurface::shared(plane));  // a body's surface: as given

        Mesh doubled = plane;  // closed (each edge twice, opposite ways) around nothing
        doubled.triangles = {{0, 1, 2}, {0, 2, 1}};
        QCOMPARE(refusal(doubled, SurfaceSides::Closed),
                 std::string("the collider mesh rock.obj encloses no volume: a collider mesh must be a solid, or set "
                             "\"oneSided\": true to use it as a surface that pushes along its normals"));
        Mesh line = plane;  // three corners in a row: no area either way
        line.positions[2] = Vec3f(0.0f, 0.0f, 0.0f);
        line.triangles = {{0, 2, 1}};
        line.positions[1] = Vec3f(0.5f, 0.0f, 0.5f);
        QCOMPARE(refusal(line, SurfaceSides::OneSided),
                 std::string("the collider mesh rock.obj has no area: its only triangle has zero area"));

        Mesh insideOut = boxMesh(half);
        for (auto& t : insideOut.triangles)
            std::swap(t[1], t[2]);
        QCOMPARE(refusal(insideOut, SurfaceSides::Closed),
                 std::string("the collider mesh rock.obj faces inwards (its signed volume is negative): flip its normals "
                             "in your modelling tool"));
        Mesh turned = boxMesh(half);  // one face's two triangles turned over: its four edges flip the winding
        for (std::size_t t : {0, 1})
            std::swap(turned.triangles[t][1], turned.triangles[t][2]);
        QCOMPARE(refusal(turned, SurfaceSides::Closed), "the collider mesh rock.obj has 4 edges where the winding flips" + mend);
        Mesh fin = boxMesh(half);  // a triangle standing on one of the box's edges
        fin.positions.emplace_back(0.0f, 2.0f, 0.0f);
        fin.triangles.push_back({fin.triangles[0][0], fin.triangles[0][1], std::uint32_t(fin.positions.size() - 1)});
        QCOMPARE(refusal(fin, SurfaceSides::Closed),
                 "the collider mesh rock.obj has 2 open edges and 1 edge shared by more than two triangles" + mend);
        QCOMPARE(refusal(fin, SurfaceSides::OneSided),
                 std::string("the collider mesh rock.obj has 1 edge shared by more than two triangles: each edge of a "
                             "one-sided collider mesh must join at most two triangles, wound the same way round; mend it "
                             "in your modelling tool"));

        // Flat-shaded, as an OBJ with a normal per face imports: every triangle has corners of its own. Joined by
        // position, it is the closed box, with the box's distances.
        Mesh split;
        for (const auto& t : boxMesh(half).triangles) {
            for (std::uint32_t v : t)
                split.positions.push_back(boxMesh(half).positions[v]);
            const auto first = std::uint32_t(split.positions.size() - 3);
            split.triangles.push_back({first, first + 1, first + 2});
        }
        const auto splitBox = MeshSurface::create(split, "rock.obj");
        QVERIFY2(splitBox, splitBox ? "" : splitBox.message().c_str());
        QVERIFY(splitBox.value()->topology().closed());
        QVERIFY(std::abs(splitBox.value()->topology().volume - 8.0 * half.prod()) < 1e-6);
        Vec3 n;
        QVERIFY(std::abs(splitBox.value()->signedDistance(Vec3(0.45, 0.25, 0.35), n) + 0.05) < 1e-6);  // inside, by an edge
        QVERIFY(std::abs(splitBox.value()->signedDistance(Vec3(0.6, 0.4, 0.0), n, 1.0) - std::sqrt(0.02)) < 1e-6);
    }

    // Above ranges::kMaxColliderTriangles a collider mesh is refused at once, with its size and what to do, before
    // anything is built (before, a 1,001,112-triangle rock took 6 s and 931 MB to validate; building 200,000
    // triangles takes over a second here).
    void largeCollidersAreRefusedBeforeTheBuild() {
        Mesh huge;  // a sheet of 317 x 317 squares, cut to one triangle past the limit
        const int cells = 317;
        for (int i = 0; i <= cells; ++i)
            for (int k = 0; k <= cells; ++k)
                huge.positions.emplace_back(float(i), 0.0f, float(k));
        for (std::uint32_t i = 0; i < cells; ++i)
            for (std::uint32_t k = 0; k < cells; ++k) {
                const std::uint32_t a = i * (cells + 1) + k, b = a + cells + 1;
                huge.triangles.push_back({a, a + 1, b + 1});
                huge.triangles.push_back({a, b + 1, b});
            }
        QVERIFY(huge.triangles.size() > ranges::kMaxColliderTriangles);
        huge.triangles.resize(ranges::kMaxColliderTriangles + 1);
        const auto start = std::chrono::steady_clock::now();
        const auto refused = MeshSurface::create(std::move(huge), "huge.ply", SurfaceSides::OneSided);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        QVERIFY(!refused);
        QCOMPARE(refused.message(),
                 std::string("the collider mesh huge.ply has 200001 triangles, more than the 200000 a collider may have: "
                             "decimate it in your modelling tool to at most 200000 triangles"));
        qInfo("refused in %.1f ms", 1e3 * seconds);
        QVERIFY2(seconds < 0.1, qPrintable(QString("%1 s").arg(seconds)));
    }

    // A one-sided sheet pushes along its normals: behind it, within its rim and as deep as it is wide, is
    // inside; beside its rim or deeper, outside (before, every point below a plane lay outside its flat bounds).
    void oneSidedSheetPushesAlongItsNormals() {
        const auto made = MeshSurface::create(planeMesh(0.5, 0.3), "plane.obj", SurfaceSides::OneSided);
        QVERIFY2(made, made ? "" : made.message().c_str());
        const MeshSurface& plane = *made.value();
        QCOMPARE(plane.backDepth(), std::sqrt(2.0));
        Vec3 n;
        QVERIFY(std::abs(plane.signedDistance(Vec3(0.1, 0.4, 0.2), n) - 0.1) < 1e-7);  // in front
        QVERIFY((n - Vec3::UnitY()).norm() < 1e-6);
        QVERIFY(std::abs(plane.signedDistance(Vec3(0.1, 0.29, 0.2), n) + 0.01) < 1e-7);  // just behind: out to the front
        QVERIFY((n - Vec3::UnitY()).norm() < 1e-6);
        QVERIFY(std::abs(plane.signedDistance(Vec3(0.45, -0.7, -0.45), n) + 1.0) < 1e-7);  // a metre behind, by the rim
        QVERIFY((n - Vec3::UnitY()).norm() < 1e-6);
        QVERIFY(plane.signedDistance(Vec3(0.0, 0.3 - 1.5, 0.0), n) > 1.4);       // deeper than it is wide
        QVERIFY(std::abs(plane.signedDistance(Vec3(0.6, 0.2, 0.0), n) - std::sqrt(0.02)) < 1e-7);  // beside, below
        QVERIFY(plane.signedDistance(Vec3(0.5, 0.2, 0.5), n) > 0.0);             // below a corner
        QVERIFY(plane.signedDistance(Vec3(3.0, -0.5, 0.0), n) > 2.0);            // far beside
        Collider c;
        c.shape = ColliderShape::Mesh;
        c.surface = made.value();
        QVERIFY(colliderBoundingRadius(c) > plane.backDepth());  // the contact pass looks behind it too
    }

    // The must-show on two triangles said to be one-sided: a pancake dropped on them rests on them as on the box
    // (before, it fell through). Heavy: every point near a one-sided sheet takes an exact query (no grid).
    void bodyRestsOnAOneSidedPlane() {
        const auto made = MeshSurface::create(planeMesh(0.5, 0.3), "plane.obj", SurfaceSides::OneSided);
        QVERIFY2(made, made ? "" : made.message().c_str());
        Collider c;
        c.shape = ColliderShape::Mesh;
        c.centre = Vec3(0, -0.45, 0);  // its top at y = -0.15, as the others'
        c.surface = made.value();
        c.friction = 1.0;
        QVERIFY(c.validate().ok());
        checkRestsOnTop(dropPancakeOn(c, IntegratorKind::Verlet, "verlet on a one-sided plane"));
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
        checkRestsOnTop(dropPancakeOn(c, IntegratorKind(integrator), QTest::currentDataTag()));
    }
};

QTEST_GUILESS_MAIN(TestColliders)
#include "test_colliders.moc"
