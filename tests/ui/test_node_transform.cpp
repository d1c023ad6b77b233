// The pose tool's transform arithmetic (ui/node_transform.h), without a window: what the mouse and typed
// amounts do to the selected nodes, and that the others never move.

#include "ui/node_transform.h"

#include <QTest>

#include <Eigen/Geometry>

#include <numbers>

using namespace softtouch;
using namespace softtouch::ui;

namespace {

/// A 3x3x1 grid of nodes 0.1 m apart, some of them off the z = 0 plane.
std::vector<Vec3> grid() {
    std::vector<Vec3> nodes;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            nodes.emplace_back(0.1 * i, 0.1 * j, 0.01 * (i + j));
    return nodes;
}

double maxDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double d = 0.0;
    for (std::size_t n = 0; n < a.size(); ++n)
        d = std::max(d, (a[n] - b[n]).norm());
    return d;
}

}  // namespace

class TestNodeTransform : public QObject {
    Q_OBJECT
private slots:
    // The pivot is the selected nodes' mean; nodes outside the lattice are ignored; unselected nodes stay.
    void pivotAndUnselectedNodes() {
        const std::vector<Vec3> start = grid();
        NodeTransform t(TransformKind::Move, start, {1, 2, 99, -1});
        QCOMPARE(t.nodes(), (std::vector<int>{1, 2}));
        QVERIFY((t.pivot() - 0.5 * (start[1] + start[2])).norm() < 1e-15);
        t.setMouseMove(Vec3(0.3, -0.2, 0.1));
        const std::vector<Vec3> moved = t.positions();
        for (std::size_t n = 0; n < start.size(); ++n) {
            const bool selected = n == 1 || n == 2;
            QVERIFY((moved[n] - start[n] - (selected ? Vec3(0.3, -0.2, 0.1) : Vec3::Zero())).norm() < 1e-15);
        }
    }

    // A held axis keeps the mouse's component along it; pressing the same axis again frees the move.
    void axisHoldsTheMouseMove() {
        NodeTransform t(TransformKind::Move, grid(), {4});
        t.setMouseMove(Vec3(0.3, -0.2, 0.1));
        t.toggleAxis(TransformAxis::Y);
        QCOMPARE(t.axis(), TransformAxis::Y);
        QVERIFY((t.positions()[4] - grid()[4] - Vec3(0, -0.2, 0)).norm() < 1e-15);
        t.toggleAxis(TransformAxis::Y);
        QCOMPARE(t.axis(), TransformAxis::Free);
        QVERIFY((t.positions()[4] - grid()[4] - Vec3(0.3, -0.2, 0.1)).norm() < 1e-15);
    }

    // Typing replaces the mouse: digits, one point, '-' flips the sign, Backspace takes back; a typed move
    // with no axis goes along X.
    void typedAmountsReplaceTheMouse() {
        NodeTransform t(TransformKind::Move, grid(), {0});
        t.setMouseMove(Vec3(1, 1, 1));
        QVERIFY(!t.typedValue());
        for (char c : std::string("0.25"))
            QVERIFY(t.type(c));
        QVERIFY(!t.type('x'));
        QVERIFY(!t.type('.'));  // a second point is refused
        QCOMPARE(t.typedText(), std::string("0.25"));
        QVERIFY((t.positions()[0] - grid()[0] - Vec3(0.25, 0, 0)).norm() < 1e-15);
        QVERIFY(t.type('-'));
        t.toggleAxis(TransformAxis::Z);
        QCOMPARE(*t.typedValue(), -0.25);
        QVERIFY((t.positions()[0] - grid()[0] - Vec3(0, 0, -0.25)).norm() < 1e-15);
        t.backspace();
        t.backspace();
        t.backspace();
        t.backspace();  // "0.2", "0.", "0", "": only the sign is left, and it needs a number
        QVERIFY(!t.typedValue());
        QVERIFY((t.positions()[0] - grid()[0] - Vec3(0, 0, 1)).norm() < 1e-15);  // the mouse's again, along Z
        QVERIFY(t.describe().find("Move Z") == 0);
    }

    // A typed rotation turns about the held axis through the pivot by that many degrees; the mouse's turn
    // (counter-clockwise as the viewer sees it) is about the view axis, and about a held axis that points
    // away from the viewer it is the opposite turn, so the nodes still follow the cursor on screen.
    void rotationFollowsTheCursor() {
        const std::vector<Vec3> start = grid();
        NodeTransform typed(TransformKind::Rotate, start, {0, 1, 3, 4});
        typed.toggleAxis(TransformAxis::Z);
        for (char c : std::string("90"))
            typed.type(c);
        const Vec3 pivot = typed.pivot();
        const Mat3 quarter = Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()).toRotationMatrix();
        std::vector<Vec3> expected = start;
        for (int n : {0, 1, 3, 4})
            expected[std::size_t(n)] = pivot + quarter * (start[std::size_t(n)] - pivot);
        QVERIFY(maxDistance(typed.positions(), expected) < 1e-15);

        // Viewer on +Z looking down: a counter-clockwise sweep of 90° turns +90° about +Z, whether the axis
        // is free (the view axis) or held to Z; seen from -Z, holding Z turns the other way about +Z.
        for (const double viewerZ : {1.0, -1.0}) {
            NodeTransform mouse(TransformKind::Rotate, start, {0, 1, 3, 4});
            mouse.setMouseRotate(std::numbers::pi / 2, Vec3(0, 0, viewerZ));
            mouse.toggleAxis(TransformAxis::Z);
            const Mat3 turn = Eigen::AngleAxisd(viewerZ * std::numbers::pi / 2, Vec3::UnitZ()).toRotationMatrix();
            std::vector<Vec3> seen = start;
            for (int n : {0, 1, 3, 4})
                seen[std::size_t(n)] = pivot + turn * (start[std::size_t(n)] - pivot);
            QVERIFY2(maxDistance(mouse.positions(), seen) < 1e-12, qPrintable(QString("viewer at z = %1").arg(viewerZ)));
            mouse.toggleAxis(TransformAxis::Z);  // free: about the view axis, the same turn
            QVERIFY(maxDistance(mouse.positions(), seen) < 1e-12);
        }
    }

    // Scale: about the pivot in every direction, or along a held axis only.
    void scaleAboutThePivot() {
        const std::vector<Vec3> start = grid();
        NodeTransform t(TransformKind::Scale, start, {0, 2, 6, 8});
        t.setMouseScale(2.0);
        for (int n : {0, 2, 6, 8})
            QVERIFY((t.positions()[std::size_t(n)] - t.pivot() - 2.0 * (start[std::size_t(n)] - t.pivot())).norm() < 1e-15);
        t.toggleAxis(TransformAxis::X);
        for (int n : {0, 2, 6, 8}) {
            const Vec3 offset = start[std::size_t(n)] - t.pivot();
            QVERIFY((t.positions()[std::size_t(n)] - t.pivot() - Vec3(2.0 * offset.x(), offset.y(), offset.z())).norm() < 1e-15);
        }
        t.type('0');  // a typed factor of 0 flattens them onto the plane through the pivot
        for (int n : {0, 2, 6, 8})
            QVERIFY(std::abs(t.positions()[std::size_t(n)].x() - t.pivot().x()) < 1e-15);
    }
};

QTEST_APPLESS_MAIN(TestNodeTransform)
#include "test_node_transform.moc"
