// Mathematical facts of the Bezier / B-spline map and its binding.
#include "core/geometry/binding.h"
#include "core/geometry/lattice.h"
#include "core/geometry/node_field_fit.h"
#include "helpers/test_support.h"

#include <Eigen/Geometry>
#include <QtTest>

using namespace softtouch;

namespace {

double binomial(int n, int k) {
    double r = 1.0;
    for (int i = 1; i <= k; ++i)
        r = r * (n - k + i) / i;
    return r;
}

/// The paper's cubic Bernstein, written out independently of AxisBasis.
double bernstein(int n, int i, double t) { return binomial(n, i) * std::pow(t, i) * std::pow(1.0 - t, n - i); }

Lattice makeLattice(LatticeKind kind, std::array<int, 3> nodes, const OrientedBox& box) {
    auto lattice = Lattice::create({kind, nodes}, box);
    if (!lattice)
        qFatal("%s", lattice.message().c_str());
    return lattice.value();
}

OrientedBox rotatedBox() {
    OrientedBox box;
    box.axes = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    box.origin = Vec3(10.0, -4.0, 2.5);  // far from the origin on purpose: float precision
    box.size = Vec3(2.0, 0.5, 1.25);
    return box;
}

std::vector<Vec3f> pointsInBox(const OrientedBox& box, int count) {
    std::vector<Vec3f> out;
    for (const Vec3f& t : test::scatter(count, Vec3::Zero(), Vec3::Ones()))
        out.push_back(box.toWorld(t.cast<double>()).cast<float>());
    return out;
}

}  // namespace

class TestLattice : public QObject {
    Q_OBJECT
private slots:
    void bernsteinMatchesPaperFormula();
    void partitionOfUnity_data();
    void partitionOfUnity();
    void slopesMatchFiniteDifferences();
    void identityReproducesMesh_data();
    void identityReproducesMesh();
    void affinePrecision_data();
    void affinePrecision();
    void sphereNormalsUnderAffineMap();
    void bsplineSupportIsLocal();
    void boxFitHandlesDegenerateMeshes();
    void badShapesAreRejected();
    void nodeFieldFromPoints();
};

void TestLattice::bernsteinMatchesPaperFormula() {
    for (int n = 1; n <= 7; ++n) {
        const AxisBasis basis = AxisBasis::bezier(n + 1);
        for (double t = 0.0; t <= 1.0; t += 0.0625) {
            const BasisSample s = basis.sample(t);
            QCOMPARE(s.first, 0);
            QCOMPARE(s.order, n + 1);
            for (int i = 0; i <= n; ++i)
                QVERIFY2(std::abs(s.value[std::size_t(i)] - bernstein(n, i, t)) < 1e-14,
                         qPrintable(QString("degree %1 i %2 t %3").arg(n).arg(i).arg(t)));
        }
    }
}

void TestLattice::partitionOfUnity_data() {
    QTest::addColumn<int>("kind");
    QTest::addColumn<int>("nodes");
    QTest::newRow("bezier-4") << int(LatticeKind::Bezier) << 4;
    QTest::newRow("bezier-8") << int(LatticeKind::Bezier) << 8;
    QTest::newRow("bspline-5") << int(LatticeKind::BSpline) << 5;
    QTest::newRow("bspline-12") << int(LatticeKind::BSpline) << 12;
}

void TestLattice::partitionOfUnity() {
    QFETCH(int, kind);
    QFETCH(int, nodes);
    const Lattice lattice = makeLattice(LatticeKind(kind), {nodes, 4, 3}, OrientedBox{});
    for (const Vec3f& p : test::scatter(500, Vec3::Zero(), Vec3::Ones())) {
        double sum = 0.0;
        for (const NodeWeight& w : lattice.weights(p.cast<double>())) {
            QVERIFY(w.weight >= -1e-15);
            sum += w.weight;
        }
        QVERIFY2(std::abs(sum - 1.0) < 1e-12, qPrintable(QString::number(sum, 'g', 17)));
    }
}

void TestLattice::slopesMatchFiniteDifferences() {
    for (const AxisBasis& basis : {AxisBasis::bezier(4), AxisBasis::bezier(7), AxisBasis::bspline(9, 3)}) {
        for (double t = 0.013; t < 1.0; t += 0.071) {
            const double h = 1e-6;
            const BasisSample s = basis.sample(t);
            const BasisSample a = basis.sample(t - h);
            const BasisSample b = basis.sample(t + h);
            if (a.first != s.first || b.first != s.first)
                continue;  // straddles a knot
            for (int r = 0; r < s.order; ++r) {
                const double fd = (b.value[std::size_t(r)] - a.value[std::size_t(r)]) / (2 * h);
                QVERIFY2(std::abs(fd - s.slope[std::size_t(r)]) < 1e-6 * (1 + std::abs(fd)),
                         qPrintable(QString("t %1 r %2: %3 vs %4").arg(t).arg(r).arg(fd).arg(s.slope[std::size_t(r)])));
            }
        }
    }
}

void TestLattice::identityReproducesMesh_data() {
    QTest::addColumn<int>("kind");
    QTest::addColumn<int>("nx");
    QTest::newRow("bezier-4x4x4") << int(LatticeKind::Bezier) << 4;
    QTest::newRow("bezier-8x4x4") << int(LatticeKind::Bezier) << 8;
    QTest::newRow("bspline-8x4x4") << int(LatticeKind::BSpline) << 8;
}

void TestLattice::identityReproducesMesh() {
    QFETCH(int, kind);
    QFETCH(int, nx);
    const OrientedBox box = rotatedBox();
    const Lattice lattice = makeLattice(LatticeKind(kind), {nx, 4, 4}, box);
    const std::vector<Vec3f> points = pointsInBox(box, 20000);
    const std::vector<Vec3f> normals(points.size(), Vec3f::UnitX());
    const Binding binding = Binding::create(lattice, points, normals);
    std::vector<Vec3f> out(points.size());
    binding.evaluate(lattice.restNodes(), out, {});
    double worst = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i)
        worst = std::max(worst, (out[i] - points[i]).cast<double>().norm());
    QVERIFY2(worst <= 1e-6 * box.diagonal(), qPrintable(QString("worst %1 of diagonal").arg(worst / box.diagonal())));
}

void TestLattice::affinePrecision_data() { identityReproducesMesh_data(); }

void TestLattice::affinePrecision() {
    QFETCH(int, kind);
    QFETCH(int, nx);
    const OrientedBox box = rotatedBox();
    const Lattice lattice = makeLattice(LatticeKind(kind), {nx, 4, 4}, box);
    Mat3 A;
    A << 1.3, 0.2, -0.1, 0.05, 0.7, 0.3, -0.2, 0.1, 1.1;
    const Vec3 t(0.4, -1.2, 3.0);
    std::vector<Vec3> nodes = lattice.restNodes();
    for (Vec3& n : nodes)
        n = A * n + t;
    const std::vector<Vec3f> points = pointsInBox(box, 5000);
    const Binding binding = Binding::create(lattice, points, std::vector<Vec3f>(points.size(), Vec3f::UnitY()));
    std::vector<Vec3f> out(points.size());
    binding.evaluate(nodes, out, {});
    double worst = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i)
        worst = std::max(worst, (out[i].cast<double>() - (A * points[i].cast<double>() + t)).norm());
    QVERIFY2(worst <= 1e-6 * (A * box.size).norm() * 2, qPrintable(QString("worst %1").arg(worst)));
}

void TestLattice::sphereNormalsUnderAffineMap() {
    const Mesh sphere = test::makeSphere(0.8, Vec3(0.3, -0.2, 0.1));
    auto box = fitBox(sphere.positions);
    QVERIFY(box.ok());
    for (LatticeKind kind : {LatticeKind::Bezier, LatticeKind::BSpline}) {
        const Lattice lattice = makeLattice(kind, {kind == LatticeKind::Bezier ? 4 : 7, 4, 5}, box.value());
        Mat3 A;
        A << 1.5, 0.4, 0.0, -0.3, 0.6, 0.2, 0.1, 0.0, 1.2;
        std::vector<Vec3> nodes = lattice.restNodes();
        for (Vec3& n : nodes)
            n = A * n + Vec3(1, 2, 3);
        const Binding binding = Binding::create(lattice, sphere.positions, sphere.normals);
        std::vector<Vec3f> positions(sphere.positions.size()), normals(sphere.positions.size());
        binding.evaluate(nodes, positions, normals);
        const Mat3 inverseTranspose = A.inverse().transpose();
        double worst = 0.0;
        for (std::size_t i = 0; i < normals.size(); ++i) {
            const Vec3 expected = (inverseTranspose * sphere.normals[i].cast<double>()).normalized();
            worst = std::max(worst, (normals[i].cast<double>() - expected).norm());
        }
        QVERIFY2(worst < 1e-5, qPrintable(QString("worst normal error %1").arg(worst)));
    }
}

void TestLattice::bsplineSupportIsLocal() {
    const Lattice lattice = makeLattice(LatticeKind::BSpline, {8, 4, 4}, OrientedBox{});
    for (const Vec3f& p : test::scatter(200, Vec3::Zero(), Vec3::Ones())) {
        const auto weights = lattice.weights(p.cast<double>());
        QCOMPARE(int(weights.size()), 64);  // 4x4x4 nodes, not 8x4x4
        int nonZero = 0;
        for (const NodeWeight& w : weights)
            nonZero += w.weight > 0.0;
        QVERIFY(nonZero <= 64);
    }
    // A node far along u does not move a vertex near u = 0.
    std::vector<Vec3> nodes = lattice.restNodes();
    nodes[std::size_t(lattice.index(7, 2, 2))] += Vec3(0, 1, 0);
    const Vec3 near(0.05, 0.5, 0.5);
    QCOMPARE(lattice.evaluate(near, nodes), lattice.evaluate(near, lattice.restNodes()));
}

void TestLattice::boxFitHandlesDegenerateMeshes() {
    // A flat square (zero thickness along z), a line, a single point.
    const std::vector<Vec3f> flat{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const std::vector<Vec3f> line{{0, 0, 0}, {2, 0, 0}};
    const std::vector<Vec3f> point{{5, 5, 5}};
    for (const auto* pts : {&flat, &line, &point}) {
        auto box = fitBox(*pts);
        QVERIFY(box.ok());
        QVERIFY(box->validate().ok());
        QVERIFY((box->size.array() > 0.0).all());
        for (const Vec3f& p : *pts) {
            const Vec3 uvw = box->toParameters(p.cast<double>());
            QVERIFY((uvw.array() > 0.0).all() && (uvw.array() < 1.0).all());
        }
    }
    QVERIFY(!fitBox(std::vector<Vec3f>{}).ok());
    QVERIFY(!fitBox(std::vector<Vec3f>{{0, std::nanf(""), 0}}).ok());
    // Oriented fit puts u along the longest direction.
    std::vector<Vec3f> diagonal;
    for (int i = 0; i < 50; ++i)
        diagonal.push_back(Vec3f(i, i, 0.01f * float(i % 3)));
    auto oriented = fitBox(diagonal, BoxFitSettings{true, 0.0, 0.05});
    QVERIFY(oriented.ok());
    QVERIFY(std::abs(std::abs(oriented->axes.col(0).dot(Vec3(1, 1, 0).normalized())) - 1.0) < 1e-6);
}

void TestLattice::badShapesAreRejected() {
    QVERIFY(!Lattice::create({LatticeKind::Bezier, {9, 4, 4}}, OrientedBox{}).ok());
    QVERIFY(!Lattice::create({LatticeKind::Bezier, {1, 4, 4}}, OrientedBox{}).ok());
    OrientedBox flat;
    flat.size = Vec3(1, 0, 1);
    const auto result = Lattice::create({LatticeKind::Bezier, {4, 4, 4}}, flat);
    QVERIFY(!result.ok());
    QVERIFY(result.message().find("size") != std::string::npos);
}

// A vertex group carried onto the nodes (goalWeightPoints): 1 everywhere is 1 on every node, exactly; a ramp
// along u gives nodes that rise along u and stay within the points' range; a B-spline node no point reaches
// takes its nearest point's value; bad input is an error, not a field.
void TestLattice::nodeFieldFromPoints() {
    OrientedBox box;
    box.size = Vec3(2.0, 1.0, 0.5);
    std::vector<PointValue> ones, ramp;
    for (int i = 0; i <= 20; ++i)
        for (int j = 0; j <= 6; ++j)
            for (int k = 0; k <= 4; ++k) {
                const Vec3 p = box.toWorld(Vec3(i / 20.0, j / 6.0, k / 4.0));
                ones.push_back({p, 1.0});
                ramp.push_back({p, i / 20.0});
            }
    for (const LatticeShape shape : {LatticeShape{LatticeKind::Bezier, {4, 4, 4}}, LatticeShape{LatticeKind::BSpline, {9, 5, 4}}}) {
        const Lattice lattice = Lattice::create(shape, box).value();
        const auto all = fitNodeField(lattice, ones);
        QVERIFY2(all.ok(), all.message().c_str());
        for (double w : all.value())
            QCOMPARE(w, 1.0);
        const std::vector<double> field = fitNodeField(lattice, ramp).value();
        for (int k = 0; k < lattice.count(2); ++k)
            for (int j = 0; j < lattice.count(1); ++j)
                for (int i = 0; i < lattice.count(0); ++i) {
                    const double w = field[std::size_t(lattice.index(i, j, k))];
                    QVERIFY(w >= 0.0 && w <= 1.0);
                    if (i > 0)
                        QVERIFY2(w > field[std::size_t(lattice.index(i - 1, j, k))], qPrintable(QString("node %1 %2 %3").arg(i).arg(j).arg(k)));
                }
        // The end nodes lean to the ends' values: the field is the points', not a blur of it.
        QVERIFY(field[0] < 0.2 && field[std::size_t(lattice.index(lattice.count(0) - 1, 0, 0))] > 0.8);
    }
    // Points in one corner of a B-spline box: the far nodes weigh none of them and take the nearest point's value.
    const Lattice fine = Lattice::create({LatticeKind::BSpline, {9, 9, 9}}, box).value();
    const std::vector<PointValue> corner{{box.toWorld(Vec3(0.01, 0.01, 0.01)), 0.25}, {box.toWorld(Vec3(0.02, 0.01, 0.01)), 0.75}};
    const std::vector<double> far = fitNodeField(fine, corner).value();
    QCOMPARE(far[std::size_t(fine.index(8, 8, 8))], 0.75);
    QVERIFY(!fitNodeField(fine, {}).ok());
    QVERIFY(!fitNodeField(fine, std::vector<PointValue>{{Vec3(0, 0, 0), std::nan("")}}).ok());
}

QTEST_GUILESS_MAIN(TestLattice)
#include "test_lattice.moc"
