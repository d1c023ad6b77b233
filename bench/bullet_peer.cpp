#include "bench/bullet_peer.h"

#ifdef SOFTTOUCH_HAVE_BULLET

#include "analysis/timer.h"

// Bullet comes in as a system include (see bench/CMakeLists.txt), so its own warnings stay out of
// the strict build.
#include <BulletSoftBody/btDefaultSoftBodySolver.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace softtouch::bench {
namespace {

/// CreateFromTriMesh allocates a vertices² table of bools indexed by an int: past this many vertices
/// the index overflows.
constexpr std::size_t kMaxTriMeshVertices = 46340;

/// Settling (settleBullet()): windows of this many steps (half a second) ...
constexpr int kSettleWindow = 120;
/// ... until one in which the held surface moved less than this fraction of its displacement (its
/// range over the window, and its mean against the window before: a ringing body passes neither) ...
constexpr double kSettleTolerance = 1e-4;
/// ... or this many steps (50 simulated seconds).
constexpr int kMaxSettleSteps = 12000;
/// kDP while settling. The equilibrium of a position solver does not depend on kDP (at rest Δx = 0
/// whatever scales it into a velocity), but how soon it is reached does: the run's 0.0037 leaves the
/// membrane ringing, 0.1 and above make it creep (the last 1% takes thousands of steps). 0.01 settled
/// fastest at 24,928 triangles.
constexpr double kSettleDamping = 0.01;

/// A soft-rigid world holding one soft body, torn down in the order Bullet needs (body out of the
/// world before either is deleted, the world before what it points to).
class BulletWorld {
public:
    BulletWorld()
        : m_configuration(std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>()),
          m_dispatcher(std::make_unique<btCollisionDispatcher>(m_configuration.get())),
          m_broadphase(std::make_unique<btDbvtBroadphase>()),
          m_constraintSolver(std::make_unique<btSequentialImpulseConstraintSolver>()),
          m_softBodySolver(std::make_unique<btDefaultSoftBodySolver>()),
          m_world(std::make_unique<btSoftRigidDynamicsWorld>(m_dispatcher.get(), m_broadphase.get(),
                                                              m_constraintSolver.get(), m_configuration.get(),
                                                              m_softBodySolver.get())) {
        // The scenario has no gravity. Soft bodies read theirs from the world info, not from the
        // world, and the world info starts at (0, -10, 0): both must be cleared.
        m_world->setGravity(btVector3(0, 0, 0));
        m_world->getWorldInfo().m_gravity.setValue(0, 0, 0);
    }
    ~BulletWorld() {
        if (m_body)
            m_world->removeSoftBody(m_body.get());
    }
    BulletWorld(const BulletWorld&) = delete;
    BulletWorld& operator=(const BulletWorld&) = delete;

    btSoftRigidDynamicsWorld& world() { return *m_world; }
    btSoftBodyWorldInfo& worldInfo() { return m_world->getWorldInfo(); }
    /// Takes ownership of `body` and adds it to the world.
    btSoftBody& adopt(btSoftBody* body) {
        m_body.reset(body);
        m_world->addSoftBody(body);
        return *body;
    }

private:
    std::unique_ptr<btSoftBodyRigidBodyCollisionConfiguration> m_configuration;
    std::unique_ptr<btCollisionDispatcher> m_dispatcher;
    std::unique_ptr<btDbvtBroadphase> m_broadphase;
    std::unique_ptr<btSequentialImpulseConstraintSolver> m_constraintSolver;
    std::unique_ptr<btDefaultSoftBodySolver> m_softBodySolver;
    std::unique_ptr<btSoftRigidDynamicsWorld> m_world;
    std::unique_ptr<btSoftBody> m_body;  // destroyed first, after ~BulletWorld took it out of the world
};

/// Bullet's per-iteration link stiffness kLST for a spring of `stiffnessNPerM` whose two ends have
/// inverse masses summing to `inverseMass` (1/kg), at step `dt`, solved by `iterations` iterations.
///
/// kLST is not in N/m: a btSoftBody link is a position-based distance constraint, and kLST in [0, 1]
/// is the fraction of its length error removed per solver iteration (PSolve_Links moves the ends by
/// kLST·C in proportion to their inverse masses). We use the XPBD equivalence (Macklin et al. 2016):
/// a spring k is the compliance α = 1/k, and one XPBD projection of a lone constraint removes the fraction
///     f = w / (w + α/dt²) = a / (1 + a),   a = k·w·dt².
/// Held still, that fraction makes the lone spring's equilibrium exactly F/k. n iterations of kLST
/// remove 1 − (1 − kLST)ⁿ; matching f gives
///     kLST = 1 − (1 + a)^(−1/n),
/// so a spring stays the same spring at any iteration count. (With one kLST for every count, as Bullet
/// users usually do, each extra iteration stiffens the body, and as iterations grow it tends to
/// inextensible links, which on a closed convex mesh held at 5% of its vertices barely moves: no count
/// would converge.) The same 80 N/m is a soft spring on the heavy nodes of a coarse mesh (one-iteration
/// kLST ≈ 0.23 at 208 triangles, 1 kg, 240 Hz) and nearly rigid on the light nodes of a fine one
/// (≈ 0.97 at 24,928 triangles), just as it is for the mass-spring contenders. The price of a position
/// solver: once a ≫ 1 a link is nearly fully projected and a stiffer spring barely changes it (in the
/// limit of many iterations the link behaves as a spring of stiffness ∝ ln(1 + a), not a), so at 240 Hz
/// Bullet cannot hold the drag of the finest meshes much closer than 18% of the diagonal and
/// its calibration saturates there (equal_response.h).
btScalar linearStiffness(double stiffnessNPerM, double inverseMass, double dt, int iterations) {
    const double a = stiffnessNPerM * inverseMass * dt * dt;
    return btScalar(std::clamp(-std::expm1(-std::log1p(a) / iterations), 0.0, 1.0));
}

/// Bullet's damping kDP for the scenario's per-spring damping `dampingNsPerM` on a body of
/// `totalMass` kg.
///
/// kDP is not a spring damper either: after the position solve Bullet sets v = (1 − kDP)·Δx/dt on
/// every node, a drag on absolute velocity ("ether" damping) that also resists the user's pull, which
/// the scenario's dampers (on relative velocity along each spring) never do. We keep it as weak as
/// the scenario allows: the per-step decay that the scenario's damping coefficient would give the
/// whole body, 1 − exp(−c·dt/M) (0.0037 at 0.9 N·s/m, 1 kg, 240 Hz). It does not depend on the mesh
/// resolution, and the position solve dissipates on its own (it discards the velocity a constraint
/// correction would need to overshoot). A larger kDP (0.01–0.1 is common in Bullet's demos) would act
/// as an ether drag of kDP·M/dt = 2.4–24 N·s/m on a 1 kg body, against a drag spring of 0.5 N·s/m.
btScalar dampingCoefficient(double dampingNsPerM, double totalMass, double dt) {
    return btScalar(std::clamp(1.0 - std::exp(-dampingNsPerM * dt / totalMass), 0.0, 1.0));
}

/// The scenario's body as a btSoftBody in its own world, with the user's drag.
///
/// The drag is the other contenders' drag spring on the same held surface (surfaceGrip()): before each step
/// the force F = Ks·(target − x̄) − Kd·v̄ on the held surface's mean x̄ is shared among its nodes by their
/// weights (btSoftBody::addForce), as the mass-springs' drag spring does. Bullet integrates node forces
/// explicitly, which on one light node would be unstable (h·Kd/m is 26 on a node of 24,928 triangles): the
/// held surface carries about 3% of the mass at every size, so h·Kd/m is 0.06 and h²·Ks/m 0.03 for its mean.
class BulletBody {
public:
    /// False when CreateFromTriMesh cannot take the mesh.
    bool build(const InteractionScenario& s, const BulletSetting& setting) {
        const Mesh& mesh = s.mesh;
        m_vertexCount = mesh.positions.size();
        if (mesh.triangles.empty() || m_vertexCount > kMaxTriMeshVertices)
            return false;
        // Nodes per vertex, links along triangle edges: the topology of the global mass-spring contender.
        std::vector<btScalar> vertices;
        vertices.reserve(3 * m_vertexCount);
        for (const Vec3f& p : mesh.positions) {
            vertices.push_back(btScalar(p.x()));
            vertices.push_back(btScalar(p.y()));
            vertices.push_back(btScalar(p.z()));
        }
        std::vector<int> triangles;
        triangles.reserve(3 * mesh.triangles.size());
        for (const auto& t : mesh.triangles) {
            for (std::uint32_t index : t)
                triangles.push_back(int(index));
        }
        // randomizeConstraints = true is Bullet's default: the links are shuffled once, so a
        // Gauss-Seidel sweep has no directional bias from the mesh's vertex order.
        btSoftBody& body = m_world.adopt(btSoftBodyHelpers::CreateFromTriMesh(
            m_world.worldInfo(), vertices.data(), triangles.data(), int(mesh.triangles.size()), true));
        m_body = &body;
        // CreateFromTriMesh makes as many nodes as the largest index used: an unreferenced last vertex
        // would be missing.
        if (std::size_t(body.m_nodes.size()) != m_vertexCount)
            return false;
        // No generateBendingConstraints(): bending links would join vertices two edges apart, which the
        // mass-spring contenders do not have. The closed surface holds its shape through its edges only,
        // exactly as theirs does, and every contender solves the same number of springs.

        const double nodeMass = s.totalMass / double(m_vertexCount);
        body.m_materials[0]->m_kLST =
            linearStiffness(setting.stiffnessScale * s.stiffness, 2.0 / nodeMass, s.dt, setting.iterations);
        body.m_cfg.kDP = dampingCoefficient(s.damping, s.totalMass, s.dt);
        body.m_cfg.piterations = setting.iterations;
        // setTotalMass spreads the mass evenly over the nodes (the mass-spring contenders' per-vertex
        // mass); zero mass then makes the held vertices static.
        body.setTotalMass(btScalar(s.totalMass), false);
        for (std::uint32_t a : s.anchors)
            body.setMass(int(a), 0);
        // Self-collision is off by default (fCollision::Default = rigid-soft only) and there are no rigid
        // bodies: no contender pays for collisions.

        // Rest lengths now, at rest (Bullet would take them at the first step).
        body.updateConstants();
        body.m_bUpdateRtCst = false;
        m_grip = surfaceGrip(s);
        for (const NodeWeight& w : m_grip)
            m_rest += w.weight * mesh.positions[w.node].cast<double>();
        m_dragStiffness = s.dragStiffness;
        m_dragDamping = s.dragDamping;
        return true;
    }

    /// One step of s.dt with the drag target at `target` (still, as the other contenders' drag target is
    /// held still within a step). maxSubSteps = 0: exactly dt, no interpolation, a fixed step like ours.
    void step(const Vec3& target, double dt) {
        const Vec3 force = m_dragStiffness * (target - held(&btSoftBody::Node::m_x)) - m_dragDamping * held(&btSoftBody::Node::m_v);
        for (const NodeWeight& w : m_grip) {
            const Vec3 f = w.weight * force;
            m_body->addForce(btVector3(btScalar(f.x()), btScalar(f.y()), btScalar(f.z())), int(w.node));
        }
        m_world.world().stepSimulation(btScalar(dt), 0);
    }
    void meshPositions(std::span<Vec3f> out) const {
        for (std::size_t n = 0; n < m_vertexCount; ++n) {
            const btVector3& p = m_body->m_nodes[int(n)].m_x;
            out[n] = Vec3f(float(p.x()), float(p.y()), float(p.z()));
        }
    }
    /// How far the held surface's mean is from its rest position.
    double displacement() const { return (held(&btSoftBody::Node::m_x) - m_rest).norm(); }
    const Vec3& gripRest() const { return m_rest; }
    btSoftBody& body() { return *m_body; }

private:
    /// The held surface's weighted mean of a node quantity (position m_x or velocity m_v).
    Vec3 held(btVector3 btSoftBody::Node::*quantity) const {
        Vec3 mean = Vec3::Zero();
        for (const NodeWeight& w : m_grip) {
            const btVector3& v = m_body->m_nodes[int(w.node)].*quantity;
            mean += w.weight * Vec3(v.x(), v.y(), v.z());
        }
        return mean;
    }

    BulletWorld m_world;
    btSoftBody* m_body = nullptr;
    std::size_t m_vertexCount = 0;
    std::vector<NodeWeight> m_grip;  ///< The held surface (surfaceGrip()).
    Vec3 m_rest = Vec3::Zero();      ///< Its mean at rest.
    double m_dragStiffness = 0.0;
    double m_dragDamping = 0.0;
};

}  // namespace

bool bulletAvailable() { return true; }

std::optional<ContenderRun> runBullet(const InteractionScenario& s, const BulletSetting& setting) {
    BulletBody bullet;
    if (!bullet.build(s, setting))
        return std::nullopt;
    const Vec3 restPoint = bullet.gripRest();
    const std::size_t vertices = s.mesh.positions.size();
    ContenderRun run;
    run.frames.resize(std::size_t(s.frames()) * vertices);  // allocated before the clock starts
    const int perFrame = s.stepsPerFrame();
    run.totalSteps = s.steps();

    // Timed: the stepping and the position reads the screen needs, as for every contender. Not timed:
    // creating the world and the soft body (CreateFromTriMesh fills a vertices² table, a one-off cost
    // that says nothing about interaction).
    analysis::Stopwatch watch;
    for (; run.steps < run.totalSteps; ++run.steps) {
        bullet.step(restPoint + s.dragOffsetAt(run.steps * s.dt), s.dt);
        if ((run.steps + 1) % perFrame == 0)
            bullet.meshPositions(std::span<Vec3f>(run.frames.data() + std::size_t(run.framesRun++) * vertices, vertices));
    }
    run.seconds = watch.seconds();
    run.finite = allFinite(run.frames);
    return run;
}

std::optional<StaticResponse> settleBullet(const InteractionScenario& s, const BulletSetting& setting) {
    BulletBody bullet;
    if (!bullet.build(s, setting))
        return std::nullopt;
    bullet.body().m_cfg.kDP = btScalar(kSettleDamping);
    const Vec3 target = bullet.gripRest() + s.dragOffset;
    StaticResponse result;
    double low = 1e300, high = 0.0, sum = 0.0, previousMean = -1.0;
    while (result.steps < kMaxSettleSteps) {
        bullet.step(target, s.dt);
        ++result.steps;
        const double d = bullet.displacement();
        low = std::min(low, d);
        high = std::max(high, d);
        sum += d;
        if (result.steps % kSettleWindow != 0)
            continue;
        const double mean = sum / kSettleWindow;
        result.displacement = mean;
        if (!std::isfinite(mean))
            break;
        if (high - low <= kSettleTolerance * mean && std::abs(mean - previousMean) <= kSettleTolerance * mean) {
            result.converged = true;
            break;
        }
        previousMean = mean;
        low = 1e300;
        high = sum = 0.0;
    }
    return result;
}

}  // namespace softtouch::bench

#else  // !SOFTTOUCH_HAVE_BULLET

namespace softtouch::bench {

bool bulletAvailable() { return false; }

std::optional<ContenderRun> runBullet(const InteractionScenario& /*scenario*/, const BulletSetting& /*setting*/) {
    return std::nullopt;
}

std::optional<StaticResponse> settleBullet(const InteractionScenario& /*scenario*/, const BulletSetting& /*setting*/) {
    return std::nullopt;
}

}  // namespace softtouch::bench

#endif
