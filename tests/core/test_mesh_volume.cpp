// Mass from the mesh: each lattice node's share of a closed mesh's volume (∫_mesh N_i dV), sampled on a
// grid, against the mesh's exact volume (divergence theorem), the shape's symmetry and a mesh with a
// hole; and the node masses made from it.
#include "core/body/volume_preservation.h"
#include "core/geometry/mesh_volume.h"
#include "core/geometry/oriented_box.h"
#include "core/geometry/primitives.h"

#include <QtTest>

using namespace softtouch;

namespace {

/// A closed triangle mesh's volume, exactly: Σ a·(b×c)/6 over its outward triangles.
double exactVolume(const Mesh& mesh) { return enclosedVolume(mesh.positions, mesh.triangles); }

/// An egg 0.6 x 0.3 x 0.2 m (off centre in its own box, so the box is fitted with padding) and its lattice.
struct Egg {
    Mesh mesh = makeUvEllipsoid(24, 48, Vec3(0.3, 0.15, 0.1), Vec3(0.2, -0.1, 0.05));
    Lattice lattice;
    explicit Egg(LatticeShape shape) {
        BoxFitSettings fit;
        fit.padding = 0.1;
        lattice = Lattice::create(shape, fitBox(mesh.positions, fit).value()).value();
    }
};

}  // namespace

class TestMeshVolume : public QObject {
    Q_OBJECT
private slots:
    void sharesAddUpToTheMeshVolume() {
        for (LatticeShape shape : {LatticeShape{LatticeKind::Bezier, {4, 4, 4}}, LatticeShape{LatticeKind::BSpline, {7, 5, 4}}}) {
            const Egg egg(shape);
            const auto shares = meshVolumeShares(egg.lattice, egg.mesh);
            QVERIFY2(shares.ok(), shares.message().c_str());
            double sum = 0.0;
            for (double v : shares->nodeVolume) {
                QVERIFY(v >= 0.0);
                sum += v;
            }
            const double exact = exactVolume(egg.mesh);
            qInfo("%dx%dx%d: sampled %.6f m³, exact %.6f m³, nodes %.6f m³", shape.nodes[0], shape.nodes[1], shape.nodes[2],
                  shares->volume, exact, sum);
            QCOMPARE(shares->openLines, 0);
            QVERIFY(std::abs(shares->volume / exact - 1.0) < 0.01);  // a 48³ grid over a padded box
            QVERIFY(std::abs(sum / shares->volume - 1.0) < 1e-9);    // the basis is a partition of unity
        }
    }

    // The egg is symmetric about its centre: nodes mirrored through the box centre carry the same share,
    // and the nodes at the box's corners, outside the egg, carry less than those around its middle.
    void sharesFollowTheShape() {
        const Egg egg({LatticeKind::Bezier, {4, 4, 4}});
        const auto shares = meshVolumeShares(egg.lattice, egg.mesh, 64).value();
        const int n = egg.lattice.nodeCount();
        double largestAsymmetry = 0.0, largest = 0.0;
        for (int node = 0; node < n; ++node) {
            largest = std::max(largest, shares.nodeVolume[std::size_t(node)]);
            largestAsymmetry = std::max(largestAsymmetry, std::abs(shares.nodeVolume[std::size_t(node)] -
                                                                   shares.nodeVolume[std::size_t(n - 1 - node)]));
        }
        QVERIFY2(largestAsymmetry < 0.02 * largest, qPrintable(QString::number(largestAsymmetry / largest)));
        const double corner = shares.nodeVolume[std::size_t(egg.lattice.index(0, 0, 0))];
        const double middle = shares.nodeVolume[std::size_t(egg.lattice.index(1, 1, 1))];
        qInfo("corner %.3g m³, middle %.3g m³", corner, middle);
        QVERIFY(middle > 5.0 * corner);
    }

    void aMeshWithAHoleHasNoVolumeToShare() {
        Egg egg({LatticeKind::Bezier, {4, 4, 4}});
        egg.mesh.triangles.resize(egg.mesh.triangles.size() / 2);  // the lower half only
        const auto shares = meshVolumeShares(egg.lattice, egg.mesh);
        QVERIFY(!shares);
        QVERIFY2(shares.message().find("not a closed surface") != std::string::npos, shares.message().c_str());
    }

    // Masses follow the shares, none falls below the floor, and they add up to the total.
    void massesFollowTheSharesAndAddUp() {
        const Egg egg({LatticeKind::Bezier, {4, 4, 4}});
        const auto shares = meshVolumeShares(egg.lattice, egg.mesh).value();
        std::vector<std::uint8_t> isVoid(std::size_t(egg.lattice.nodeCount()), 0);
        isVoid[0] = 1;
        const std::vector<double> kg = meshMassPerNode(shares, isVoid, 2.5);
        double total = 0.0, lightest = 1e9;
        for (std::size_t i = 0; i < kg.size(); ++i) {
            if (isVoid[i]) {
                QCOMPARE(kg[i], 0.0);
                continue;
            }
            total += kg[i];
            lightest = std::min(lightest, kg[i]);
        }
        const double mean = 2.5 / (kg.size() - 1);
        QVERIFY(std::abs(total - 2.5) < 1e-12);
        QVERIFY(lightest >= 0.95 * kMeshMassFloor * mean);
        const auto heavy = std::size_t(egg.lattice.index(1, 1, 1)), light = std::size_t(egg.lattice.index(3, 3, 3));
        QVERIFY(kg[heavy] > 3.0 * kg[light]);
    }
};

QTEST_APPLESS_MAIN(TestMeshVolume)
#include "test_mesh_volume.moc"
