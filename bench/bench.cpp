#include "bench/bench.h"

#include "analysis/timer.h"
#include "bench/bullet_peer.h"
#include "bench/reference_deform.h"
#include "bench/table1_report.h"
#include "core/base/node_change.h"
#include "core/base/parallel.h"
#include "core/body/lattice_body.h"
#include "core/geometry/binding.h"
#include "core/geometry/mesh_surface.h"
#include "core/geometry/primitives.h"
#include "core/modes/material_conversion.h"
#include "core/scene/scene.h"
#include "core/solver/simulator.h"

#include <cstdio>
#include <iomanip>
#include <map>
#include <thread>

namespace softtouch::bench {
namespace {

using nlohmann::json;

/// The cartoon controls a bench body may use (all off by default).
struct CartoonControls {
    StrainLimits limits;
    double volumePreservation = 0.0;  ///< Of the whole box (the bench body has no mesh).
    /// The solid element instead of springs, on the continuum material with the springs' lowest mode and mass
    /// (continuumEquivalent()).
    bool solidElement = false;
    /// No damping at all (the material's viscosity included): what the step bound is without it.
    bool undamped = false;
};

/// A lattice body with the fish material, pinned at its u = 0 face.
std::shared_ptr<const BodyModel> benchBody(const Lattice& lattice, const CartoonControls& controls = {}) {
    LatticeMaterial m = uniformMaterial(lattice, 0.02, 80.0, controls.undamped ? 0.0 : 0.9);
    m.strainLimits = controls.limits;
    setVolumePreservation(m, controls.volumePreservation);
    for (int k = 0; k < lattice.count(2); ++k)
        for (int j = 0; j < lattice.count(1); ++j)
            m.anchor[std::size_t(lattice.index(0, j, k))] = AnchorMode::Pinned;
    if (controls.solidElement) {
        m = continuumEquivalent(lattice, m).value().material;
        m.element = BodyElement::Solid;
    }
    return buildLatticeBody(lattice, m).value();
}

/// A benchBody() lattice pulled at its free end by one drag whose target moves on every step (which
/// keeps it awake), or, when `sleeping`, left alone until it sleeps. The scene of the step and frame
/// benchmarks.
struct DraggedBody {
    DraggedBody(const LatticeShape& shape, IntegratorKind integrator, const ExternalForces& base, bool leftToSleep,
                bool energyGuard = true, const CartoonControls& controls = {})
        : lattice(Lattice::create(shape, OrientedBox{}).value()),
          sim(benchBody(lattice, controls), settingsFor(integrator, leftToSleep, energyGuard)), forces(base), sleeping(leftToSleep) {
        drag.support = lattice.weights(Vec3(1.0, 0.5, 0.5));
        drag.stiffness = 50.0;
        drag.damping = 0.5;
        if (sleeping) {
            for (int i = 0; i < 2000 && !sim.isSleeping(); ++i)
                (void)sim.step(forces);
        }
    }
    static SimulationSettings settingsFor(IntegratorKind integrator, bool leftToSleep, bool energyGuard) {
        SimulationSettings settings;
        settings.integrator = integrator;
        settings.dt = 1.0 / 240.0;
        settings.sleep = leftToSleep;
        if (!energyGuard)
            settings.energyCheckSteps = 0;
        return settings;
    }
    /// One simulator step, the drag target moved first unless the body is left to sleep.
    void step() {
        if (!sleeping) {
            drag.target = Vec3(1.0, 0.5 + 0.2 * std::sin(0.05 * double(steps)), 0.5);
            forces.drags.assign(1, drag);
        }
        (void)sim.step(forces);
        ++steps;
    }

    Lattice lattice;
    Simulator sim;
    ExternalForces forces;
    DragSpring drag;
    bool sleeping = false;  ///< Left to sleep: the drag is never applied.
    long long steps = 0;
};

/// Microseconds per step of a DraggedBody.
double stepMicroseconds(const LatticeShape& shape, IntegratorKind integrator, const ExternalForces& base, bool sleeping,
                        double minSeconds, bool energyGuard = true, const CartoonControls& controls = {}) {
    DraggedBody body(shape, integrator, base, sleeping, energyGuard, controls);
    const int batch = 200;
    auto run = [&] {
        for (int i = 0; i < batch; ++i)
            body.step();
    };
    return 1e6 * analysis::bestSecondsPerUnit(run, batch, minSeconds);
}

json latticeSteps(const LatticeShape& shape, const char* label, double minSeconds, std::ostream& out) {
    json result = json::object();
    out << "\nLattice step, " << label << " (dt 1/240 s, one drag, anchored face), us per step\n";
    double baseline = 0.0;
    std::map<IntegratorKind, double> springs;
    for (IntegratorKind k : integratorKinds()) {
        const double us = stepMicroseconds(shape, k, {}, false, minSeconds);
        springs[k] = us;
        if (k == IntegratorKind::SymplecticEuler)
            baseline = us;
        result[std::string(integratorName(k))] = us;
        out << "  " << std::left << std::setw(18) << integratorName(k) << std::right << std::fixed << std::setprecision(2)
            << std::setw(9) << us << " us   " << std::setprecision(1) << us / baseline << "x symplectic-euler\n";
    }
    // The solid element on the same body (the continuum material of the springs' lowest mode and mass): its
    // consistent mass raises the highest frequency, where the material's viscosity (damping that grows with
    // frequency) then bounds the explicit step, so the substeps are counted too, and what they would be undamped.
    CartoonControls solid, undamped;
    solid.solidElement = undamped.solidElement = true;
    undamped.undamped = true;
    for (IntegratorKind k : integratorKinds()) {
        if (!integratorInfo(k).runsElement)
            continue;
        const double us = stepMicroseconds(shape, k, {}, false, minSeconds, true, solid);
        const DraggedBody body(shape, k, {}, false, true, solid);
        const DraggedBody withoutViscosity(shape, k, {}, false, true, undamped);
        const std::string name = std::string(integratorName(k)) + " (solid element)";
        result[name] = us;
        out << "  " << std::left << std::setw(33) << name << std::right << std::fixed << std::setprecision(2) << std::setw(9)
            << us << " us   " << std::setprecision(1) << us / baseline << "x symplectic-euler, " << us / springs[k]
            << "x its springs, " << body.sim.substepsFor(body.forces) << " substeps a step ("
            << withoutViscosity.sim.substepsFor(withoutViscosity.forces) << " undamped)\n";
    }
    return result;
}

json deformation(const BenchOptions& options, std::ostream& out) {
    json rows = json::array();
    const int all = resolveThreadCount(0);
    out << "\nDeformation (4x4x4 Bezier), ms per evaluation; reference = plain scalar kernel, one thread\n";
    out << "  vertices  threads  normals        ms  reference ms   speed-up\n";
    std::vector<int> sizes = {10000, 100000, 1000000};
    if (options.quick)
        sizes = {10000, 100000};
    for (int vertices : sizes) {
        OrientedBox box;
        box.size = Vec3(1.0, 0.6, 0.3);
        const Lattice lattice = Lattice::create({}, box).value();
        std::vector<Vec3f> points, normals(std::size_t(vertices), Vec3f::UnitY());
        unsigned seed = 7;
        auto next = [&] { seed = seed * 1664525u + 1013904223u; return double(seed >> 8) / double(1u << 24); };
        for (int i = 0; i < vertices; ++i)
            points.push_back(box.toWorld(Vec3(next(), next(), next())).cast<float>());
        const Binding binding = Binding::create(lattice, points, normals);
        const ReferenceDeformer reference(lattice, points, normals);
        std::vector<Vec3> nodes = lattice.restNodes();
        for (Vec3& n : nodes)
            n += Vec3(0.05 * n.y(), 0.02 * n.z(), -0.03 * n.x());
        std::vector<Vec3f> outPositions(points.size()), outNormals(points.size());
        const double minSeconds = options.quick ? 0.05 : 0.3;
        for (bool withNormals : {false, true}) {
            const std::span<Vec3f> n = withNormals ? std::span<Vec3f>(outNormals) : std::span<Vec3f>();
            const double refMs = 1e3 * analysis::bestSecondsPerUnit([&] { reference.evaluate(nodes, outPositions, n); }, 1, minSeconds);
            for (int threads : {1, all}) {
                if (threads == 1 && all == 1 && rows.size() % 2 == 1)
                    continue;
                const double ms = 1e3 * analysis::bestSecondsPerUnit([&] { binding.evaluate(nodes, outPositions, n, threads); }, 1, minSeconds);
                rows.push_back({{"vertices", vertices}, {"threads", threads}, {"normals", withNormals}, {"ms", ms},
                                {"reference_ms", refMs}});
                char line[160];
                std::snprintf(line, sizeof line, "  %8d  %7d  %7s  %8.3f  %12.3f  %8.1fx\n", vertices, threads,
                              withNormals ? "yes" : "no", ms, refMs, refMs / ms);
                out << line;
            }
        }
    }
    return rows;
}

/// Microseconds per 60 Hz frame of a 4x4x4 DraggedBody (symplectic Euler) deforming 100,000 scattered
/// vertices (positions and normals, one thread): four steps of 1/240 s, then the mesh, unless the
/// nodes did not move.
double frameMicroseconds(bool sleeping, double minSeconds) {
    DraggedBody body({}, IntegratorKind::SymplecticEuler, {}, sleeping);
    std::vector<Vec3f> points, normals(100000, Vec3f::UnitY());
    unsigned seed = 11;
    auto next = [&] { seed = seed * 1664525u + 1013904223u; return float(seed >> 8) / float(1u << 24); };
    for (std::size_t i = 0; i < normals.size(); ++i)
        points.emplace_back(next(), next(), next());
    const Binding binding = Binding::create(body.lattice, points, normals);
    std::vector<Vec3f> outPositions(points.size()), outNormals(points.size());
    NodeChangeTracker moved;
    auto frame = [&] {
        for (int i = 0; i < 4; ++i)
            body.step();
        if (moved.changed(body.sim.state().position))
            binding.evaluate(body.sim.state().position, outPositions, outNormals, 1);
    };
    return 1e6 * analysis::bestSecondsPerUnit(frame, 1, minSeconds);
}

/// Microseconds per scene step of two soft bodies (4x4x4 Bezier, 500-vertex ellipsoid meshes, symplectic
/// Euler): a fish-sized one and a wide, stiffer flat one whose bottom is pinned; side by side (1 m apart) without and
/// with body collisions, and the first resting on the second under gravity, after a second to settle.
json bodyContactCosts(double minSeconds, std::ostream& out) {
    const auto scene = [](bool collide, double gap) {
        Scene s;
        for (int k = 0; k < 2; ++k) {
            SceneObject o;
            o.name = k == 0 ? "below" : "above";
            const Vec3 radii = k == 0 ? Vec3(0.3, 0.05, 0.3) : Vec3(0.15, 0.06, 0.1);
            const Vec3 centre(k == 0 ? 0.0 : gap, k == 0 ? 0.0 : 0.115, 0.0);
            o.mesh = makeUvEllipsoid(16, 32, radii, centre);
            OrientedBox box;
            box.origin = centre - 1.1 * radii;
            box.size = 2.2 * radii;
            o.lattice = Lattice::create({LatticeKind::Bezier, {4, 4, 4}}, box).value();
            // The support stiff enough to carry the body (at 60 N/m it folded under it: docs/design/lattice.md).
            o.material = uniformMaterial(o.lattice, 0.01, k == 0 ? 3000.0 : 60.0, 0.05);
            if (k == 0)
                for (int n = 0; n < o.lattice.nodeCount(); ++n)
                    if (o.lattice.coords(n)[1] == 0)
                        o.material.anchor[std::size_t(n)] = AnchorMode::Pinned;
            s.objects.push_back(std::move(o));
        }
        s.world.gravity = Vec3(0, -9.81, 0);
        s.world.simulation.integrator = IntegratorKind::SymplecticEuler;
        s.world.simulation.sleep = false;
        s.world.bodyCollisions.enabled = collide;
        return s;
    };
    int touching = 0;
    const auto perStep = [&](bool collide, double gap) {
        auto created = SceneSimulation::create(scene(collide, gap));
        SceneSimulation sim = std::move(created.value());
        sim.advanceTo(1.0);
        touching = sim.lastBodyContacts().contacts;
        const double dt = 1.0 / 240.0;
        return 1e6 * analysis::bestSecondsPerUnit([&] { sim.advanceTo(sim.time() + dt); }, 1, minSeconds);
    };
    const double off = perStep(false, 1.0), apart = perStep(true, 1.0), resting = perStep(true, 0.0);
    char line[220];
    std::snprintf(line, sizeof line,
                  "  two bodies (500 vertices each), us per scene step: body collisions off %.2f, on and apart %.2f "
                  "(%.2fx), one resting on the other (%d points touching) %.2f (%.2fx)\n",
                  off, apart, apart / off, touching, resting, resting / off);
    out << line;
    return {{"off_us", off}, {"apart_us", apart}, {"resting_us", resting}, {"resting_contacts", touching}};
}

json features(double minSeconds, std::ostream& out) {
    // Only what a scene uses costs anything: gravity and planes add passes, a sleeping body costs nothing.
    const LatticeShape shape;
    ExternalForces none, gravity, plane;
    gravity.gravity = Vec3(0, -9.81, 0);
    plane.planes.push_back(CollisionPlane{Vec3(0, -10, 0), Vec3::UnitY(), 0.0, 0.5});
    const double base = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, none, false, minSeconds);
    const double withGravity = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, gravity, false, minSeconds);
    const double withPlane = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, plane, false, minSeconds);
    const double asleep = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, none, true, minSeconds);
    const double unguarded = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, none, false, minSeconds, false);
    out << "\nWhat a scene does not use costs nothing (4x4x4, symplectic Euler), us per step\n";
    char line[200];
    std::snprintf(line, sizeof line,
                  "  drag only %.2f   + gravity %.2f   + plane %.2f   sleeping body %.3f (%.0fx cheaper)\n", base,
                  withGravity, withPlane, asleep, base / asleep);
    out << line;
    std::snprintf(line, sizeof line, "  energy guard off %.2f (the guard costs %.2fx)\n", unguarded, base / unguarded);
    out << line;
    // Stretch and squash limits: a scan of every spring per substep while none is out of bounds, the
    // Gauss-Seidel projection only when one is (the drag stretches this body's springs by up to ~8%).
    const double limitsIdle = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, none, false, minSeconds, true, {{1.5, 0.5}});
    const double limitsBinding = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, none, false, minSeconds, true, {{1.02, 0.98}});
    std::snprintf(line, sizeof line,
                  "  stretch/squash limits never reached (1.5x/0.5x) %.2f (%.2fx), holding (1.02x/0.98x) %.2f (%.2fx)\n",
                  limitsIdle, limitsIdle / base, limitsBinding, limitsBinding / base);
    out << line;
    // Volume preservation per integrator: the whole box's volume sampled at 4³ points, compliant (0.5) and
    // hard (1: Newton steps until |C| < 1e-6 V0).
    json volume = json::object();
    for (IntegratorKind k : integratorKinds()) {
        const double off = stepMicroseconds(shape, k, none, false, minSeconds);
        const double half = stepMicroseconds(shape, k, none, false, minSeconds, true, {{}, 0.5});
        const double hard = stepMicroseconds(shape, k, none, false, minSeconds, true, {{}, 1.0});
        std::snprintf(line, sizeof line, "  volume preservation, %-16s off %.2f   0.5 %.2f (%.2fx)   1 %.2f (%.2fx)\n",
                      std::string(integratorName(k)).c_str(), off, half, half / off, hard, hard / off);
        out << line;
        volume[std::string(integratorName(k))] = {{"off_us", off}, {"compliant_us", half}, {"hard_us", hard}};
    }
    // Colliders: one far away (the bounding-box test skips it), one the body rests on (contact at the nodes:
    // the bench body has no mesh).
    ExternalForces farRock, nearRock;
    Collider rock;
    rock.centre = Vec3(0.5, -5.0, 0.5);
    rock.radius = 0.5;
    farRock.colliders.push_back(rock);
    rock.centre = Vec3(0.8, -0.15, 0.5);
    rock.radius = 0.2;
    nearRock.colliders.push_back(rock);
    const double withFarRock = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, farRock, false, minSeconds);
    const double withNearRock = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, nearRock, false, minSeconds);
    std::snprintf(line, sizeof line, "  sphere collider out of reach %.2f (%.2fx), touching %.2f (%.2fx)\n", withFarRock,
                  withFarRock / base, withNearRock, withNearRock / base);
    out << line;
    // The same rocks as meshes (a sphere of 1,984 triangles): FCL's queries where the grid cannot rule a
    // point out.
    const auto rockMesh = MeshSurface::create(makeUvEllipsoid(32, 32, Vec3::Ones())).value();
    for (ExternalForces* f : {&farRock, &nearRock}) {
        Collider& c = f->colliders.front();
        c.shape = ColliderShape::Mesh;
        c.surface = rockMesh;
        c.scale = c.radius;
    }
    const double withFarMesh = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, farRock, false, minSeconds);
    const double withNearMesh = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, nearRock, false, minSeconds);
    std::snprintf(line, sizeof line, "  mesh collider (%zu triangles) out of reach %.2f (%.2fx), touching %.2f (%.2fx)\n",
                  rockMesh->mesh().triangles.size(), withFarMesh, withFarMesh / base, withNearMesh, withNearMesh / base);
    out << line;
    const json bodies = bodyContactCosts(minSeconds, out);
    // What of that is the energy guard booking the pass (two energy evaluations a substep).
    const double hardUnguarded = stepMicroseconds(shape, IntegratorKind::SymplecticEuler, none, false, minSeconds, false, {{}, 1.0});
    std::snprintf(line, sizeof line, "  volume preservation 1, symplectic-euler, energy guard off: %.2f (%.2fx the guarded step without it)\n",
                  hardUnguarded, hardUnguarded / base);
    out << line;
    volume["symplectic-euler"]["hard_guard_off_us"] = hardUnguarded;
    // An unchanged frame (the body asleep) skips the mesh too.
    const double frameAwake = frameMicroseconds(false, minSeconds);
    const double frameAsleep = frameMicroseconds(true, minSeconds);
    std::snprintf(line, sizeof line,
                  "  60 Hz frame with 100,000 vertices (4 steps + positions and normals): moving %.1f us, "
                  "asleep %.3f us (%.0fx cheaper)\n", frameAwake, frameAsleep, frameAwake / frameAsleep);
    out << line;
    return {{"awake_us", base},          {"gravity_us", withGravity},        {"plane_us", withPlane},
            {"sleeping_us", asleep},     {"frame_moving_us", frameAwake},    {"frame_sleeping_us", frameAsleep},
            {"energy_guard_off_us", unguarded}, {"strain_limits_idle_us", limitsIdle},
            {"strain_limits_binding_us", limitsBinding}, {"volume_preservation", volume},
            {"collider_out_of_reach_us", withFarRock}, {"collider_touching_us", withNearRock},
            {"mesh_collider_out_of_reach_us", withFarMesh}, {"mesh_collider_touching_us", withNearMesh},
            {"body_contacts", bodies}};
}

/// What an edit in the editor costs on `scene`'s first object: the simulation built from nothing (what
/// every paint dab, step change or preset cost before: a binding, contact and volume samples and bodies)
/// against the incremental rebuild that keeps what mesh and lattice alone make, then one 60 Hz frame
/// on it (4 steps at 240 Hz, every vertex deformed).
json editCosts(const Scene& scene, double minSeconds, std::ostream& out) {
    Scene dab = scene;  // a dab: one node's stiffness raised by a tenth (and its goal weight, on a base animation)
    LatticeMaterial& m = dab.objects.front().material;
    m.stiffness[m.stiffness.size() / 2] *= 1.1;
    if (!m.goalWeight.empty())
        m.goalWeight[m.goalWeight.size() / 2] = 0.5 * (m.goalWeight[m.goalWeight.size() / 2] + 1.0);
    auto previous = SceneSimulation::create(scene);
    if (!previous) {
        out << "\nedit: " << previous.message() << "\n";
        return {{"error", previous.message()}};
    }
    const double rebuildMs = 1e3 * analysis::bestSecondsPerUnit([&] { (void)SceneSimulation::create(dab); }, 1, minSeconds);
    const double incrementalMs =
        1e3 * analysis::bestSecondsPerUnit([&] { (void)SceneSimulation::create(dab, &previous.value()); }, 1, minSeconds);
    SceneSimulation sim = std::move(SceneSimulation::create(dab, &previous.value()).value());
    std::vector<Vec3f> positions(sim.object(0).mesh->positions.size()), normals(positions.size());
    // The editor's viewport deforms the mesh on the GPU from the nodes (render/): its frame is the steps.
    const double stepsMs = 1e3 * analysis::bestSecondsPerUnit([&] { sim.advanceTo(sim.time() + 1.0 / 60.0); }, 1, minSeconds);
    const double frameMs = 1e3 * analysis::bestSecondsPerUnit(
                                     [&] {
                                         sim.advanceTo(sim.time() + 1.0 / 60.0);
                                         sim.evaluate(0, positions, normals);
                                     },
                                     1, minSeconds);
    // The properties panel's lowest modes of the edited object, as it shows them after a dab.
    const double modesMs = 1e3 * analysis::bestSecondsPerUnit([&] { (void)objectModes(dab.objects.front(), 3); }, 1, minSeconds);
    char line[800];
    std::snprintf(line, sizeof line,
                  "\nEditor edit (a paint dab on %s: %zu vertices, %zu triangles, %zu nodes)\n"
                  "  rebuild from nothing %.3f ms; incremental (binding and samples kept) %.3f ms (%.1fx cheaper)\n"
                  "  what the dab adds to its frame: the incremental rebuild, %.3f of a rebuild from nothing\n"
                  "  the editor's frame with the dab (the rebuild and 4 steps; the viewport deforms on the GPU): %.3f ms, "
                  "%.3f of a rebuild from nothing\n"
                  "  a bake's 60 Hz frame (4 steps, every vertex deformed on the CPU), edit or not: %.3f ms\n"
                  "  the lowest modes the properties panel shows after the dab: %.3f ms\n",
                  sim.object(0).name.c_str(), positions.size(), sim.object(0).mesh->triangles.size(),
                  sim.simulator(0).state().position.size(), rebuildMs, incrementalMs, rebuildMs / incrementalMs,
                  incrementalMs / rebuildMs, incrementalMs + stepsMs, (incrementalMs + stepsMs) / rebuildMs, frameMs, modesMs);
    out << line;
    return {{"scene", sim.object(0).name}, {"nodes", sim.simulator(0).state().position.size()}, {"rebuild_ms", rebuildMs},
            {"incremental_ms", incrementalMs}, {"steps_ms", stepsMs}, {"frame_ms", frameMs}, {"modes_ms", modesMs},
            {"vertices", positions.size()}};
}

}  // namespace

json runBench(const BenchOptions& options, std::ostream& out) {
    const double minSeconds = options.quick ? 0.05 : 0.3;
    const auto wanted = [&](const char* key) { return options.only.empty() || options.only == key; };
    json doc;
    doc["machine"] = {{"hardware_threads", resolveThreadCount(0)}, {"bullet", bulletAvailable()}};
    doc["quick"] = options.quick;
    if (wanted("lattice_step_us"))
        doc["lattice_step_us"] = latticeSteps({LatticeKind::Bezier, {4, 4, 4}}, "4x4x4 Bezier", minSeconds, out);
    if (wanted("lattice_step_us_8x4x4"))
        doc["lattice_step_us_8x4x4"] = latticeSteps({LatticeKind::BSpline, {8, 4, 4}}, "8x4x4 B-spline", minSeconds, out);
    // A fine lattice, where the element's explicit substeps grow fastest: seconds of stepping, so only in a full run.
    if ((!options.quick && options.only.empty()) || options.only == "lattice_step_us_8x8x8")
        doc["lattice_step_us_8x8x8"] = latticeSteps({LatticeKind::Bezier, {8, 8, 8}}, "8x8x8 Bezier", minSeconds, out);
    if (wanted("features")) doc["features"] = features(minSeconds, out);
    if (wanted("deform")) doc["deform"] = deformation(options, out);
    if (wanted("table1")) doc["table1"] = table1Section(options.quick, out);
    if (wanted("edit"))
        for (const Scene* scene : options.editScenes)
            doc["edit"].push_back(editCosts(*scene, minSeconds, out));
    if (wanted("haptic")) doc["haptic"] = hapticBench(options.hapticScenes, options.quick ? 2.0 : 5.0, options.hapticPriority, out);
    return doc;
}

}  // namespace softtouch::bench
