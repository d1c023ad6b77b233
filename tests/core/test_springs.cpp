// Lattice spring topology (counts, voids, automatic void detection) and the spring force pass.
#include "core/body/forces.h"
#include "core/body/lattice_body.h"
#include "helpers/test_support.h"

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

/// The spring force on every node, spring by spring: k(|r| − L) r̂ + c (r̂·Δv) r̂ on a, the opposite on b.
std::vector<Vec3> referenceSpringForces(const BodyModel& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v) {
    std::vector<Vec3> f(model.nodeCount(), Vec3::Zero());
    for (const Spring& s : model.springs) {
        const Vec3 r = x[s.b] - x[s.a];
        const double length = r.norm();
        if (length == 0.0)
            continue;
        const Vec3 dir = r / length;
        const Vec3 force = (s.stiffness * (length - s.restLength) + s.damping * dir.dot(v[s.b] - v[s.a])) * dir;
        f[s.a] += force;
        f[s.b] -= force;
    }
    return f;
}

/// A 4x4x4 body with mixed per-node stiffness and damping, its u = 0 face pinned and one void node.
std::shared_ptr<const BodyModel> mixedBody() {
    const Lattice lattice = makeLattice({4, 4, 4});
    LatticeMaterial m = uniformMaterial(lattice, 0.01, 80, 0.3);
    for (std::size_t i = 0; i < m.stiffness.size(); ++i) {
        m.stiffness[i] = 10.0 + 37.0 * double(i % 7);
        m.damping[i] = 0.05 * double(i % 5);
    }
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            m.anchor[std::size_t(lattice.index(0, j, k))] = AnchorMode::Pinned;
    m.isVoid[std::size_t(lattice.index(2, 3, 3))] = 1;
    return buildLatticeBody(lattice, m).value();
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
    void springForcesMatchThePerSpringFormula();
    void springForcesSkipPinnedPairsAndZeroLengths();
    void springForcesPropagateNonFinitePositions();
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

void TestSprings::springForcesMatchThePerSpringFormula() {
    const auto model = mixedBody();
    const std::size_t n = model->nodeCount();
    std::vector<Vec3> x = model->restPositions, v(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double t = double(i);
        x[i] += 0.04 * Vec3(std::sin(1.3 * t), std::cos(2.1 * t), std::sin(0.7 * t + 1.0));
        v[i] = Vec3(std::cos(0.9 * t), 0.5 - std::sin(1.7 * t), 0.2 * t / double(n));
    }
    const std::vector<Vec3> expected = referenceSpringForces(*model, x, v);
    std::vector<Vec3> f(n);
    SpringScratch scratch;
    ForceTerms terms;
    terms.nodeDamping = false;
    for (int pass = 0; pass < 2; ++pass) {  // the second pass reuses the scratch
        accumulateForces(*model, ExternalForces{}, x, v, f, scratch, terms);
        double largest = 0.0;
        for (const Vec3& e : expected)
            largest = std::max(largest, e.norm());
        QVERIFY(largest > 1.0);  // the deformation really loads the springs
        for (std::size_t i = 0; i < n; ++i) {
            if (model->inverseMass[i] == 0.0) {
                QCOMPARE(f[i], Vec3(Vec3::Zero()));  // pinned and void nodes get no spring force
                continue;
            }
            QVERIFY2((f[i] - expected[i]).norm() <= 1e-12 * largest,
                     qPrintable(QString("node %1: %2 off").arg(i).arg((f[i] - expected[i]).norm())));
        }
    }
}

void TestSprings::springForcesSkipPinnedPairsAndZeroLengths() {
    const auto model = mixedBody();
    const SpringTable& table = model->springTable;
    int pinnedPairs = 0;
    for (const Spring& s : model->springs)
        pinnedPairs += model->pinned[s.a] && model->pinned[s.b];
    QVERIFY(pinnedPairs > 0);
    QCOMPARE(int(table.size()), int(model->springs.size()) - pinnedPairs);
    // Every free node lists each of its springs once, at the end it sits on.
    std::size_t listed = 0;
    for (std::size_t i = 0; i < model->nodeCount(); ++i) {
        listed += table.startOffset[i + 1] - table.startOffset[i] + table.endOffset[i + 1] - table.endOffset[i];
        for (std::uint32_t e = table.startOffset[i]; e < table.startOffset[i + 1]; ++e)
            QCOMPARE(table.a[table.startSpring[e]], std::uint32_t(i));
        for (std::uint32_t e = table.endOffset[i]; e < table.endOffset[i + 1]; ++e)
            QCOMPARE(table.b[table.endSpring[e]], std::uint32_t(i));
    }
    std::size_t freeEnds = 0;
    for (std::size_t k = 0; k < table.size(); ++k)
        freeEnds += (model->inverseMass[table.a[k]] > 0.0) + (model->inverseMass[table.b[k]] > 0.0);
    QCOMPARE(listed, freeEnds);

    // Two coincident nodes: the spring between them has no direction and adds nothing, and every
    // other force stays finite.
    std::vector<Vec3> x = model->restPositions, v(model->nodeCount(), Vec3::Zero());
    const Spring& s = model->springs[std::size_t(model->springs.size() / 2)];
    x[s.b] = x[s.a];
    std::vector<Vec3> f(model->nodeCount());
    SpringScratch scratch;
    accumulateForces(*model, ExternalForces{}, x, v, f, scratch);
    const std::vector<Vec3> expected = referenceSpringForces(*model, x, v);
    for (std::size_t i = 0; i < model->nodeCount(); ++i) {
        QVERIFY(isFinite(f[i]));
        if (model->inverseMass[i] > 0.0)
            QVERIFY((f[i] - expected[i]).norm() <= 1e-12 * (1.0 + expected[i].norm()));
    }
}

void TestSprings::springForcesPropagateNonFinitePositions() {
    // A NaN node must poison its neighbours' forces (so the simulator sees it and rolls back), not
    // be masked by the zero-length guard.
    const auto model = mixedBody();
    std::vector<Vec3> x = model->restPositions, v(model->nodeCount(), Vec3::Zero());
    const std::size_t bad = std::size_t(makeLattice({4, 4, 4}).index(2, 1, 1));
    x[bad].y() = std::nan("");
    std::vector<Vec3> f(model->nodeCount());
    SpringScratch scratch;
    accumulateForces(*model, ExternalForces{}, x, v, f, scratch);
    QVERIFY(!isFinite(f[bad]));
    int poisoned = 0;
    for (const Spring& s : model->springs) {
        const std::uint32_t other = s.a == bad ? s.b : s.b == bad ? s.a : std::uint32_t(-1);
        if (other != std::uint32_t(-1) && model->inverseMass[other] > 0.0) {
            QVERIFY(!isFinite(f[other]));
            ++poisoned;
        }
    }
    QCOMPARE(poisoned, 26);  // an interior node has 26 springs
}
