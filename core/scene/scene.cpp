#include "core/scene/scene.h"

#include "core/base/ranges.h"
#include "core/geometry/mesh_surface.h"
#include "core/geometry/oriented_box.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace softtouch {

Status WorldSettings::validate() {
    if (!isFinite(gravity) || gravity.norm() > ranges::kMaxGravity)
        return Status::error("gravity must be finite and at most 1e4 m/s² (a thousand g)");
    if (Status s = simulation.validate(); !s)
        return s;
    for (const auto& [range, value] : {std::pair{ranges::kFrames, double(frames)}, std::pair{ranges::kFps, fps}})
        if (std::string problem = range.problem(value); !problem.empty())
            return Status::error(std::move(problem));
    for (std::size_t i = 0; i < planes.size(); ++i) {
        CollisionPlane& p = planes[i];
        const std::string name = "plane " + std::to_string(i);
        if (!isFinite(p.point) || !isFinite(p.normal) || p.normal.norm() < 1e-9)
            return Status::error(name + ": point and normal must be finite and the normal non-zero");
        p.normal.normalize();
        for (const auto& [range, value] : {std::pair{ranges::kRestitution, p.restitution}, std::pair{ranges::kFriction, p.friction}})
            if (const std::string problem = range.problem(value); !problem.empty())
                return Status::error(name + ": " + problem);
    }
    for (std::size_t i = 0; i < colliders.size(); ++i)
        if (Status s = colliders[i].validate(); !s)
            return Status::error("collider " + std::to_string(i) + ": " + s.message());
    return bodyCollisions.validate();
}

Bounds restBounds(const Scene& scene) {
    if (scene.objects.empty())
        return {};
    Bounds all = scene.objects.front().mesh->bounds();
    for (const SceneObject& o : scene.objects)
        all = all.united(o.mesh->bounds());
    return all;
}

SimulationSettings newSceneSimulation(const Scene& scene) {
    SimulationSettings settings;
    settings.integrator = IntegratorKind::Verlet;
    for (const SceneObject& object : scene.objects) {
        auto model = buildLatticeBody(object.lattice, object.material);
        if (!model)
            continue;  // the scene does not build at all; SceneSimulation::create says why
        if (Simulator(model.value(), settings).substepsFor({}) > kNewSceneMaxSubsteps) {
            settings.integrator = IntegratorKind::ImplicitEuler;
            break;
        }
    }
    return settings;
}

Result<Scene> newScene(std::string name, Mesh mesh) {
    SceneObject object;
    object.name = std::move(name);
    if (mesh.normals.empty())
        mesh.computeNormals();
    object.mesh = std::move(mesh);
    auto box = fitBox(object.mesh->positions);
    if (!box)
        return Status::error(box.message());
    auto lattice = Lattice::create(LatticeShape{}, box.value());
    if (!lattice)
        return Status::error(lattice.message());
    object.lattice = lattice.value();
    object.material = defaultMaterial(object.lattice);
    Scene scene;
    scene.objects.push_back(std::move(object));
    scene.world.simulation = newSceneSimulation(scene);
    return scene;
}

LatticeMaterial simulatedMaterial(const SceneObject& object) {
    return object.baseAnimation ? followingMaterial(object.material) : object.material;
}

Result<ModalAnalysis> objectModes(const SceneObject& object, int count) {
    return objectModes(object.lattice, object.material, object.baseAnimation ? &object.follow : nullptr, count);
}

Result<ModalAnalysis> objectModes(const Lattice& lattice, const LatticeMaterial& material, const FollowSettings* follow,
                                  int count) {
    auto body = buildLatticeBody(lattice, follow ? followingMaterial(material) : material);
    if (!body)
        return body.status();
    if (!follow)
        return analyseModes(*body.value(), count);
    return analyseModes(*body.value(), count, goalSprings(*body.value(), material.goalWeight, *follow));
}

Status checkSolverLimits(const SceneObject& object, const WorldSettings& world) {
    if (world.simulation.integrator == IntegratorKind::ImplicitEuler &&
        std::size_t(object.lattice.nodeCount()) > ranges::kMaxImplicitNodes)
        return Status::error("object '" + object.name + "': implicit Euler factorises at most " +
                             std::to_string(ranges::kMaxImplicitNodes) + " lattice nodes (16x16x16) and this lattice has " +
                             std::to_string(object.lattice.nodeCount()) + "; use verlet or xpbd, or fewer nodes");
    if (const IntegratorInfo& scheme = integratorInfo(world.simulation.integrator);
        object.material.element == BodyElement::Solid && !scheme.runsElement)
        return Status::error("object '" + object.name + "': the solid element runs with " +
                             integratorNames([](const IntegratorInfo& i) { return i.runsElement; }) + ", not " +
                             std::string(scheme.name) + " (whose constraints act on springs and node masses); set "
                             "simulation.integrator or use \"element\": \"springs\"");
    return Status::success();
}

Status checkObjectLimits(const SceneObject& object, const WorldSettings& world) {
    const Bounds bounds = object.mesh->bounds();
    const double across = (bounds.max - bounds.min).norm();
    if (!(across >= ranges::kMinMeshSize && across <= ranges::kMaxMeshSize)) {
        char size[32];
        std::snprintf(size, sizeof size, "%.3g", across);
        return Status::error("object '" + object.name + "': its mesh is " + size +
                             " m across; SoftTouch works in metres, from 0.1 mm to 100 km: rescale it");
    }
    // How far outside the box (in box lengths) the farthest vertex lies.
    const OrientedBox& box = object.lattice.box();
    double outside = 0.0;
    for (const Vec3f& p : object.mesh->positions) {
        const Vec3 t = box.toParameters(p.cast<double>());
        outside = std::max({outside, -t.minCoeff(), t.maxCoeff() - 1.0});
    }
    if (!(outside <= ranges::kMaxOutsideBox)) {
        char distance[32];
        std::snprintf(distance, sizeof distance, "%.3g", outside);
        return Status::error("object '" + object.name + "': its mesh lies up to " + distance +
                             " box lengths outside its lattice box (at most 10): move or enlarge the box, or leave "
                             "\"box\" out so SoftTouch fits one");
    }
    return checkSolverLimits(object, world);
}

namespace {

bool sameLattice(const SceneObject& a, const SceneObject& b) {
    return a.lattice.shape() == b.lattice.shape() && a.lattice.restNodes() == b.lattice.restNodes();
}

/// Whether two objects have the same mesh and lattice: what their bindings and samples are made of. The
/// editor's copies of a scene share one mesh, so comparing values is for meshes made again (a reload).
bool sameGeometry(const SceneObject& a, const SceneObject& b) {
    const Mesh& x = *a.mesh;
    const Mesh& y = *b.mesh;
    return (a.mesh.sameAs(b.mesh) || (x.positions == y.positions && x.triangles == y.triangles && x.normals == y.normals)) &&
           sameLattice(a, b);
}

}  // namespace

Result<SceneSimulation> SceneSimulation::create(const Scene& input, const SceneSimulation* previous) {
    return create(Scene(input), previous);
}

Result<SceneSimulation> SceneSimulation::create(Scene&& input, const SceneSimulation* previous) {
    auto scene = std::make_shared<Scene>(std::move(input));
    if (scene->objects.empty())
        return Status::error("the scene has no objects");
    if (Status s = scene->world.validate(); !s)
        return s;
    // A mesh and lattice the previous simulation ran were checked then (shared meshes never change): only
    // what depends on the world is checked again.
    std::vector<bool> ranBefore(scene->objects.size(), false);
    for (std::size_t i = 0; i < scene->objects.size(); ++i) {
        const SceneObject& object = scene->objects[i];
        if (previous && i < previous->m_objects.size()) {
            const SceneObject& before = *previous->m_objects[i].source;
            ranBefore[i] = before.mesh.sameAs(object.mesh) && sameLattice(before, object);
        }
        if (Status s = ranBefore[i] ? checkSolverLimits(object, scene->world) : checkObjectLimits(object, scene->world); !s)
            return s;
    }
    SceneSimulation sim;
    sim.m_scene = scene;
    for (std::size_t i = 0; i < scene->objects.size(); ++i) {
        SceneObject& object = scene->objects[i];
        const std::string where = "object '" + object.name + "': ";
        if (!ranBefore[i]) {
            if (Status s = object.mesh->validate(); !s)
                return Status::error(where + s.message());
        }
        if (object.mesh->normals.empty()) {
            Mesh withNormals = *object.mesh;
            withNormals.computeNormals();
            object.mesh = std::move(withNormals);
        }
        for (std::size_t d = 0; d < object.drivers.size(); ++d) {
            if (Status s = validateDriver(object.drivers[d]); !s)
                return Status::error(where + "driver " + std::to_string(d) + ": " + s.message());
        }
        std::shared_ptr<Geometry> geometry;
        if (ranBefore[i] || (previous && i < previous->m_objects.size() && sameGeometry(*previous->m_objects[i].source, object)))
            geometry = previous->m_objects[i].geometry;
        else
            geometry = std::make_shared<Geometry>(
                Geometry{Binding::create(object.lattice, object.mesh->positions, object.mesh->normals), {}, nullptr, nullptr});
        const bool animated = object.baseAnimation != nullptr;
        // An object whose mesh, lattice, material and base animation are those the previous simulation ran keeps
        // its body and base motion (both immutable): an edit of one object of several rebuilds that one alone.
        const Runtime* kept = nullptr;
        if (ranBefore[i]) {
            const Runtime& before = previous->m_objects[i];
            const SceneObject& was = *before.source;
            if (was.material == object.material && was.baseAnimation == object.baseAnimation &&
                (!animated || was.follow == object.follow))
                kept = &before;
        }
        auto model = kept ? Result<std::shared_ptr<const BodyModel>>(kept->simulator.sharedModel())
                          : buildLatticeBody(object.lattice, simulatedMaterial(object), &*object.mesh, &geometry->derived);
        if (!model)
            return Status::error(where + model.message());
        if (scene->world.bodyCollisions.enabled && scene->objects.size() > 1 && !object.mesh->triangles.empty() &&
            !geometry->restSurface) {
            auto surface = MeshSurface::shared(object.mesh);
            if (!surface)
                return Status::error(where + surface.message());
            geometry->restSurface = surface.value();
        }
        std::shared_ptr<BaseMotion> motion;
        if (kept) {
            motion = kept->motion;
        } else if (animated) {
            if (!geometry->goalFit) {  // depends on mesh and lattice only: kept with the geometry
                auto fit = GoalFit::create(object.lattice, object.mesh->positions, geometry->binding.parameters());
                if (!fit)
                    return Status::error(where + fit.message());
                geometry->goalFit = std::make_shared<const GoalFit>(std::move(fit.value()));
            }
            auto created = BaseMotion::create(object.lattice, *model.value(), object.mesh->positions, geometry->goalFit,
                                              object.baseAnimation, object.material.goalWeight, object.follow);
            if (!created)
                return Status::error(where + created.message());
            motion = created.value();
        }
        sim.m_objects.push_back(Runtime{&object, std::move(geometry), Simulator(model.value(), scene->world.simulation), {},
                                        std::move(motion), {}, {}, -1, {}});
        // Where the drivers hold the lattice: a ball's grip sums the basis over thousands of points (1.3 ms on
        // 8x8x8), so an edit that leaves the lattice and the drivers as they ran keeps it.
        std::vector<DriverGrip>& grips = sim.m_objects.back().grips;
        if (ranBefore[i] && previous->m_objects[i].source->drivers == object.drivers) {
            grips = previous->m_objects[i].grips;
        } else {
            for (const Driver& driver : object.drivers)
                grips.push_back(driverGrip(driver, object.lattice));
        }
    }
    return sim;
}

ExternalForces SceneSimulation::forcesAt(std::size_t i, double seconds) const {
    ExternalForces f;
    f.gravity = m_scene->world.gravity;
    f.planes = m_scene->world.planes;
    f.colliders = m_scene->world.colliders;
    const SceneObject& object = *m_objects[i].source;
    for (std::size_t d = 0; d < object.drivers.size(); ++d) {
        if (auto drag = driverDrag(object.drivers[d], m_objects[i].grips[d], seconds))
            f.drags.push_back(std::move(*drag));
    }
    const std::size_t firstInteractive = f.drags.size();
    f.drags.insert(f.drags.end(), m_objects[i].interactive.begin(), m_objects[i].interactive.end());
    if (const auto& motion = m_objects[i].motion) {
        // A hand pulls where it sees the body, in the world: its target moves into the deviation frame by
        // what separates it from the material point as shown, turned back by the base's rotation.
        // Only with a hand: the pose as shown at the step's start is a fit of its own.
        const std::vector<Vec3>& x = m_objects[i].simulator.state().position;
        std::vector<Vec3> shown;
        Mat3 rotation;
        if (f.drags.size() > firstInteractive)
            motion->shownNodes(seconds, x, shown, &rotation);
        for (std::size_t d = firstInteractive; d < f.drags.size(); ++d) {
            DragSpring& drag = f.drags[d];
            Vec3 local = Vec3::Zero(), world = Vec3::Zero();
            for (const NodeWeight& w : drag.support) {
                local += w.weight * x[w.node];
                world += w.weight * shown[w.node];
            }
            drag.target = local + rotation.transpose() * (drag.target - world);
            drag.targetVelocity = rotation.transpose() * drag.targetVelocity;
        }
        // The body is the deviation from the base animation, in the base's frame: world planes and colliders
        // do not apply to it (docs/design/lattice.md, "Secondary motion on a base animation").
        f.planes.clear();
        f.colliders.clear();
        motion->addForces(seconds, m_scene->world.simulation.dt, m_objects[i].simulator.model(), f);
    }
    return f;
}

void SceneSimulation::record(std::size_t i, const StepReport& report, std::vector<std::string>* problems) {
    if (report.problem.empty())
        return;
    const Simulator& sim = m_objects[i].simulator;
    std::ostringstream at;
    at << "object '" << m_objects[i].source->name << "' at t=" << sim.time() + double(report.rewoundSteps) * sim.settings().dt
       << " s: " << report.problem;
    if (report.refused && m_refusal.empty())
        m_refusal = at.str();
    if (problems)
        problems->push_back(at.str());
}

StepReport SceneSimulation::stepObject(std::size_t i, std::vector<std::string>* problems, const StepInputs& inputs) {
    Runtime& r = m_objects[i];
    if (inputs)
        inputs(*this, i, r.simulator.stepCount());
    r.lastForces = forcesAt(i, r.simulator.time());  // forces sampled at the step's start
    r.previous = r.simulator.state().position;
    r.previousStep = r.simulator.stepCount();
    const StepReport report = r.simulator.step(r.lastForces);
    record(i, report, problems);
    return report;
}

bool SceneSimulation::settleObject(std::size_t i, std::vector<std::string>* problems) {
    StepReport report;
    const bool accepted = m_objects[i].simulator.settle(m_objects[i].lastForces, report);
    record(i, report, problems);
    return accepted;
}

void SceneSimulation::advanceTo(double seconds, std::vector<std::string>* problems, const StepInputs& inputs) {
    const double dt = m_scene->world.simulation.dt;
    // A step is due while it ends at or before `seconds` (a relative tolerance absorbs rounding of
    // seconds = frame / fps).
    const auto due = [&](const Simulator& sim) { return double(sim.stepCount() + 1) * dt <= seconds * (1.0 + 1e-12) + 1e-12; };
    // A rollback puts the clock back (Simulator::step), so each loop runs until the span is stepped again and
    // the guard accepts the end; each rollback doubles the substeps or stops the body, so it ends.
    if (!m_scene->world.bodyCollisions.enabled || m_objects.size() < 2) {
        for (std::size_t i = 0; i < m_objects.size(); ++i) {  // independent: each runs to the end alone
            do {
                while (due(m_objects[i].simulator))
                    (void)stepObject(i, problems, inputs);
            } while (!settleObject(i, problems));
        }
        return;
    }
    // Every object takes the same steps, so when one rolls back all go back to the last step every guard
    // accepted (`accepted`), keeping what each guard learnt, and step from there together.
    Snapshot accepted = saveSnapshot();
    const auto rewindAll = [&] {
        for (std::size_t i = 0; i < m_objects.size(); ++i) {
            m_objects[i].simulator.rewind(accepted.bodies[i], accepted.step);
            m_objects[i].previousStep = -1;
        }
    };
    const auto settleAll = [&] {
        bool all = true;
        for (std::size_t i = 0; i < m_objects.size(); ++i)
            all = settleObject(i, problems) && all;
        return all;
    };
    for (;;) {
        while (due(m_objects.front().simulator)) {
            const double start = m_objects.front().simulator.time();
            bool rolledBack = false;
            for (std::size_t i = 0; i < m_objects.size(); ++i)
                rolledBack = stepObject(i, problems, inputs).rewoundSteps > 0 || rolledBack;
            if (rolledBack) {
                rewindAll();
                continue;
            }
            resolveBodyContacts(start);
            // One guard's check moves its accepted state on: the others check at the same step, so the scene
            // has one accepted step to go back to.
            bool checked = false;
            for (const Runtime& r : m_objects)
                checked = checked || r.simulator.lastAcceptedStep() == r.simulator.stepCount();
            if (!checked)
                continue;
            if (!settleAll()) {
                rewindAll();
                continue;
            }
            accepted = saveSnapshot();
        }
        if (settleAll())
            return;
        rewindAll();
    }
}

void SceneSimulation::advanceToSample(double seconds, std::vector<std::string>* problems, const StepInputs& inputs) {
    const double dt = m_scene->world.simulation.dt;
    // The first step whose end is at or past `seconds`, with advanceTo's tolerance for a time on a step.
    const double steps = std::ceil(seconds / dt * (1.0 - 1e-12) - 1e-9);
    advanceTo(std::max(0.0, steps) * dt, problems, inputs);
}

std::vector<Vec3> SceneSimulation::nodesAt(std::size_t i, double seconds) const {
    const Runtime& r = m_objects[i];
    const Simulator& sim = r.simulator;
    const std::vector<Vec3>& now = sim.state().position;
    const double dt = sim.settings().dt;
    // Behind the end by this fraction of the step (0 at the state itself).
    const double back = (sim.time() - seconds) / dt;
    if (back <= 1e-9 || r.previousStep != sim.stepCount() - 1)
        return now;
    const double w = std::min(back, 1.0);
    std::vector<Vec3> out(now.size());
    for (std::size_t k = 0; k < now.size(); ++k)
        out[k] = now[k] + w * (r.previous[k] - now[k]);
    return out;
}

void SceneSimulation::resolveBodyContacts(double stepStart) {
    m_lastBodyContacts = {};
    const WorldSettings& world = m_scene->world;
    // Working copies only for objects that touch another: a scene whose objects are apart pays one bounds
    // pass per pair.
    std::vector<BodyState> states(m_objects.size());
    std::vector<ContactBody> bodies(m_objects.size());
    for (std::size_t i = 0; i < m_objects.size(); ++i) {
        const Runtime& r = m_objects[i];
        bodies[i] = {&r.simulator.model(), &r.source->lattice, r.geometry->restSurface.get(), const_cast<BodyState*>(&r.simulator.state())};
    }
    std::vector<std::uint8_t> changed(m_objects.size(), 0);
    for (std::size_t i = 0; i < m_objects.size(); ++i)
        for (std::size_t j = i + 1; j < m_objects.size(); ++j) {
            // A body on a base animation lives in its base's frame: not yet tested against others.
            if (m_objects[i].motion || m_objects[j].motion || !bodiesMayTouch(bodies[i], bodies[j]))
                continue;
            for (std::size_t k : {i, j})
                if (!changed[k]) {
                    states[k] = m_objects[k].simulator.state();
                    bodies[k].state = &states[k];
                    changed[k] = 1;
                }
            const BodyContactPass pass = softtouch::resolveBodyContacts(
                bodies[i], bodies[j], world.bodyCollisions, restingContactSpeed(world.gravity, world.simulation.dt));
            m_lastBodyContacts.contacts += pass.contacts;
            m_lastBodyContacts.deepest = std::max(m_lastBodyContacts.deepest, pass.deepest);
        }
    if (m_lastBodyContacts.contacts == 0)
        return;
    for (std::size_t i = 0; i < m_objects.size(); ++i)
        if (changed[i])
            m_objects[i].simulator.applyCorrection(states[i], forcesAt(i, stepStart));
}

double SceneSimulation::time() const {
    return m_objects.empty() ? 0.0 : m_objects.front().simulator.time();
}

long long SceneSimulation::stepCount() const {
    return m_objects.empty() ? 0 : m_objects.front().simulator.stepCount();
}

void SceneSimulation::setInteractiveDrags(std::size_t i, std::vector<DragSpring> drags) {
    m_objects[i].interactive = std::move(drags);
}

SceneSimulation::Snapshot SceneSimulation::saveSnapshot() const {
    Snapshot s;
    s.step = stepCount();
    for (const Runtime& r : m_objects)
        s.bodies.push_back(r.simulator.saveState());
    return s;
}

void SceneSimulation::restoreSnapshot(const Snapshot& snapshot) {
    assert(snapshot.bodies.size() == m_objects.size());
    for (std::size_t i = 0; i < m_objects.size(); ++i) {
        assert(snapshot.bodies[i].position.size() == m_objects[i].simulator.state().position.size());
        m_objects[i].simulator.restoreState(snapshot.bodies[i], snapshot.step);
        m_objects[i].previousStep = -1;
    }
}

void SceneSimulation::reset() {
    for (Runtime& r : m_objects) {
        r.simulator.restoreState(restState(r.simulator.model()), 0);
        r.interactive.clear();
        r.previousStep = -1;
    }
    m_refusal.clear();
}

void SceneSimulation::evaluate(std::size_t i, std::span<Vec3f> positions, std::span<Vec3f> normals, int threads) const {
    evaluateNodes(i, m_objects[i].simulator.state().position, m_objects[i].simulator.time(), positions, normals, threads);
}

void SceneSimulation::evaluateNodes(std::size_t i, std::span<const Vec3> nodes, double seconds, std::span<Vec3f> positions,
                                    std::span<Vec3f> normals, int threads) const {
    const Runtime& r = m_objects[i];
    if (r.motion)
        r.motion->deform(seconds, r.geometry->binding, nodes, r.source->mesh->triangles, positions, normals);
    else
        r.geometry->binding.evaluate(nodes, positions, normals, threads);
}

std::vector<Vec3> SceneSimulation::shownNodes(std::size_t i, std::span<const Vec3> nodes, double seconds) const {
    if (!m_objects[i].motion)
        return {nodes.begin(), nodes.end()};
    std::vector<Vec3> shown;
    m_objects[i].motion->shownNodes(seconds, nodes, shown);
    return shown;
}

std::size_t SceneSimulation::totalVertexCount() const {
    std::size_t n = 0;
    for (const Runtime& r : m_objects)
        n += r.geometry->binding.vertexCount();
    return n;
}

}  // namespace softtouch
