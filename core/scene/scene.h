#pragma once
/// A scene: objects (mesh + lattice + material + drivers) and the world they share, plus the
/// runtime that simulates them. Only what a scene uses is computed: no planes, no collision pass;
/// no gravity, no gravity term; a body at rest sleeps.

#include "core/animation/base_motion.h"
#include "core/animation/drivers.h"
#include "core/body/body_contacts.h"
#include "core/body/lattice_body.h"
#include "core/geometry/binding.h"
#include "core/solver/simulator.h"

#include <functional>
#include <string>
#include <vector>

namespace softtouch {

/// One deformable object.
struct SceneObject {
    std::string name;                 ///< Shown to the user; unique in the scene.
    SharedMesh mesh;                  ///< Rest mesh (normals filled on load), shared between the scene's copies.
    Lattice lattice;                  ///< Lattice around the mesh.
    LatticeMaterial material;         ///< Painted values, anchors, voids.
    std::vector<Driver> drivers;      ///< Headless motion sources.
    /// The mesh's own animation, when it came with one: the body adds secondary motion on top of it
    /// (core/animation/base_motion.h; goal weights are the material's). The mesh above is its first sample.
    std::shared_ptr<const BaseAnimation> baseAnimation;
    FollowSettings follow;            ///< Goal springs toward the base animation.
};

/// The material an object's body is built from: its own, with the nodes of goal weight 1 pinned when it
/// follows a base animation (followingMaterial()). Modes and step bounds shown for it use this.
LatticeMaterial simulatedMaterial(const SceneObject& object);
/// The lowest `count` modes of an object's body as it is simulated: simulatedMaterial() and, on a base
/// animation, its goal springs (core/animation/base_motion.h).
Result<ModalAnalysis> objectModes(const SceneObject& object, int count = 3);
/// The same for a lattice and material, on a base animation followed with `follow` (nullptr: none).
Result<ModalAnalysis> objectModes(const Lattice& lattice, const LatticeMaterial& material, const FollowSettings* follow,
                                  int count = 3);

/// Settings shared by every object.
struct WorldSettings {
    Vec3 gravity = Vec3::Zero();              ///< m/s^2.
    std::vector<CollisionPlane> planes;       ///< Collision planes.
    std::vector<Collider> colliders;          ///< Spheres, capsules, boxes and meshes.
    BodyCollisionSettings bodyCollisions;     ///< Objects against each other; off by default.
    SimulationSettings simulation;            ///< Integrator, dt, guards.
    int frames = 48;                          ///< Default clip length, frames. [1, 1e6].
    double fps = 24.0;                        ///< Default clip rate, frames per second. (0, 1000].
    /// Checks ranges; planes get unit normals.
    Status validate();
};

/// A whole scene as authored.
struct Scene {
    std::vector<SceneObject> objects; ///< At least one.
    WorldSettings world;              ///< Shared settings.
};

/// Every object's rest mesh together: their bounds (zero bounds for no objects).
Bounds restBounds(const Scene& scene);

/// Most explicit substeps per step a new scene accepts at its default step: a body that needs more
/// (very stiff or very light for its size) starts on implicit Euler instead, which is stable at any step.
inline constexpr int kNewSceneMaxSubsteps = 32;

/// The simulation settings a newly created scene starts with (docs/design/lattice.md, "The integrator of a new
/// scene"): Verlet at 240 steps/s, which substeps below its stability bound and so keeps the material's
/// own decay per period (≥ 99% of it; implicit Euler at the same step keeps 92% of the angelfish's), unless
/// some object's body would need more than kNewSceneMaxSubsteps substeps per step: then implicit Euler.
/// Projects that do not name an integrator keep SimulationSettings' default (implicit Euler), so old
/// files move as they did; a saved new scene names its integrator.
SimulationSettings newSceneSimulation(const Scene& scene);

/// A new scene of one object made from a mesh (the editor's Import Mesh): a 4x4x4 Bezier lattice fitted
/// to it, the default material (defaultMaterial(): a Continuum fish body, the same on any lattice), no
/// gravity, and newSceneSimulation(). Fails, saying why, when no box fits the mesh.
Result<Scene> newScene(std::string name, Mesh mesh);

/// What an object needs beyond each field's range before it can run in this world: the solver's limits
/// (ranges::kMaxImplicitNodes). SceneSimulation::create checks it and so does the project reader (before
/// it builds the body), so a file that validates also runs. Errors name the object.
Status checkObjectLimits(const SceneObject& object, const WorldSettings& world);
/// The solver's part of checkObjectLimits(), what a material or world edit can change: implicit Euler's node
/// limit (its factor grows with the lattice) and the schemes that run the solid element (not XPBD).
Status checkSolverLimits(const SceneObject& object, const WorldSettings& world);

/// Runtime of a scene: bodies, bindings and simulators built once, stepped together.
class SceneSimulation {
public:
    /// Validates the scene and builds everything; errors name the object. With `previous` (a simulation
    /// of an earlier version of the scene: the editor after an edit), each object whose mesh and lattice
    /// are unchanged keeps what they alone make (the binding, the contact samples, the volume samples'
    /// occupancy, the rest surface): a material, world or driver edit rebuilds only the bodies.
    static Result<SceneSimulation> create(const Scene& scene, const SceneSimulation* previous = nullptr);
    static Result<SceneSimulation> create(Scene&& scene, const SceneSimulation* previous = nullptr);

    /// Everything that changes while a scene runs: every body's state and the time. Restoring one
    /// and stepping with the same inputs reproduces the same states bit for bit.
    struct Snapshot {
        long long step = 0;              ///< Steps taken (time = step × dt).
        std::vector<BodyState> bodies;   ///< Per object.
    };

    /// What a caller sets before each step (a take's recorded drags, keyframe goals): called with the object
    /// and the step about to be taken (its start time is step × dt). A rollback steps a span again, so it
    /// may be called for a step more than once, always before that step.
    using StepInputs = std::function<void(SceneSimulation&, std::size_t object, long long step)>;

    /// Steps every object until the simulated time reaches `seconds` (fixed dt; a step is taken when
    /// its end time is <= seconds). Problems reported by any step are appended to `problems`. With body
    /// collisions on, the objects step together and touching ones are pushed apart after each step.
    /// Before it returns, the energy guard has accepted every step taken (Simulator::settle): a span it
    /// rolled back was stepped again at finer substeps, so the time it reaches is on one continuous
    /// trajectory, whatever is shown or written there.
    void advanceTo(double seconds, std::vector<std::string>* problems = nullptr, const StepInputs& inputs = {});
    /// Steps until `seconds` lies within the last step taken, so nodesAt() can give the state at exactly
    /// that time (a frame of a clip whose rate does not divide the step rate).
    void advanceToSample(double seconds, std::vector<std::string>* problems = nullptr, const StepInputs& inputs = {});
    /// Object i's lattice nodes at scene time `seconds`, within the last step taken (advanceToSample):
    /// linear between the states at the step's two ends, the state itself at its end. The trajectory
    /// between steps is what the integrator leaves undefined; linear is exact for uniform motion and off
    /// by at most dt²/8 × the acceleration, where snapping to a step is off by up to dt × the speed.
    std::vector<Vec3> nodesAt(std::size_t i, double seconds) const;
    /// The first step refused since creation or reset() (it needed more than maxSubsteps substeps, so
    /// the body stood still), as "object 'x' at t=… s: …"; empty when none. A bake fails on it: a frozen
    /// cache is no answer.
    const std::string& refusal() const { return m_refusal; }
    /// Simulated time, seconds.
    double time() const;
    /// Steps taken so far (every object takes the same steps).
    long long stepCount() const;

    /// Drag springs applied to object i on top of its drivers from the next step on (the editor's
    /// mouse, a device); an empty list releases them. Targets are in the world as the body is shown (on a
    /// base animation they are carried into the body's deviation frame each step).
    void setInteractiveDrags(std::size_t i, std::vector<DragSpring> drags);
    /// The interactive drags of object i.
    const std::vector<DragSpring>& interactiveDrags(std::size_t i) const { return m_objects[i].interactive; }
    /// Every force acting on object i during a step that starts at `seconds`: world, drivers, interactive.
    ExternalForces forcesAt(std::size_t i, double seconds) const;

    /// The current runtime state.
    Snapshot saveSnapshot() const;
    /// Restores a snapshot taken from this scene (same objects and node counts); wakes every body.
    void restoreSnapshot(const Snapshot& snapshot);
    /// Back to the rest state at time 0, interactive drags released.
    void reset();
    /// Number of objects.
    std::size_t objectCount() const { return m_objects.size(); }
    /// Object i's name, mesh, lattice and simulator.
    const SceneObject& object(std::size_t i) const { return *m_objects[i].source; }
    const Simulator& simulator(std::size_t i) const { return m_objects[i].simulator; }
    /// Deformed positions and (optional) normals of object i, in its mesh order (on a base animation: the
    /// base mesh at the current time plus the body's deviation, core/animation/base_motion.h).
    void evaluate(std::size_t i, std::span<Vec3f> positions, std::span<Vec3f> normals, int threads = 0) const;
    /// The same for given node positions of object i at scene time `seconds` (a clip's frame).
    void evaluateNodes(std::size_t i, std::span<const Vec3> nodes, double seconds, std::span<Vec3f> positions,
                       std::span<Vec3f> normals, int threads = 0) const;
    /// Object i's lattice as it is seen at scene time `seconds` for node positions `nodes`: the nodes
    /// themselves, or on a base animation its goal plus the turned deviation (core/animation/base_motion.h).
    std::vector<Vec3> shownNodes(std::size_t i, std::span<const Vec3> nodes, double seconds) const;
    /// Object i follows a base animation: its mesh moves even where its nodes stand still.
    bool followsBaseAnimation(std::size_t i) const { return m_objects[i].motion != nullptr; }
    /// Total vertex count over all objects (the order of a concatenated cache).
    std::size_t totalVertexCount() const;
    /// Object i's binding (mesh vertices on its lattice); shared with the simulation it was kept from.
    const Binding& binding(std::size_t i) const { return m_objects[i].geometry->binding; }
    /// What the body contacts did in the last step (zero when off or apart).
    const BodyContactPass& lastBodyContacts() const { return m_lastBodyContacts; }

private:
    /// What an object's mesh and lattice make, whatever its material and world; kept across edits
    /// (create's `previous`). Filled while a simulation is created, read-only after.
    struct Geometry {
        Binding binding;
        MeshLatticeCache derived;                        ///< Contact samples, volume occupancy.
        std::shared_ptr<const MeshSurface> restSurface;  ///< Its rest mesh, for body contacts (when on).
        std::shared_ptr<const GoalFit> goalFit;          ///< On a base animation: the lattice's fit of the mesh.
    };
    struct Runtime {
        const SceneObject* source = nullptr;
        std::shared_ptr<Geometry> geometry;
        Simulator simulator;
        std::vector<DragSpring> interactive;
        std::shared_ptr<BaseMotion> motion;  ///< On a base animation: its goals and the output's base.
        ExternalForces lastForces;             ///< Of the step just taken (what the guard settles with).
        std::vector<Vec3> previous;            ///< Node positions before the step just taken.
        long long previousStep = -1;           ///< Step count `previous` was taken at; -1: none.
        std::vector<DriverGrip> grips;         ///< Where each of the object's drivers holds its lattice.
    };

    /// Takes one step of object i (inputs first), appending problems; returns its report.
    StepReport stepObject(std::size_t i, std::vector<std::string>* problems, const StepInputs& inputs);
    /// Runs object i's pending energy check; false when it rolled back.
    bool settleObject(std::size_t i, std::vector<std::string>* problems);
    /// Appends a step's problem, naming the object and time, and keeps the first refusal.
    void record(std::size_t i, const StepReport& report, std::vector<std::string>* problems);

    /// Pushes touching objects apart after a step that started at `stepStart` seconds.
    void resolveBodyContacts(double stepStart);

    std::shared_ptr<const Scene> m_scene;
    std::vector<Runtime> m_objects;
    std::string m_refusal;
    BodyContactPass m_lastBodyContacts;
};

}  // namespace softtouch
