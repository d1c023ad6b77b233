// Lattice spring topology: counts, voids, automatic void detection.
#include "core/lattice_body.h"
#include "test_support.h"

#include <QtTest>
#include <set>

using namespace softtouch;

namespace {

Lattice makeLattice(std::array<int, 3> nodes, LatticeKind kind = LatticeKind::BSpline) {
    return Lattice::create({kind, nodes}, OrientedBox{}).value();
}

/// Unique counts from the grid's formulas, written independently of latticeSprings().
SpringCounts expectedCounts(int nx, int ny, int nz) {
    SpringCounts c;
    c.edges = (nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1);
    c.faceDiagonals = 2 * ((nx - 1) * (ny - 1) * nz + (nx - 1) * ny * (nz - 1) + nx * (ny - 1) * (nz - 1));
    c.bodyDiagonals = 4 * (nx - 1) * (ny - 1) * (nz - 1);
    return c;
}

}  // namespace

class TestSprings : public QObject {
    Q_OBJECT
private slots:
    void counts_data();
    void counts();
    void springsAreUniqueAndRestLengthsMatch();
    void voidNodeRemovesExactlyItsSprings();
    void anisotropySoftensOneAxis();
    void autoVoidFindsEmptyCells();
    void badMaterialNamesTheNode();
};

void TestSprings::counts_data() {
    QTest::addColumn<int>("nx");
    QTest::addColumn<int>("ny");
    QTest::addColumn<int>("nz");
    QTest::addColumn<int>("total");
    QTest::newRow("2x2x2 (one cube)") << 2 << 2 << 2 << 28;
    QTest::newRow("4x4x4 (paper)") << 4 << 4 << 4 << 468;
    QTest::newRow("4x6x3") << 4 << 6 << 3 << 524;
}

void TestSprings::counts() {
    QFETCH(int, nx);
    QFETCH(int, ny);
    QFETCH(int, nz);
    QFETCH(int, total);
    const Lattice lattice = makeLattice({nx, ny, nz});
    const auto springs = latticeSprings(lattice, uniformMaterial(lattice, 0.01, 80, 0.1));
    const SpringCounts c = countSprings(springs);
    const SpringCounts e = expectedCounts(nx, ny, nz);
    QCOMPARE(c.edges, e.edges);
    QCOMPARE(c.faceDiagonals, e.faceDiagonals);
    QCOMPARE(c.bodyDiagonals, e.bodyDiagonals);
    QCOMPARE(c.total(), total);
    if (nx == 4 && ny == 4 && nz == 4) {
        QCOMPARE(c.edges, 144);
        QCOMPARE(c.faceDiagonals, 216);
        QCOMPARE(c.bodyDiagonals, 108);
    }
}

void TestSprings::springsAreUniqueAndRestLengthsMatch() {
    OrientedBox box;
    box.size = Vec3(3, 2, 1);
    const Lattice lattice = Lattice::create({LatticeKind::Bezier, {4, 4, 4}}, box).value();
    const auto springs = latticeSprings(lattice, uniformMaterial(lattice, 0.01, 80, 0.1));
    std::set<std::pair<int, int>> seen;
    const auto rest = lattice.restNodes();
    for (const Spring& s : springs) {
        const auto key = std::make_pair(std::min(int(s.a), int(s.b)), std::max(int(s.a), int(s.b)));
        QVERIFY2(seen.insert(key).second, "duplicate spring");
        QVERIFY(std::abs(s.restLength - (rest[s.a] - rest[s.b]).norm()) < 1e-12);
        QCOMPARE(s.stiffness, 80.0);
    }
}

void TestSprings::voidNodeRemovesExactlyItsSprings() {
    const Lattice lattice = makeLattice({4, 4, 4});
    LatticeMaterial material = uniformMaterial(lattice, 0.01, 80, 0.1);
    const auto all = latticeSprings(lattice, material);
    for (int node : {lattice.index(0, 0, 0), lattice.index(1, 2, 1), lattice.index(3, 1, 0)}) {
        LatticeMaterial m = material;
        m.isVoid[std::size_t(node)] = 1;
        auto body = buildLatticeBody(lattice, m);
        QVERIFY(body.ok());
        int touching = 0;
        for (const Spring& s : all)
            touching += (int(s.a) == node || int(s.b) == node);
        QCOMPARE(int(body.value()->springs.size()), int(all.size()) - touching);
        for (const Spring& s : body.value()->springs)
            QVERIFY(int(s.a) != node && int(s.b) != node);
        QCOMPARE(body.value()->simulated[std::size_t(node)], std::uint8_t(0));
        QCOMPARE(int(body.value()->voidFollowers.size()), 1);
    }
    // Interior node of a 4x4x4 grid: 6 edges + 12 face diagonals + 8 body diagonals = 26.
    int interior = 0;
    const int node = lattice.index(1, 1, 1);
    for (const Spring& s : all)
        interior += (int(s.a) == node || int(s.b) == node);
    QCOMPARE(interior, 26);
}

void TestSprings::anisotropySoftensOneAxis() {
    const Lattice lattice = makeLattice({3, 3, 3});
    LatticeMaterial m = uniformMaterial(lattice, 0.01, 100, 0.0);
    m.anisotropy = Vec3(1.0, 0.1, 1.0);  // the paper's transversely isotropic material
    for (const Spring& s : latticeSprings(lattice, m)) {
        const Vec3 d = (lattice.restNodes()[s.b] - lattice.restNodes()[s.a]).normalized();
        if (s.kind == SpringKind::Edge && std::abs(d.y()) > 0.99)
            QVERIFY(std::abs(s.stiffness - 10.0) < 1e-9);
        else if (s.kind == SpringKind::Edge)
            QVERIFY(std::abs(s.stiffness - 100.0) < 1e-9);
    }
}

void TestSprings::autoVoidFindsEmptyCells() {
    // A thin L-shape: a slab along u at v=0 and a slab along v at u=0; the far corner is empty.
    Mesh mesh;
    for (const Vec3f& p : test::scatter(2000, Vec3(0, 0, 0), Vec3(1, 0.1, 1), 3))
        mesh.positions.push_back(p);
    for (const Vec3f& p : test::scatter(2000, Vec3(0, 0, 0), Vec3(0.1, 1, 1), 4))
        mesh.positions.push_back(p);
    OrientedBox box;
    box.size = Vec3(1, 1, 1);
    const Lattice lattice = Lattice::create({LatticeKind::BSpline, {6, 6, 3}}, box).value();
    const auto empty = findEmptyNodes(lattice, mesh);
    QCOMPARE(empty[std::size_t(lattice.index(0, 0, 0))], std::uint8_t(0));
    QCOMPARE(empty[std::size_t(lattice.index(5, 0, 1))], std::uint8_t(0));
    QCOMPARE(empty[std::size_t(lattice.index(0, 5, 1))], std::uint8_t(0));
    QCOMPARE(empty[std::size_t(lattice.index(5, 5, 1))], std::uint8_t(1));
    QCOMPARE(empty[std::size_t(lattice.index(3, 3, 2))], std::uint8_t(1));
    // A void body built from it simulates and its void nodes follow.
    LatticeMaterial m = uniformMaterial(lattice, 0.01, 80, 0.1);
    m.isVoid = empty;
    auto body = buildLatticeBody(lattice, m);
    QVERIFY(body.ok());
    int voids = 0;
    for (auto v : empty)
        voids += v;
    QCOMPARE(int(body.value()->voidFollowers.size()), voids);
}

void TestSprings::badMaterialNamesTheNode() {
    const Lattice lattice = makeLattice({4, 4, 4});
    LatticeMaterial m = uniformMaterial(lattice, 0.01, 80, 0.1);
    m.mass[std::size_t(lattice.index(2, 1, 3))] = -1.0;
    auto body = buildLatticeBody(lattice, m);
    QVERIFY(!body.ok());
    QVERIFY2(body.message().find("node (2,1,3)") != std::string::npos, body.message().c_str());
    QVERIFY(body.message().find("mass") != std::string::npos);
    m = uniformMaterial(lattice, 0.01, 80, 0.1);
    m.stiffness[0] = std::nan("");
    QVERIFY(!buildLatticeBody(lattice, m).ok());
    m = uniformMaterial(lattice, 0.01, 80, 0.1);
    m.isVoid.assign(m.isVoid.size(), 1);
    QVERIFY(!buildLatticeBody(lattice, m).ok());
}

QTEST_GUILESS_MAIN(TestSprings)
#include "test_springs.moc"
