// Rest-shape edits (core/scene/rest_shape.h): the mesh takes the posed lattice's shape, the lattice returns to rest
// around it, and the body rests there; what cannot be applied is refused with the reason.

#include "core/scene/rest_shape.h"
#include "helpers/test_support.h"

#include <QTest>

#include <Eigen/Geometry>

#include <limits>
#include <numbers>

using namespace softtouch;
using namespace softtouch::test;

namespace {

double maxDistance(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        d = std::max(d, double((a[i] - b[i]).norm()));
    return d;
}

}  // namespace

class TestRestShape : public QObject {
    Q_OBJECT
private slots:
    // The rest pose is no edit: the Bezier map reproduces the mesh (to float rounding) and keeps the box.
    void restPoseLeavesTheMesh() {
        const SceneObject ball = anchoredBallScene().objects[0];
        auto change = withRestShape(ball, ball.lattice.restNodes());
        QVERIFY2(change.ok(), change.message().c_str());
        QVERIFY(maxDistance(change->object.mesh->positions, ball.mesh->positions) < 1e-6);
        QVERIFY(change->object.lattice.box().origin == ball.lattice.box().origin);
        QVERIFY(change->object.lattice.box().size == ball.lattice.box().size);
    }

    // A turned top layer: the new rest mesh is what the posed lattice showed, the new body rests in it (its
    // nodes at rest draw it), the material is kept node for node, and a pose that stays inside keeps the box.
    void posedShapeBecomesTheRest() {
        Scene scene = anchoredBallScene();
        const SceneObject& ball = scene.objects[0];
        std::vector<Vec3> pose = ball.lattice.restNodes();
        const Vec3 centre = ball.lattice.box().toWorld(Vec3::Constant(0.5));
        const Mat3 turn = Eigen::AngleAxisd(0.3, Vec3::UnitY()).toRotationMatrix();
        for (int n = 0; n < ball.lattice.nodeCount(); ++n)
            if (ball.lattice.coords(n)[1] == ball.lattice.count(1) - 1)  // the top layer, turned and pulled in
                pose[std::size_t(n)] = centre + 0.8 * (turn * (pose[std::size_t(n)] - centre));
        auto made = SceneSimulation::create(scene);
        QVERIFY(made.ok());
        SceneSimulation& shown = made.value();
        std::vector<Vec3f> posedMesh(ball.mesh->positions.size());
        SceneSimulation::Snapshot snapshot = shown.saveSnapshot();
        snapshot.bodies[0].position = pose;
        shown.restoreSnapshot(snapshot);
        shown.evaluate(0, posedMesh, {});

        auto change = withRestShape(ball, pose);
        QVERIFY2(change.ok(), change.message().c_str());
        QVERIFY(maxDistance(change->object.mesh->positions, posedMesh) < 1e-6);
        QVERIFY(change->object.lattice.box().size == ball.lattice.box().size);  // pulled in: the box holds it
        QVERIFY(change->object.material.stiffness == ball.material.stiffness);
        QVERIFY(change->object.material.anchor == ball.material.anchor);
        QCOMPARE(change->edit.nodes, pose);
        scene.objects[0] = change->object;
        auto rested = SceneSimulation::create(scene);
        QVERIFY2(rested.ok(), rested.message().c_str());
        std::vector<Vec3f> atRest(posedMesh.size());
        rested->evaluate(0, atRest, {});
        QVERIFY(maxDistance(atRest, posedMesh) < 1e-5);
        // The normals are the posed map's (unit, and turned with the top).
        for (const Vec3f& n : change->object.mesh->normals)
            QVERIFY(std::abs(n.norm() - 1.0f) < 1e-4f);
    }

    // A pose that pushes the mesh out of the box grows the box along its own axes to hold every vertex.
    void boxGrowsToHoldTheMesh() {
        const SceneObject ball = anchoredBallScene().objects[0];
        std::vector<Vec3> pose = ball.lattice.restNodes();
        for (Vec3& x : pose)
            x.x() *= 1.5;
        auto change = withRestShape(ball, pose);
        QVERIFY(change.ok());
        const OrientedBox& box = change->object.lattice.box();
        QVERIFY(box.size.x() > ball.lattice.box().size.x());
        QCOMPARE(box.size.y(), ball.lattice.box().size.y());
        for (const Vec3f& p : change->object.mesh->positions) {
            const Vec3 uvw = box.toParameters(p.cast<double>());
            QVERIFY((uvw.array() >= 0.0).all() && (uvw.array() <= 1.0).all());
        }
    }

    // Refused, naming the reason: another node count, a non-finite node, an object on its own animation.
    void refusesWhatCannotBeApplied() {
        SceneObject ball = anchoredBallScene().objects[0];
        std::vector<Vec3> pose = ball.lattice.restNodes();
        pose.pop_back();
        auto shortPose = withRestShape(ball, pose);
        QVERIFY(!shortPose.ok() && shortPose.message().find("63 nodes; its lattice has 64") != std::string::npos);
        pose = ball.lattice.restNodes();
        pose[5].y() = std::numeric_limits<double>::quiet_NaN();
        auto nan = withRestShape(ball, pose);
        QVERIFY(!nan.ok() && nan.message().find("node 5") != std::string::npos);
        ball.baseAnimation = std::make_shared<BaseAnimation>();
        auto animated = withRestShape(ball, ball.lattice.restNodes());
        QVERIFY(!animated.ok() && animated.message().find("its own animation") != std::string::npos);
    }
};

QTEST_APPLESS_MAIN(TestRestShape)
#include "test_rest_shape.moc"
