// Secondary motion on a base animation (core/animation/base_motion.h, core/animation/goal_fit.h): the goal fit is exact on
// affine motion, goal weight 1 reproduces the base animation, and the lag and overshoot of a body driven by
// its base match the driven damped oscillator of its lowest mode.

#include "helpers/physics_fixture.h"

#include "core/animation/base_motion.h"
#include "core/geometry/primitives.h"
#include "core/modes/mode_accuracy.h"
#include "core/modes/modes.h"
#include "core/scene/scene.h"

#include <QtTest>

#include <cmath>

using namespace softtouch;
using namespace softtouch::test;

namespace {

/// A fish-sized ellipsoid (0.6 × 0.2 × 0.1 m) in a fitted 4x4x4 Bezier lattice.
Scene ellipsoidScene() {
    Mesh mesh = makeUvEllipsoid(16, 32, Vec3(0.3, 0.1, 0.05));
    mesh.computeNormals();
    Scene scene = newScene("body", std::move(mesh)).value();
    scene.world.simulation.integrator = IntegratorKind::Verlet;
    return scene;
}

/// A base animation of `mesh` sampled at `rate` over `seconds` from `motion(p, t)`.
std::shared_ptr<BaseAnimation> sampled(const Mesh& mesh, double rate, double seconds, bool loop,
                                       const std::function<Vec3f(const Vec3f&, double)>& motion) {
    auto animation = std::make_shared<BaseAnimation>();
    animation->rate = rate;
    animation->loop = loop;
    const int count = int(std::lround(seconds * rate)) + (loop ? 0 : 1);
    for (int k = 0; k < count; ++k) {
        std::vector<Vec3f> p(mesh.positions.size());
        for (std::size_t v = 0; v < p.size(); ++v)
            p[v] = motion(mesh.positions[v], k / rate);
        animation->samples.push_back(std::move(p));
    }
    return animation;
}

/// φᵀ M ê: the load a frame accelerating along ê puts on a mode, over the free nodes' rows and every node's column
/// (the frame carries held nodes' mass too, which a solid element's consistent mass couples to the free ones).
double frameLoad(const BodyModel& model, const std::vector<Vec3>& shape, const Vec3& direction) {
    double load = 0.0;
    for (std::size_t i = 0; i < shape.size(); ++i) {
        if (model.inverseMass[i] == 0.0)
            continue;
        if (!model.element) {
            load += model.mass[i] * shape[i].dot(direction);
            continue;
        }
        for (std::size_t j = 0; j < shape.size(); ++j)
            load += model.element->mass(Eigen::Index(i), Eigen::Index(j)) * shape[i].dot(direction);
    }
    return load;
}

/// A bar anchored at one end (the anchors follow the animation) carried sideways by its base, x_b(t) = A sin(Ωt),
/// with goal weight 0 on the rest: in the base's frame it feels −M ẍ_b, so its lowest mode is driven like a damped
/// oscillator, q̈ + 2ζω q̇ + ω² q = Γ A Ω² sin(Ωt), Γ = φᵀMê / φᵀMφ. The free end's steady lag and overshoot match
/// Γ A Ω² / √((ω² − Ω²)² + (2ζωΩ)²) · |φ_tip| within 10%.
void checkDrivenLag(IntegratorKind integrator, BodyElement element) {
    Scene scene = ellipsoidScene();
    scene.world.simulation.integrator = IntegratorKind(integrator);
    SceneObject& o = scene.objects[0];
    for (int node = 0; node < o.lattice.nodeCount(); ++node)
        if (o.lattice.coords(node)[0] == 0)
            o.material.anchor[std::size_t(node)] = AnchorMode::Pinned;
    // Some node damping so the start-up transient is gone after a few seconds.
    o.material.nodeDamping.assign(o.material.mass.size(), 2.0);
    o.material.element = element;
    const auto model = buildLatticeBody(o.lattice, followingMaterial(o.material), &*o.mesh).value();
    const auto modes = analyseModes(*model, 1).value();
    const VibrationMode& first = modes.modes.front();
    const double omega = 2.0 * M_PI * first.frequencyHz;
    // Its main direction: the one its shape moves most along (the bar's thin side).
    Vec3 direction = Vec3::Zero();
    std::size_t tip = 0;
    for (std::size_t i = 0; i < first.shape.size(); ++i) {
        if (first.shape[i].norm() > first.shape[tip].norm())
            tip = i;
    }
    direction = first.shape[tip].normalized();
    const double participation = frameLoad(*model, first.shape, direction) / massInnerProduct(*model, first.shape, first.shape);
    const double drive = 0.7 * omega, amplitude = 0.02;
    const double predicted = participation * amplitude * drive * drive /
                             std::hypot(omega * omega - drive * drive, 2.0 * first.dampingRatio * omega * drive) *
                             first.shape[tip].norm();
    o.baseAnimation = sampled(o.mesh, 240.0, 8.0, false, [&](const Vec3f& p, double t) {
        return Vec3f((p.cast<double>() + amplitude * std::sin(drive * t) * direction).cast<float>());
    });
    auto sim = SceneSimulation::create(scene);
    QVERIFY2(sim.ok(), sim.message().c_str());
    double measured = 0.0;
    for (int step = 1; step <= 8 * 240; ++step) {
        sim->advanceTo(step / 240.0);
        if (step > 5 * 240)  // steady state: the transient has decayed by e^(−ζω·5 s)
            measured = std::max(measured, std::abs((sim->simulator(0).state().position[tip] - model->restPositions[tip]).dot(direction)));
    }
    qInfo("%s: lowest mode %.3f Hz, ζ %.3f, Γ %.3f; driven at %.3f Hz by ±%.3f m: tip lags ±%.4f m, "
          "the mode's oscillator gives ±%.4f m (%+.1f%%)",
          QTest::currentDataTag(), first.frequencyHz, first.dampingRatio, participation, drive / (2 * M_PI), amplitude,
          measured, predicted, 100.0 * (measured / predicted - 1.0));
    QVERIFY(first.dampingRatio > 0.05 && first.dampingRatio < 0.5);
    QVERIFY2(std::abs(measured / predicted - 1.0) <= 0.10, "lag within 10% of the lowest mode's oscillator");
}

}  // namespace

class TestBaseMotion : public QObject {
    Q_OBJECT

private slots:
    // The basis reproduces affine maps, so the fitted lattice of an affinely moved mesh is the rest lattice
    // moved the same way, and the rotation is the map's.
    void goalFitIsExactOnAffineMotion() {
        const Scene scene = ellipsoidScene();
        const SceneObject& o = scene.objects[0];
        const Binding binding = Binding::create(o.lattice, o.mesh->positions, o.mesh->normals);
        auto fit = GoalFit::create(o.lattice, o.mesh->positions, binding.parameters());
        QVERIFY2(fit.ok(), fit.message().c_str());
        const Mat3 turn = Eigen::AngleAxisd(0.7, Vec3(0.2, 1.0, 0.3).normalized()).toRotationMatrix();
        const Mat3 stretch = Vec3(1.2, 0.9, 1.0).asDiagonal();
        const Vec3 shift(0.3, -0.1, 2.0);
        std::vector<Vec3f> moved;
        for (const Vec3f& p : o.mesh->positions)
            moved.push_back((turn * stretch * p.cast<double>() + shift).cast<float>());
        std::vector<Vec3> nodes;
        Mat3 rotation;
        fit->fit(moved, nodes, rotation);
        double worst = 0.0;
        for (std::size_t i = 0; i < nodes.size(); ++i)
            worst = std::max(worst, (nodes[i] - (turn * stretch * o.lattice.restNodes()[i] + shift)).norm());
        qInfo("largest node error %.3g m (mesh positions are float), rotation error %.3g", worst, (rotation - turn).norm());
        // The moved mesh is float (2.4e-7 m at 2 m): nodes the mesh barely reaches carry that a hundredfold.
        QVERIFY(worst < 1e-4 * o.mesh->bounds().diagonal());
        QVERIFY((rotation - turn).norm() < 1e-6);
    }

    void weightOneReproducesTheBase_data() { addIntegratorRows(); }

    // Goal weight 1 everywhere: every node follows its goal exactly, so the output is the base animation
    // itself (a bending wave the lattice cannot represent, moved and turned), to float precision.
    void weightOneReproducesTheBase() {
        QFETCH(int, integrator);
        Scene scene = ellipsoidScene();
        scene.world.simulation.integrator = IntegratorKind(integrator);
        SceneObject& o = scene.objects[0];
        scene.objects[0].baseAnimation = sampled(o.mesh, 240.0, 1.0, true, [](const Vec3f& p, double t) {
            const double phase = 2.0 * M_PI * t;
            const Mat3 turn = Eigen::AngleAxisd(0.3 * std::sin(phase), Vec3::UnitY()).toRotationMatrix();
            const Vec3 wave(0.0, 0.0, 0.04 * std::sin(phase + 12.0 * p.x()));  // finer than the lattice
            return Vec3f((turn * (p.cast<double>() + wave) + Vec3(0.2 * std::sin(phase), 0, 0)).cast<float>());
        });
        o.material.goalWeight.assign(o.material.mass.size(), 1.0);
        auto sim = SceneSimulation::create(scene);
        QVERIFY2(sim.ok(), sim.message().c_str());
        const double diagonal = o.mesh->bounds().diagonal();
        std::vector<Vec3f> out(o.mesh->positions.size()), base(out.size());
        double worst = 0.0;
        for (int frame = 1; frame <= 24; ++frame) {
            sim->advanceTo(frame / 24.0);
            sim->evaluate(0, out, {});
            scene.objects[0].baseAnimation->positionsAt(frame / 24.0, base);
            for (std::size_t v = 0; v < out.size(); ++v)
                worst = std::max(worst, double((out[v] - base[v]).norm()));
        }
        qInfo("%s: largest distance from the base %.3g of the diagonal", QTest::currentDataTag(), worst / diagonal);
        QCOMPARE(worst, 0.0);
    }

    // A carried bar lags as its lowest mode's oscillator says (checkDrivenLag), on springs with every scheme.
    void drivenLagMatchesTheLowestMode_data() { addIntegratorRows(); }
    void drivenLagMatchesTheLowestMode() {
        QFETCH(int, integrator);
        checkDrivenLag(IntegratorKind(integrator), BodyElement::Springs);
    }

    // The same on the solid element, whose frame inertia is its consistent mass's (F = M Rᵀ(g − G̈)).
    void drivenLagOnTheSolidElement_data() {
        QTest::addColumn<int>("integrator");
        for (IntegratorKind k : {IntegratorKind::Verlet, IntegratorKind::ImplicitEuler})
            QTest::newRow(std::string(integratorName(k)).c_str()) << int(k);
    }
    void drivenLagOnTheSolidElement() {
        QFETCH(int, integrator);
        checkDrivenLag(IntegratorKind(integrator), BodyElement::Solid);
    }

    // The modes shown for a body on a base animation include its goal springs: started on its lowest mode
    // (on a still base), the baked free vibration has the shown frequency within 3% and damping ratio within
    // 10%, with every integrator at a fine step; without the goal springs the shown frequency would be off.
    void shownModesIncludeTheGoalSprings_data() { addIntegratorRows(); }
    void shownModesIncludeTheGoalSprings() {
        QFETCH(int, integrator);
        Scene scene = ellipsoidScene();
        scene.world.simulation.integrator = IntegratorKind(integrator);
        scene.world.simulation.dt = 1.0 / 2000.0;
        SceneObject& o = scene.objects[0];
        for (int node = 0; node < o.lattice.nodeCount(); ++node)
            if (o.lattice.coords(node)[0] == 0)
                o.material.anchor[std::size_t(node)] = AnchorMode::Pinned;
        o.material.goalWeight.assign(o.material.mass.size(), 0.5);
        o.follow = FollowSettings{1.5, 0.05};
        o.baseAnimation = sampled(o.mesh, 240.0, 10.0, false, [](const Vec3f& p, double) { return p; });
        const auto shown = objectModes(o, 1);
        QVERIFY2(shown.ok(), shown.message().c_str());
        const VibrationMode& mode = shown->modes.front();
        const auto springsAlone = analyseModes(*buildLatticeBody(o.lattice, simulatedMaterial(o)).value(), 1).value();
        auto sim = SceneSimulation::create(scene);
        QVERIFY2(sim.ok(), sim.message().c_str());
        const BodyModel& model = sim->simulator(0).model();
        SceneSimulation::Snapshot start = sim->saveSnapshot();
        for (std::size_t i = 0; i < model.nodeCount(); ++i)
            start.bodies[0].position[i] += 0.01 * mode.shape[i];
        sim->restoreSnapshot(start);
        std::vector<double> q;
        const double dt = scene.world.simulation.dt;
        for (int step = 1; step <= 4000; ++step) {
            sim->advanceTo(step * dt);
            double projected = 0.0;
            for (std::size_t i = 0; i < model.nodeCount(); ++i)
                projected += model.mass[i] * mode.shape[i].dot(sim->simulator(0).state().position[i] - model.restPositions[i]);
            q.push_back(projected);
        }
        const FittedOscillation fitted = fitOscillation(q, dt);
        qInfo("%s: shown %.3f Hz ζ %.3f (the springs alone: %.3f Hz); baked %.3f Hz ζ %.3f", QTest::currentDataTag(),
              mode.frequencyHz, mode.dampingRatio, springsAlone.modes.front().frequencyHz, fitted.frequencyHz, fitted.dampingRatio);
        QVERIFY(fitted.oscillates);
        QVERIFY(std::abs(fitted.frequencyHz / mode.frequencyHz - 1.0) <= 0.03);
        QVERIFY(std::abs(fitted.dampingRatio / mode.dampingRatio - 1.0) <= 0.10);
        QVERIFY(std::abs(springsAlone.modes.front().frequencyHz / mode.frequencyHz - 1.0) > 0.05);
    }

    // A hand pulls an object on a base animation where it is seen: with the base 2 m away from the rest
    // pose, a drag 5 cm above a surface point lifts that point by about that much, where a target taken in
    // the body's own frame would have pulled it 2 m.
    void handPullsWhereTheBodyIsShown() {
        Scene scene = ellipsoidScene();
        SceneObject& o = scene.objects[0];
        o.baseAnimation = sampled(o.mesh, 240.0, 2.0, false, [](const Vec3f& p, double) { return Vec3f(p + Vec3f(2, 0, 0)); });
        o.material.goalWeight.assign(o.material.mass.size(), 0.3);
        o.material.nodeDamping.assign(o.material.mass.size(), 3.0);
        auto sim = SceneSimulation::create(scene);
        QVERIFY2(sim.ok(), sim.message().c_str());
        std::vector<Vec3f> shown(o.mesh->positions.size());
        sim->evaluate(0, shown, {});
        const std::size_t vertex = 0;
        const Vec3 target = shown[vertex].cast<double>() + Vec3(0, 0.05, 0);
        const Binding binding = Binding::create(o.lattice, o.mesh->positions, o.mesh->normals);
        DragSpring hand;
        const Vec3 u = binding.parameters()[vertex];
        const BasisSample a = o.lattice.axis(0).sample(u.x()), b = o.lattice.axis(1).sample(u.y()), c = o.lattice.axis(2).sample(u.z());
        for (int k = 0; k < c.order; ++k)
            for (int j = 0; j < b.order; ++j)
                for (int i = 0; i < a.order; ++i)
                    hand.support.push_back({std::uint32_t(o.lattice.index(a.first + i, b.first + j, c.first + k)),
                                            a.value[std::size_t(i)] * b.value[std::size_t(j)] * c.value[std::size_t(k)]});
        hand.target = target;
        hand.stiffness = 20.0;
        hand.damping = 0.5;
        sim->setInteractiveDrags(0, {hand});
        sim->advanceTo(1.5);
        sim->evaluate(0, shown, {});
        const Vec3 point = shown[vertex].cast<double>();
        qInfo("held 5 cm above it, the point ends %.4f m from the target (%.4f m up, %.4f m along x)",
              (point - target).norm(), point.y() - (target.y() - 0.05), point.x() - target.x());
        QVERIFY((point - target).norm() < 0.05);
        QVERIFY(point.y() - (target.y() - 0.05) > 0.01);
    }

    // Goal weights pull each node back to its goal with a spring that means the same on every lattice
    // (mass-proportional): a node of weight ½ alone swings at the set frequency.
    void goalSpringsAreMassProportional() {
        Scene scene = ellipsoidScene();
        SceneObject& o = scene.objects[0];
        o.baseAnimation = sampled(o.mesh, 240.0, 1.0, true, [](const Vec3f& p, double) { return p; });
        o.material.goalWeight.assign(o.material.mass.size(), 0.5);
        o.material.goalWeight[0] = 0.0;
        o.follow.frequency = 3.0;
        auto sim = SceneSimulation::create(scene);
        QVERIFY2(sim.ok(), sim.message().c_str());
        const ExternalForces f = sim->forcesAt(0, 0.0);
        QCOMPARE(f.drags.size(), o.material.mass.size() - 1);
        const BodyModel& model = sim->simulator(0).model();
        for (const DragSpring& d : f.drags) {
            const std::uint32_t node = d.support.front().node;
            QVERIFY(std::abs(d.stiffness / model.mass[node] - std::pow(2.0 * M_PI * 3.0, 2)) < 1e-9 * d.stiffness);
            QVERIFY((d.target - model.restPositions[node]).norm() == 0.0);
        }
        // A still base: no inertia at all, so a still body stays at rest.
        for (const Vec3& force : f.nodeForces)
            QVERIFY(force.norm() < 1e-9);
        sim->advanceTo(1.0);
        double moved = 0.0;
        for (std::size_t i = 0; i < model.nodeCount(); ++i)
            moved = std::max(moved, (sim->simulator(0).state().position[i] - model.restPositions[i]).norm());
        QVERIFY2(moved < 1e-9, qPrintable(QString("moved %1 m").arg(moved)));
    }
};

QTEST_GUILESS_MAIN(TestBaseMotion)
#include "test_base_motion.moc"
